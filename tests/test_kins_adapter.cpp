// pkm::linuxcnc::KinsAdapter, the pkmkins module without LinuxCNC: units at LinuxCNC's side,
// inverse with the failing joint, forward from the previous pose, the counters, the messages.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pkm/linuxcnc/kins_adapter.hpp"
#include "test_support.hpp"

namespace pkm::linuxcnc {
namespace {

// LinuxCNC INI text as the file x.ini.
IniFile ini(std::string_view text) {
  return IniFile::parse(text, "x.ini");
}

KinsAdapter example(const std::string& file,
                    std::optional<machine::LengthUnit> unit = std::nullopt) {
  return KinsAdapter(test::load_example(file), unit);
}

TEST(KinsAdapter, WorldUnitsAreInchesForAnInchMachine) {
  const KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  EXPECT_EQ(kins.world_unit(), machine::LengthUnit::inch);
  const geometry::Pose pose = kins.to_pose({1.0, -2.0, 20.0, 90.0, 0.0, -45.0});
  EXPECT_DOUBLE_EQ(pose.position_mm.x(), 25.4);
  EXPECT_DOUBLE_EQ(pose.position_mm.y(), -50.8);
  EXPECT_DOUBLE_EQ(pose.position_mm.z(), 508.0);
  EXPECT_DOUBLE_EQ(pose.orientation_rad.x(), M_PI / 2);
  EXPECT_DOUBLE_EQ(pose.orientation_rad.z(), -M_PI / 4);
  WorldPose back{0, 0, 0, 0, 0, 0, 7.0, 8.0, 9.0};
  kins.to_world(pose, back);
  EXPECT_DOUBLE_EQ(back.x, 1.0);
  EXPECT_DOUBLE_EQ(back.z, 20.0);
  EXPECT_DOUBLE_EQ(back.a, 90.0);
  EXPECT_DOUBLE_EQ(back.u, 7.0);  // u v w are LinuxCNC's, left alone
}

TEST(KinsAdapter, UnitsParameterOverridesTheMachineFile) {
  const KinsAdapter kins = example("linuxcnc-hexapod-sim.toml", machine::LengthUnit::mm);
  WorldPose home;
  double joints[kinematics::kMaxJoints];
  kins.home(home, joints);
  EXPECT_NEAR(home.z, 508.0, 1e-12);                     // the file's home z 20 in, in mm
  EXPECT_NEAR(joints[0], 29.7466 * 25.4, 0.001 * 25.4);  // hexapod.ini's HOME of every leg
}

TEST(KinsAdapter, HomeOfTheHexapodSimIsTheSampleConfigsHome) {
  const KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  WorldPose home;
  double joints[kinematics::kMaxJoints];
  kins.home(home, joints);
  EXPECT_DOUBLE_EQ(home.z, 20.0);
  // Leg 0 from base (-22.95, 13.25, 0) to platform joint (-1, 11.5, 0) + (0, 0, 20); leg 3 from
  // (0, -26.5, 0) to (9.459, -6.616, 20).
  EXPECT_NEAR(joints[0], std::sqrt(21.95 * 21.95 + 1.75 * 1.75 + 400.0), 1e-12);
  EXPECT_NEAR(joints[3], std::sqrt(9.459 * 9.459 + 19.884 * 19.884 + 400.0), 1e-12);
  // hexapod.ini's HOME, 29.7466 for every leg, is that to its 4 decimals.
  for (int n = 0; n < 6; ++n) EXPECT_NEAR(joints[n], 29.7466, 3e-4) << "leg " << n;
}

TEST(KinsAdapter, InverseOfTheLinearDeltaHome) {
  // Every carriage at ldelta.ini's HOME 270 mm: z = 270 - sqrt(269^2 - 130.25^2).
  KinsAdapter kins = example("linuxcnc-ldelta.toml");
  const double z = 270.0 - std::sqrt(269.0 * 269.0 - 130.25 * 130.25);
  double joints[3] = {0, 0, 0};
  ASSERT_TRUE(kins.inverse({0.0, 0.0, z}, joints).ok());
  for (double joint : joints) EXPECT_NEAR(joint, 270.0, 1e-9);
  EXPECT_EQ(kins.counters().ik_failures, 0u);
  EXPECT_EQ(kins.counters().ik_failed_joint, -1);
}

TEST(KinsAdapter, RefusedInverseNamesTheJointAndKeepsTheJoints) {
  KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  double joints[6] = {1, 2, 3, 4, 5, 6};
  const kinematics::Status status =
      kins.inverse({0.0, 0.0, 40.0}, joints);  // legs past their 36 in
  ASSERT_EQ(status.code, kinematics::StatusCode::joint_limit);
  EXPECT_EQ(joints[0], 1.0);
  EXPECT_EQ(joints[5], 6.0);
  EXPECT_EQ(kins.counters().ik_failures, 1u);
  EXPECT_EQ(kins.counters().ik_failed_joint, status.joint);
  EXPECT_EQ(kins.counters().ik_status, static_cast<int>(kinematics::StatusCode::joint_limit));
  char message[512];
  const std::string text = kins.failure_message(message, sizeof message);
  const std::string joint = std::to_string(status.joint);
  EXPECT_NE(text.find("pkmkins: inverse kinematics refused x 0.0000 y 0.0000 z 40.0000 in a "
                      "0.000 b 0.000 c 0.000 deg: joint " +
                      joint + " 'leg" + joint + "' = "),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(" in passes its max 36.0000 in"), std::string::npos) << text;
  // A success clears the failed joint, not the count.
  ASSERT_TRUE(kins.inverse({0.0, 0.0, 20.0}, joints).ok());
  EXPECT_EQ(kins.counters().ik_failed_joint, -1);
  EXPECT_EQ(kins.counters().ik_failures, 1u);
}

TEST(KinsAdapter, RefusedInverseOutsideTheEnvelopeNamesTheAxis) {
  KinsAdapter kins = example("linuxcnc-ldelta.toml");
  double joints[3];
  ASSERT_EQ(kins.inverse({0.0, 0.0, 50.0}, joints).code, kinematics::StatusCode::outside_envelope);
  char message[512];
  EXPECT_STREQ(kins.failure_message(message, sizeof message),
               "pkmkins: inverse kinematics refused x 0.000 y 0.000 z 50.000 mm a 0.000 b 0.000 "
               "c 0.000 deg: z passes the work envelope's max 35.0000 mm");
}

TEST(KinsAdapter, FailureMessageFitsAnySmallBuffer) {
  KinsAdapter kins = example("linuxcnc-ldelta.toml");
  double joints[3];
  kins.inverse({0.0, 0.0, 50.0}, joints);
  char message[16];
  EXPECT_STREQ(kins.failure_message(message, sizeof message), "pkmkins: invers");
}

TEST(KinsAdapter, FailuresAreReportedOnceThenEveryThousandth) {
  KinsAdapter kins = example("linuxcnc-ldelta.toml");
  double joints[3];
  int reported = 0;
  for (int k = 0; k < 2500; ++k) {
    kins.inverse({0.0, 0.0, 50.0}, joints);
    reported += kins.should_report_failure() ? 1 : 0;
  }
  EXPECT_EQ(reported, 3);  // the 1st, 1000th and 2000th
  char message[512];
  EXPECT_NE(std::string(kins.failure_message(message, sizeof message)).find("(2500 in a row)"),
            std::string::npos);
  ASSERT_TRUE(kins.inverse({0.0, 0.0, 30.0}, joints).ok());
  kins.inverse({0.0, 0.0, 50.0}, joints);
  EXPECT_TRUE(kins.should_report_failure());  // a new run of failures is reported again
}

TEST(KinsAdapter, ForwardFromThePreviousPoseReturnsThePose) {
  KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  const WorldPose target{1.5, -2.0, 21.0, 3.0, -4.0, 10.0};
  double joints[6];
  ASSERT_TRUE(kins.inverse(target, joints).ok());
  WorldPose world{1.5001, -2.0, 21.0, 3.0, -4.0, 10.0, 0.0, 0.0, 0.0};  // a servo step away
  ASSERT_TRUE(kins.forward(joints, world).ok());
  EXPECT_NEAR(world.x, 1.5, 1e-9);
  EXPECT_NEAR(world.y, -2.0, 1e-9);
  EXPECT_NEAR(world.z, 21.0, 1e-9);
  EXPECT_NEAR(world.a, 3.0, 1e-9);
  EXPECT_NEAR(world.b, -4.0, 1e-9);
  EXPECT_NEAR(world.c, 10.0, 1e-9);
  EXPECT_EQ(kins.counters().fk_status, 0);
  EXPECT_GT(kins.counters().fk_iterations, 0);  // Newton: a hexapod has no closed-form FK
  EXPECT_LT(kins.counters().fk_iterations, 10);
}

TEST(KinsAdapter, ForwardWithoutAFiniteSeedStartsFromTheLastPose) {
  KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  double joints[6];
  ASSERT_TRUE(kins.inverse({0.5, 0.5, 19.0, 2.0, 0.0, 0.0}, joints).ok());
  WorldPose world{NAN, 0.0, 0.0, 0.0, 0.0, 0.0};
  ASSERT_TRUE(kins.forward(joints, world).ok());
  EXPECT_NEAR(world.x, 0.5, 1e-9);
  EXPECT_NEAR(world.a, 2.0, 1e-9);
}

TEST(KinsAdapter, ForwardFromAFarSeedFallsBackToHome) {
  // LinuxCNC seeds with its [TRAJ] HOME, all zeros when the INI has none: the platform in the
  // base's plane, where the hexapod is singular.
  KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  double joints[6];
  ASSERT_TRUE(kins.inverse({0.0, 1.0, 22.0}, joints).ok());
  WorldPose world{};
  ASSERT_TRUE(kins.forward(joints, world).ok());
  EXPECT_NEAR(world.y, 1.0, 1e-9);
  EXPECT_NEAR(world.z, 22.0, 1e-9);
}

TEST(KinsAdapter, RefusedForwardLeavesThePoseAndCounts) {
  KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  const double joints[6] = {50, 50, 50, 50, 50, 50};  // past every leg's 36 in
  WorldPose world{1.0, 2.0, 20.0};
  EXPECT_FALSE(kins.forward(joints, world).ok());
  EXPECT_EQ(world.x, 1.0);
  EXPECT_EQ(kins.counters().fk_failures, 1u);
  EXPECT_EQ(kins.counters().fk_status, static_cast<int>(kinematics::StatusCode::joint_limit));
}

TEST(KinsAdapter, ForwardLeavesUncontrolledCoordinatesAsSeeded) {
  KinsAdapter kins = example("linuxcnc-ldelta.toml");
  const double joints[3] = {270.0, 270.0, 270.0};
  WorldPose world{0.0, 0.0, 30.0, 12.0, 0.0, 0.0};  // a delta has no A: LinuxCNC's stays
  ASSERT_TRUE(kins.forward(joints, world).ok());
  EXPECT_NEAR(world.z, 270.0 - std::sqrt(269.0 * 269.0 - 130.25 * 130.25), 1e-9);
  EXPECT_EQ(world.a, 12.0);
  EXPECT_EQ(kins.counters().fk_iterations, 0);  // closed form
}

TEST(KinsAdapter, RotaryJointsAreDegreesAtLinuxCncsSide) {
  const KinsAdapter kins = example("linuxcnc-xyzac-trt.toml");
  for (int n = 0; n < kins.joint_count(); ++n) {
    if (kins.machine().joints()[static_cast<std::size_t>(n)].kind != kinematics::JointKind::rotary)
      continue;
    EXPECT_DOUBLE_EQ(kins.joint_to_world(n, M_PI / 2), 90.0);
    EXPECT_DOUBLE_EQ(kins.joint_from_world(n, 180.0), M_PI);
    return;
  }
  FAIL() << "no rotary joint";
}

TEST(KinsAdapter, WorldUnitNames) {
  EXPECT_EQ(parse_world_unit("mm"), machine::LengthUnit::mm);
  EXPECT_EQ(parse_world_unit("inch"), machine::LengthUnit::inch);
  EXPECT_EQ(parse_world_unit("in"), machine::LengthUnit::inch);
  EXPECT_EQ(parse_world_unit("cm"), std::nullopt);
}

TEST(KinsAdapter, MachineFileIsFoundBesideTheIni) {
  EXPECT_EQ(resolve_machine_file("/abs/m.toml", "/cfg/x.ini", "/cwd"), "/abs/m.toml");
  EXPECT_EQ(resolve_machine_file("m.toml", "/cfg/x.ini", "/cwd"), "/cfg/m.toml");
  EXPECT_EQ(resolve_machine_file("sub/m.toml", "cfg/x.ini", "/cwd"), "/cwd/cfg/sub/m.toml");
  EXPECT_EQ(resolve_machine_file("m.toml", "x.ini", "/cwd"), "/cwd/m.toml");
  EXPECT_EQ(resolve_machine_file("m.toml", nullptr, "/cwd"), "/cwd/m.toml");
}

TEST(KinsAdapter, IniThatAgreesSaysNothing) {
  const KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  EXPECT_EQ(ini_mismatch(kins, ini("[KINS]\nKINEMATICS = pkmkins machine=m.toml\nJOINTS = 6\n"
                                   "[TRAJ]\nLINEAR_UNITS = inch\n[JOINT_0]\nTYPE = LINEAR\n")),
            "");
  EXPECT_EQ(ini_mismatch(kins, ini("[EMC]\nVERSION = 1.1\n")), "");  // nothing said, nothing wrong
}

TEST(KinsAdapter, IniWithOtherJointsOrUnitsIsNamed) {
  const KinsAdapter kins = example("linuxcnc-hexapod-sim.toml");
  EXPECT_EQ(ini_mismatch(kins, ini("[KINS]\n  JOINTS = 5  \n")),
            "x.ini:2: [KINS] JOINTS = 5 but the machine file has 6 joints: set JOINTS = 6");
  EXPECT_EQ(ini_mismatch(kins, ini("[TRAJ]\nLINEAR_UNITS = mm\n[KINS]\nJOINTS = 6\n")),
            "x.ini:2: [TRAJ] LINEAR_UNITS = mm but pkmkins works in inch: add units=mm to [KINS] "
            "KINEMATICS (the default is the machine file's units)");
  // JOINTS of another section does not count; of a repeated key, the first does (LinuxCNC's
  // IniFile::Find takes the first).
  EXPECT_EQ(ini_mismatch(kins, ini("[JOINT_0]\nJOINTS = 2\n[KINS]\nJOINTS = 6\nJOINTS = 4\n")), "");
  EXPECT_EQ(ini_mismatch(kins, ini("[JOINT_0]\nJOINTS = 2\n[KINS]\nJOINTS = 4\nJOINTS = 6\n")),
            "x.ini:4: [KINS] JOINTS = 4 but the machine file has 6 joints: set JOINTS = 6");
}

TEST(KinsAdapter, BrokenMachineFileKeepsItsLocatedError) {
  try {
    load_kins(std::string(PKM_SOURCE_DIR) + "/tests/data/bad-strut.toml", std::nullopt);
    FAIL() << "loaded a broken machine file";
  } catch (const machine::MachineFileError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("bad-strut.toml:14:kinematics.rails[1].strut: must be a positive length"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace pkm::linuxcnc
