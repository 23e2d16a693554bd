// pkm import linuxcnc: LinuxCNC's own sample configurations (skipped, with the reason, where
// LinuxCNC's examples are not installed) and small hand-written ones in tests/data/linuxcnc. The
// joints of every imported machine are checked against the kinematics module's equations as
// LinuxCNC's sources state them, written out here independently of pkmkit's models.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/kinematics/registry.hpp"
#include "pkm/linuxcnc/config_import.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::linuxcnc {
namespace {

namespace fs = std::filesystem;

const fs::path kSamples = PKM_LINUXCNC_SAMPLES;
const fs::path kData = fs::path(PKM_SOURCE_DIR) / "tests/data/linuxcnc";
const fs::path kMachines = fs::path(PKM_SOURCE_DIR) / "examples/machines";

#define PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES()                                                 \
  do {                                                                                      \
    if (!fs::is_directory(kSamples / "sim/axis")) {                                         \
      GTEST_SKIP() << "LinuxCNC's sample configurations are not at " << kSamples.string()   \
                   << " (Debian: linuxcnc-uspace's examples; scripts/setup installs them)"; \
    }                                                                                       \
  } while (false)

// LinuxCNC's hallib for its sample configurations; the stand-in of tests/data for ours.
ImportedConfig read_config(const fs::path& ini) {
  ImportOptions options;
  if (ini.string().rfind(kData.string(), 0) == 0) options.hallib = kData / "hallib";
  return read_linuxcnc_config(ini, options);
}

machine::Machine import_machine(const fs::path& ini) {
  return machine::parse_machine(machine_file_text(read_config(ini), "imported.toml"),
                                "imported.toml");
}

bool has_note(const ImportedConfig& config, const std::string& part) {
  return std::any_of(config.notes.begin(), config.notes.end(),
                     [&](const std::string& note) { return note.find(part) != std::string::npos; });
}

// genhexkins' strut lengths (its source): the offset t = tool-offset + spindle-offset is added to
// the z of every base joint b and platform joint a; strut = |p + R (a + t z) - (b + t z)| with R
// from roll a, pitch b, yaw c: Rz(c) Ry(b) Rx(a).
double genhexkins_strut(const Eigen::Vector3d& base, const Eigen::Vector3d& platform, double t,
                        const Eigen::Vector3d& p, const Eigen::Vector3d& abc_deg) {
  const Eigen::Vector3d r = abc_deg * std::numbers::pi / 180.0;
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  const Eigen::Vector3d lift(0.0, 0.0, t);
  return (p + rotation * (platform + lift) - (base + lift)).norm();
}

TEST(LinuxcncImport, HexapodSimGivesTheExampleGeometry) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const fs::path ini = kSamples / "sim/axis/vismach/hexapod-sim/hexapod.ini";
  const ImportedConfig config = read_config(ini);
  EXPECT_EQ(config.module, "genhexkins");
  EXPECT_TRUE(config.inch);
  // tool-offset is connected to motion.tooloffset.z: 0 without a tool, and said so.
  EXPECT_TRUE(has_note(config, "genhexkins.tool-offset follows motion.tooloffset.z"));
  const machine::Machine imported = import_machine(ini);
  const machine::Machine example = machine::load_machine(kMachines / "linuxcnc-hexapod-sim.toml");
  const auto& got =
      dynamic_cast<const kinematics::HexapodKinematics&>(imported.kinematics()).geometry();
  const auto& want =
      dynamic_cast<const kinematics::HexapodKinematics&>(example.kinematics()).geometry();
  for (int leg = 0; leg < 6; ++leg) {
    EXPECT_EQ(got.base_mm[leg], want.base_mm[leg]) << "leg " << leg;
    EXPECT_EQ(got.platform_mm[leg], want.platform_mm[leg]) << "leg " << leg;
  }
  EXPECT_EQ(got.tool_length_mm, 0.0);
  EXPECT_EQ(imported.units(), machine::LengthUnit::inch);
  EXPECT_EQ(imported.home().position_mm, Eigen::Vector3d(0.0, 0.0, 20.0 * 25.4));
  // [JOINT_n]: -1000..1000 in, 20 in/s, 200 in/s^2; [TRAJ] 10 in/s and 20 in/s^2 cap the tool.
  EXPECT_DOUBLE_EQ(imported.joints()[3].min, -1000.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.joints()[3].max_velocity, 20.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.joints()[3].max_acceleration, 200.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.cartesian().max_feed_mm_per_min, 600.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.cartesian().max_acceleration_mm_per_s2, 20.0 * 25.4);
}

// The sample's -1000..1000 in on every leg and on X Y Z (and A B C) describe no machine: the
// import says so with the numbers; the legs keep them (there is no other travel to take), the
// work envelope is left out (the reach is what the legs allow).
TEST(LinuxcncImport, HexapodSimPlaceholderLimitsAreWarnedAndNoEnvelopeIsWritten) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const fs::path ini = kSamples / "sim/axis/vismach/hexapod-sim/hexapod.ini";
  const ImportedConfig config = read_config(ini);
  ASSERT_EQ(config.warnings.size(), 2u);
  EXPECT_NE(config.warnings[0].find("[JOINT_0] .. [JOINT_5] MIN_LIMIT/MAX_LIMIT are -1000 .. 1000 "
                                    "in on every joint: placeholders"),
            std::string::npos)
      << config.warnings[0];
  EXPECT_NE(config.warnings[1].find("[AXIS_X] [AXIS_Y] [AXIS_Z] MIN_LIMIT/MAX_LIMIT are -1000 .. "
                                    "1000 in on every axis: placeholders"),
            std::string::npos)
      << config.warnings[1];
  EXPECT_FALSE(config.envelope_min.has_value());
  EXPECT_TRUE(has_note(config, "WARNING: [JOINT_0] .. [JOINT_5]"));
  const std::string text = machine_file_text(config, "imported.toml");
  EXPECT_EQ(text.find("\nmin = ["), std::string::npos) << text;
  EXPECT_NE(text.find("\nmin = -1000.0\n"), std::string::npos) << text;  // the legs, kept
}

// Real travel is no placeholder: LinuxCNC's linear delta (joints 0..375 mm, axes of their own)
// and its rotary delta import without a warning.
TEST(LinuxcncImport, RealLimitsAreNotPlaceholders) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  for (const char* name : {"sim/axis/ldelta.ini", "sim/axis/rdelta.ini"}) {
    const ImportedConfig config = read_config(kSamples / name);
    EXPECT_TRUE(config.warnings.empty()) << name << ": " << config.warnings.front();
    EXPECT_TRUE(config.envelope_min.has_value()) << name;
  }
}

// The hexapod of kinematics.hal at a tilted pose: the imported joints are genhexkins' struts.
TEST(LinuxcncImport, HexapodSimJointsAreGenhexkinsStruts) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const machine::Machine imported =
      import_machine(kSamples / "sim/axis/vismach/hexapod-sim/hexapod.ini");
  const Eigen::Vector3d p(1.5, -2.0, 21.0);  // in
  const Eigen::Vector3d abc(4.0, -3.0, 10.0);
  kinematics::JointVector joints;
  ASSERT_TRUE(imported
                  .inverse(geometry::Pose::from_mm_deg(p.x() * 25.4, p.y() * 25.4, p.z() * 25.4,
                                                       abc.x(), abc.y(), abc.z()),
                           joints)
                  .ok());
  const auto& g =
      dynamic_cast<const kinematics::HexapodKinematics&>(imported.kinematics()).geometry();
  for (int leg = 0; leg < 6; ++leg) {
    const double strut =
        genhexkins_strut(g.base_mm[leg] / 25.4, g.platform_mm[leg] / 25.4, 0.0, p, abc);
    EXPECT_NEAR(joints[leg] / 25.4, strut, 1e-9) << "leg " << leg;
  }
}

// A constant tool-offset (25) and spindle-offset (5, through a signal): genhexkins adds 30 to
// the z of the base joints and of the platform joints; the import's machine gives the same struts
// at every pose, tilted ones included (where the two meanings of the offset differ).
TEST(LinuxcncImport, GenhexkinsToolOffsetGivesGenhexkinsJoints) {
  const fs::path ini = kData / "genhex-tool-offset/hexapod.ini";
  const ImportedConfig config = read_config(ini);
  EXPECT_TRUE(has_note(config, "geometry.tcl is Tcl"));
  const machine::Machine imported = import_machine(ini);
  const auto& g =
      dynamic_cast<const kinematics::HexapodKinematics&>(imported.kinematics()).geometry();
  EXPECT_EQ(g.tool_length_mm, 30.0);
  EXPECT_EQ(g.base_mm[0], Eigen::Vector3d(-410.0, 260.0, 30.0));
  EXPECT_EQ(g.base_mm[3], Eigen::Vector3d(-20.0, -485.0, 40.0));
  EXPECT_EQ(g.platform_mm[2], Eigen::Vector3d(195.0, -65.0, -15.0));
  // genhexkins' own pins, as geometry.tcl sets them.
  const double base[6][3] = {{-410, 260, 0},  {430, 225, 0},  {20, -485, 0},
                             {-20, -485, 10}, {-430, 225, 0}, {410, 260, 0}};
  const double platform[6][3] = {{-40, 200, -15},  {40, 200, -15},    {195, -65, -15},
                                 {155, -135, -15}, {-155, -135, -15}, {-195, -65, -15}};
  for (const auto& [p, abc] :
       {std::pair{Eigen::Vector3d(0, 0, 500), Eigen::Vector3d(0, 0, 0)},
        std::pair{Eigen::Vector3d(30, -20, 520), Eigen::Vector3d(8, 0, 0)},
        std::pair{Eigen::Vector3d(-40, 10, 480), Eigen::Vector3d(-5, 7, 20)}}) {
    kinematics::JointVector joints;
    ASSERT_TRUE(
        imported
            .inverse(geometry::Pose::from_mm_deg(p.x(), p.y(), p.z(), abc.x(), abc.y(), abc.z()),
                     joints)
            .ok());
    for (int leg = 0; leg < 6; ++leg) {
      const double strut = genhexkins_strut(Eigen::Vector3d(base[leg]),
                                            Eigen::Vector3d(platform[leg]), 30.0, p, abc);
      EXPECT_NEAR(joints[leg], strut, 1e-9) << "leg " << leg << " at a " << abc.x();
    }
  }
}

TEST(LinuxcncImport, LdeltaGivesTheExampleRails) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const machine::Machine imported = import_machine(kSamples / "sim/axis/ldelta.ini");
  const machine::Machine example = machine::load_machine(kMachines / "linuxcnc-ldelta.toml");
  const auto& got = dynamic_cast<const kinematics::GlideKinematics&>(imported.kinematics()).rails();
  const auto& want = dynamic_cast<const kinematics::GlideKinematics&>(example.kinematics()).rails();
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_LT((got[i].origin_mm - want[i].origin_mm).norm(), 1e-9) << "rail " << i;
    EXPECT_LT((got[i].direction - want[i].direction).norm(), 1e-9) << "rail " << i;
    EXPECT_LT((got[i].attach_mm - want[i].attach_mm).norm(), 1e-9) << "rail " << i;
    EXPECT_NEAR(got[i].strut_mm, want[i].strut_mm, 1e-9) << "rail " << i;
    EXPECT_EQ(got[i].branch, want[i].branch);
  }
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(imported.joints()[j].min, example.joints()[j].min);
    EXPECT_EQ(imported.joints()[j].max, example.joints()[j].max);
    EXPECT_EQ(imported.joints()[j].max_velocity, example.joints()[j].max_velocity);
  }
  // The fourth joint (A, an extruder) passes through, as lineardeltakins passes it.
  ASSERT_EQ(imported.joints().size(), 4u);
  EXPECT_EQ(imported.kinematics().passthrough_axis(3), 3);
  // Every carriage at its HOME of 270 mm: the example's home.
  EXPECT_LT((imported.home().position_mm - example.home().position_mm).norm(), 1e-9);
  EXPECT_EQ(imported.cartesian().envelope_min[0], -95.0);
  EXPECT_EQ(imported.cartesian().envelope_max[0], 150.0);
}

// lineardeltakins' inverse (its source): towers (0, R), (-R sin 60, -R cos 60),
// (R sin 60, -R cos 60); joint = z + sqrt(L^2 - horizontal distance^2).
TEST(LinuxcncImport, LdeltaJointsAreLineardeltakins) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const machine::Machine imported = import_machine(kSamples / "sim/axis/ldelta.ini");
  const double r = 130.25, l = 269.0, s = std::sqrt(3.0) / 2.0;
  const double towers[3][2] = {{0.0, r}, {-s * r, -0.5 * r}, {s * r, -0.5 * r}};
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(40, -30, 10), Eigen::Vector3d(-60, 20, 0)}) {
    kinematics::JointVector joints;
    ASSERT_TRUE(imported.inverse(geometry::Pose::from_mm_deg(p.x(), p.y(), p.z()), joints).ok());
    for (int j = 0; j < 3; ++j) {
      const double dx = towers[j][0] - p.x(), dy = towers[j][1] - p.y();
      EXPECT_NEAR(joints[j], p.z() + std::sqrt(l * l - dx * dx - dy * dy), 1e-9) << "joint " << j;
    }
  }
}

// rotarydeltakins' pins under rotary_delta's keys (the contract of issue 11); the model itself
// is another branch's, so the loaded machine is checked only where this build has it.
TEST(LinuxcncImport, RdeltaWritesTheRotaryDeltaKeys) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const ImportedConfig config = read_config(kSamples / "sim/axis/rdelta.ini");
  EXPECT_EQ(config.kinematics_section,
            "[kinematics]\ntype = \"rotary_delta\"\nbase_radius = 10.0\narm_length = 10.0\n"
            "forearm_length = 18.0\nplatform_radius = 5.0\n");
  EXPECT_TRUE(config.inch);
  ASSERT_EQ(config.joints.size(), 3u);
  EXPECT_TRUE(config.joints[2].angular);
  EXPECT_EQ(config.joints[2].min, -45.0);
  EXPECT_EQ(config.joints[2].max, 90.0);
  EXPECT_EQ(config.joints[2].max_velocity, 100.0);
  EXPECT_EQ(config.joints[2].max_acceleration, 50.0);
  EXPECT_EQ(config.joints[2].home, 1.0);
  EXPECT_TRUE(has_note(config, "joints 3..8 ([KINS] JOINTS = 9"));
  // [TRAJ] 10 in/s and [AXIS_X] 100 in/s^2 are the smallest.
  EXPECT_EQ(config.max_feed_per_min, 600.0);
  EXPECT_EQ(config.max_acceleration, 100.0);
  const machine::Machine imported = import_machine(kSamples / "sim/axis/rdelta.ini");
  kinematics::JointVector joints;
  ASSERT_TRUE(imported.inverse(imported.home(), joints).ok());
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(joints[j] * 180.0 / std::numbers::pi, 1.0, 1e-9);
  // rotarydeltakins (its source): arm i works on the point turned by -120 deg * i (arm 2: +120),
  // its knee at (0, -(pfr + tl cos q), -tl sin q), the ankle at (x, y - fr, z), sl apart.
  const double pfr = 10.0, tl = 10.0, sl = 18.0, fr = 5.0;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.0, 0.0, -12.0), Eigen::Vector3d(2.0, -1.0, -14.0),
        Eigen::Vector3d(-3.0, 2.5, -11.0)}) {
    ASSERT_TRUE(
        imported
            .inverse(geometry::Pose::from_mm_deg(p.x() * 25.4, p.y() * 25.4, p.z() * 25.4), joints)
            .ok());
    for (int arm = 0; arm < 3; ++arm) {
      const double turn = (arm == 1 ? -2.0 : arm == 2 ? 2.0 : 0.0) * std::numbers::pi / 3.0;
      const double x = p.x() * std::cos(turn) - p.y() * std::sin(turn);
      const double y = p.x() * std::sin(turn) + p.y() * std::cos(turn);
      const double q = joints[arm];
      const Eigen::Vector3d knee(0.0, -(pfr + tl * std::cos(q)), -tl * std::sin(q));
      EXPECT_NEAR((Eigen::Vector3d(x, y - fr, p.z()) - knee).norm(), sl, 1e-9) << "arm " << arm;
    }
  }
  // The example made by hand from the same configuration.
  const fs::path example_path = kMachines / "linuxcnc-rdelta.toml";
  if (fs::exists(example_path)) {
    const machine::Machine example = machine::load_machine(example_path);
    EXPECT_LT((imported.home().position_mm - example.home().position_mm).norm(), 1e-9);
    kinematics::JointVector want;
    const geometry::Pose pose = geometry::Pose::from_mm_deg(2.0 * 25.4, -1.0 * 25.4, -14.0 * 25.4);
    ASSERT_TRUE(example.inverse(pose, want).ok());
    ASSERT_TRUE(imported.inverse(pose, joints).ok());
    EXPECT_LT((joints - want).norm(), 1e-12);
  }
}

TEST(LinuxcncImport, TrivkinsAxisIsTheIdentity) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const machine::Machine imported = import_machine(kSamples / "sim/axis/axis.ini");
  const auto& matrix = dynamic_cast<const kinematics::MatrixKinematics&>(imported.kinematics());
  EXPECT_EQ(matrix.coefficients(), Eigen::Matrix3d::Identity());
  ASSERT_EQ(imported.joints().size(), 3u);
  EXPECT_EQ(imported.units(), machine::LengthUnit::inch);
  EXPECT_DOUBLE_EQ(imported.joints()[0].min, -10.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.joints()[0].max_velocity, 5.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.cartesian().max_feed_mm_per_min, 240.0 * 25.4);
  EXPECT_DOUBLE_EQ(imported.cartesian().envelope_max[2], 0.12 * 25.4);
}

// A stepconf configuration's [JOINT_n] SCALE (80 steps/mm on LinuxCNC's 3-axis tutorial mill) is
// the joint's steps_per_unit, what `pkm export grbl` writes as $100..$102; axis.ini, a servo-less
// sim without SCALE, has none.
TEST(LinuxcncImport, StepperScaleIsStepsPerUnit) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const machine::Machine imported =
      import_machine(kSamples / "sim/axis/vismach/3axis-tutorial/3axis-tutorial.ini");
  ASSERT_EQ(imported.joints().size(), 3u);
  for (const machine::JointSpec& joint : imported.joints()) {
    ASSERT_TRUE(joint.steps_per_unit);
    EXPECT_DOUBLE_EQ(*joint.steps_per_unit, 80.0);
  }
  EXPECT_FALSE(import_machine(kSamples / "sim/axis/axis.ini").joints()[0].steps_per_unit);
}

TEST(LinuxcncImport, TrivkinsCoordinatesPassRotaryAxesThrough) {
  PKM_SKIP_WITHOUT_LINUXCNC_SAMPLES();
  const machine::Machine imported = import_machine(kSamples / "sim/gmoccapy/gmoccapy_XYZAC.ini");
  ASSERT_EQ(imported.joints().size(), 5u);
  EXPECT_EQ(imported.kinematics().passthrough_axis(3), 3);  // a
  EXPECT_EQ(imported.kinematics().passthrough_axis(4), 5);  // c
  EXPECT_EQ(imported.joints()[4].kind, kinematics::JointKind::rotary);
}

// matrixkins' C_ parameters from setp lines (two through [CALIBRATION] substitutions), the joints
// from an #INCLUDE, the core HAL file from LIB:: the example matrix mill's coefficients.
TEST(LinuxcncImport, MatrixkinsGivesTheExampleMatrix) {
  const machine::Machine imported = import_machine(kData / "matrixkins/mill.ini");
  const machine::Machine example = machine::load_machine(kMachines / "matrix-mill.toml");
  const auto& got = dynamic_cast<const kinematics::MatrixKinematics&>(imported.kinematics());
  EXPECT_EQ(got.coefficients(),
            dynamic_cast<const kinematics::MatrixKinematics&>(example.kinematics()).coefficients());
  // Joints 3 and 4 are A and B: matrixkins passes joint n through as axis n.
  EXPECT_EQ(imported.kinematics().passthrough_axis(3), 3);
  EXPECT_EQ(imported.kinematics().passthrough_axis(4), 4);
  EXPECT_EQ(imported.joints()[2].min, -250.0);
  // Home: the joints' HOME (300, 200, -100) through matrixkins' forward, C^-1 joints.
  const Eigen::Vector3d home = got.coefficients().inverse() * Eigen::Vector3d(300, 200, -100);
  EXPECT_LT((imported.home().position_mm - home).norm(), 1e-9);
  // [AXIS_Z] 50 mm/s and 500 mm/s^2 are below [TRAJ]'s 90 and 800.
  EXPECT_DOUBLE_EQ(imported.cartesian().max_feed_mm_per_min, 3000.0);
  EXPECT_DOUBLE_EQ(imported.cartesian().max_acceleration_mm_per_s2, 500.0);
  EXPECT_EQ(imported.cartesian().envelope_min[4], -360.0 * std::numbers::pi / 180.0);
}

TEST(LinuxcncIni, RepeatedKeysCommentsAndValues) {
  const IniFile ini = IniFile::parse(
      "; comment\n[HAL]\nHALFILE = a.hal\n# HALFILE = b.hal\nHALFILE = c.hal\n"
      "[X]\nVALUE = 1 # not a comment\n  KEY=  2.5  \n",
      "t.ini");
  const auto files = ini.find_all("HAL", "HALFILE");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[1]->value, "c.hal");
  EXPECT_EQ(files[1]->where.line, 5);
  EXPECT_EQ(ini.find("X", "VALUE")->value, "1 # not a comment");
  EXPECT_EQ(ini.number("X", "KEY"), 2.5);
  try {
    (void)ini.number("X", "VALUE");
    FAIL() << "a value with a '#' is no number";
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(), "t.ini:7:[X]VALUE: '1 # not a comment' is not a number");
  }
}

TEST(LinuxcncHal, SubstitutesIniValues) {
  const IniFile ini = IniFile::parse("[KINS]\nKINEMATICS = trivkins coordinates=xz\n", "t.ini");
  const SourceLocation where{"t.hal", 3};
  EXPECT_EQ(substitute_ini_values("loadrt [KINS]KINEMATICS", ini, where),
            "loadrt trivkins coordinates=xz");
  EXPECT_EQ(substitute_ini_values("x [KINS](KINEMATICS)y", ini, where),
            "x trivkins coordinates=xzy");
  try {
    (void)substitute_ini_values("setp a [KINS]JOINTS", ini, where);
    FAIL() << "a missing key is an error";
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(), "t.hal:3: [KINS]JOINTS is not in t.ini");
  }
}

}  // namespace
}  // namespace pkm::linuxcnc
