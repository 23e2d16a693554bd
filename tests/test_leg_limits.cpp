// Joint-angle and leg-interference limits (max_joint_angle, leg_diameter) of hexapods and glides:
// hand-computed thresholds, the upside-down platform, the neighbour rule, the file's keys.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/leg_limits.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

machine::Machine vertical_hexapod(const std::string& extra_keys) {
  return test::parallel_leg_hexapod(test::hexagon_points(), extra_keys);
}

// The leg at 270 deg (leg 5) under a tilt A about x: its base joint (0, -r, 0), its platform
// joint (0, -r cos A, h - r sin A), so the leg leans by t = atan(r (1 - cos A) / (h - r sin A))
// from the vertical, towards +y; the platform's neutral axis (z at home) turns by A towards -y.
// Its platform end is then at A + t from its axis, the most of any end (the legs nearer the x
// axis lean less, those at +y lean against the turn). A + t = 30 deg at A = 25.4958 deg, found by
// bisection on this formula alone.
double tilt_where_leg5_reaches(double limit_deg) {
  const double r = 300.0, h = 500.0;
  const auto end_angle = [&](double a) {
    return a + std::atan(r * (1.0 - std::cos(a)) / (h - r * std::sin(a)));
  };
  double low = 0.0, high = geometry::degrees_to_radians(limit_deg);
  while (high - low > 1e-14) {
    const double middle = 0.5 * (low + high);
    (end_angle(middle) < geometry::degrees_to_radians(limit_deg) ? low : high) = middle;
  }
  return geometry::radians_to_degrees(low);
}

TEST(LegLimits, TiltedHexapodPassesThirtyDegreesWhereComputedByHand) {
  const machine::Machine machine = vertical_hexapod("max_joint_angle = 30");
  const double tilt = tilt_where_leg5_reaches(30.0);
  EXPECT_NEAR(tilt, 25.4958, 1e-4);
  kinematics::JointVector joints;
  EXPECT_TRUE(
      machine.inverse(geometry::Pose::from_mm_deg(0, 0, 500, tilt - 1e-6, 0, 0), joints).ok());
  const geometry::Pose beyond = geometry::Pose::from_mm_deg(0, 0, 500, tilt + 1e-6, 0, 0);
  const kinematics::Status status = machine.inverse(beyond, joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::joint_angle);
  EXPECT_EQ(status.joint, 4);  // leg5
  EXPECT_EQ(machine.explain(beyond, status),
            "pose x 0.000 y 0.000 z 500.000 mm a 25.496 b 0.000 c 0.000 deg: joint_angle: the "
            "platform joint of 'leg5' is at 30.000 deg from its axis; max_joint_angle is "
            "30.000 deg");
  EXPECT_NE(machine.kinematics().why_refused(beyond, status).find("the platform joint of leg 5"),
            std::string::npos);
  // The values behind it: leg 5's platform end at the limit, its base end at the lean t.
  std::vector<kinematics::MechanismLimit> limits;
  machine.kinematics().mechanism_limits(beyond, limits);
  ASSERT_EQ(limits.size(), 12u);
  EXPECT_NEAR(geometry::radians_to_degrees(limits[9].value), 30.0, 1e-5);
  EXPECT_NEAR(geometry::radians_to_degrees(limits[8].value), 30.0 - tilt, 1e-5);
  for (const kinematics::MechanismLimit& limit : limits) {
    if (limit.leg != 4 || limit.other != kinematics::kPlatformEnd) {
      EXPECT_GT(limit.margin(), 0.0);
    }
  }
}

TEST(LegLimits, TranslationTurnsEveryLegAlike) {
  // Moving x by d leans every vertical leg by atan(d / 500) at both ends: 30 deg at
  // d = 500 tan 30 = 288.675 mm; with max_joint_angle = [40, 30] only the platform ends count.
  const machine::Machine machine = vertical_hexapod("max_joint_angle = [40, 30]");
  const double d = 500.0 * std::tan(std::numbers::pi / 6.0);
  kinematics::JointVector joints;
  EXPECT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(d - 1e-6, 0, 500, 0, 0, 0), joints).ok());
  const kinematics::Status status =
      machine.inverse(geometry::Pose::from_mm_deg(d + 1e-6, 0, 500, 0, 0, 0), joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::joint_angle);
  EXPECT_EQ(status.joint, 0);
}

TEST(LegLimits, UpsideDownPlatformIsRefusedByTheModel) {
  const machine::Machine machine = vertical_hexapod("max_joint_angle = 45");
  kinematics::JointVector joints;
  // B = 180 deg, the platform turned over about y; its legs reach (IK alone gives lengths).
  const geometry::Pose flipped = geometry::Pose::from_mm_deg(0, 0, 500, 0, 180, 0);
  EXPECT_TRUE(dynamic_cast<const kinematics::HexapodKinematics&>(machine.kinematics())
                  .inverse_without_leg_limits(flipped, joints)
                  .ok());
  EXPECT_EQ(machine.kinematics().inverse(flipped, joints).code,
            kinematics::StatusCode::joint_angle);
  EXPECT_EQ(machine.inverse(flipped, joints).code, kinematics::StatusCode::joint_angle);
  // The platform joint at angle phi goes to (-r cos phi, r sin phi, h) and the platform's axis to
  // -z: the leg (-2 r cos phi, 0, h) is at 180 - atan(2 r |cos phi| / h) from it, 180 deg for
  // the legs at 90 and 270 deg, 133.898 deg for the others.
  std::vector<kinematics::MechanismLimit> limits;
  machine.kinematics().mechanism_limits(flipped, limits);
  ASSERT_EQ(limits.size(), 12u);
  for (int leg = 0; leg < 6; ++leg) {
    const double cos_phi = std::cos(geometry::degrees_to_radians(30.0 + 60.0 * leg));
    EXPECT_NEAR(geometry::radians_to_degrees(limits[static_cast<std::size_t>(2 * leg + 1)].value),
                180.0 - geometry::radians_to_degrees(std::atan(600.0 * std::abs(cos_phi) / 500.0)),
                1e-6);  // the points are written to 6 decimals
  }
}

// The leg-limit-free view forward kinematics iterates on: its inverse is the model's without the
// angle check, and a clone of it keeps working after the model it was made from is gone.
TEST(LegLimits, ALegLimitFreeCloneOutlivesItsModel) {
  const machine::Machine machine = vertical_hexapod("max_joint_angle = 45");
  const geometry::Pose flipped = geometry::Pose::from_mm_deg(0, 0, 500, 0, 180, 0);
  std::unique_ptr<kinematics::Kinematics> clone;
  {
    const auto model = std::make_unique<kinematics::HexapodKinematics>(
        dynamic_cast<const kinematics::HexapodKinematics&>(machine.kinematics()));
    clone = kinematics::WithoutLegLimits<kinematics::HexapodKinematics>(*model).clone();
  }
  kinematics::JointVector joints, expected;
  ASSERT_TRUE(clone->inverse(flipped, joints).ok());
  ASSERT_TRUE(dynamic_cast<const kinematics::HexapodKinematics&>(machine.kinematics())
                  .inverse_without_leg_limits(flipped, expected)
                  .ok());
  for (int leg = 0; leg < 6; ++leg) EXPECT_DOUBLE_EQ(joints[leg], expected[leg]);
}

// Legs 1 and 2 stand 60 mm apart along x, 500 mm tall; moving the platform by d along x leans
// both alike, so their axes stay parallel at 60 h / sqrt(d^2 + h^2) mm: 40 mm at
// d = h sqrt(1.5^2 - 1) = 559.017 mm. The other legs lie at least 300 mm apart across x.
TEST(LegLimits, TwoLegsBroughtWithinTheDiameterInterfere) {
  const machine::Machine machine =
      test::parallel_leg_hexapod(test::close_pair_points(), "leg_diameter = 40");
  const double d = 500.0 * std::sqrt(1.25);
  kinematics::JointVector joints;
  EXPECT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(d - 1e-6, 0, 500, 0, 0, 0), joints).ok());
  const geometry::Pose close = geometry::Pose::from_mm_deg(d + 1e-6, 0, 500, 0, 0, 0);
  const kinematics::Status status = machine.inverse(close, joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::interference);
  EXPECT_EQ(status.joint, 0);
  EXPECT_EQ(machine.explain(close, status),
            "pose x 559.017 y 0.000 z 500.000 mm a 0.000 b 0.000 c 0.000 deg: interference: "
            "'leg1' and 'leg2' are 40.000 mm apart (axis to axis); leg_diameter is 40.000 mm");
  std::vector<kinematics::MechanismLimit> limits;
  machine.kinematics().mechanism_limits(geometry::Pose::from_mm_deg(0, 0, 500, 0, 0, 0), limits);
  ASSERT_EQ(limits.size(), 15u);  // every pair: no two joints within 40 mm
  EXPECT_NEAR(limits[0].value, 60.0, 1e-12);
}

TEST(LegLimits, LegsSharingAJointAreNotCheckedAgainstEachOther) {
  // A biglide's two struts meet at one platform joint: a pair within the diameter at home.
  // Rails on the x axis, struts of 500 mm to the pen, carriages at x -+ 300 at home (0, -400).
  const std::string text =
      "name = \"biglide\"\n[kinematics]\ntype = \"glide\"\nmax_joint_angle = 30\n"
      "leg_diameter = 30\n"
      "[[kinematics.rails]]\norigin = [0, 0, 0]\ndirection = [1, 0, 0]\nstrut = 500\n"
      "attach = [0, 0, 0]\nbranch = -1\n"
      "[[kinematics.rails]]\norigin = [0, 0, 0]\ndirection = [1, 0, 0]\nstrut = 500\n"
      "attach = [0, 0, 0]\nbranch = 1\n" +
      test::joints_text(2, -1000, 1000) +
      "[cartesian]\nmax_feed = 6000\nmax_acceleration = 1000\nhome = [0, -400]\n";
  const machine::Machine machine = machine::parse_machine(text, "biglide.toml");
  std::vector<kinematics::MechanismLimit> limits;
  machine.kinematics().mechanism_limits(machine.home(), limits);
  EXPECT_EQ(limits.size(), 4u);  // two ends of two struts; no pair
  // The struts leave the rail at asin(y / 500); from -53.130 deg at home, 30 deg more at
  // y = 500 sin(-23.130 deg) = -196.41 mm, whatever x.
  const double y = 500.0 * std::sin(std::asin(-0.8) + std::numbers::pi / 6.0);
  EXPECT_NEAR(y, -196.41, 0.01);
  kinematics::JointVector joints;
  EXPECT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(120.0, y - 1e-6, 0), joints).ok());
  const kinematics::Status status =
      machine.inverse(geometry::Pose::from_mm_deg(120.0, y + 1e-6, 0), joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::joint_angle);
  EXPECT_EQ(status.joint, 0);
  EXPECT_NE(machine.kinematics()
                .why_refused(geometry::Pose::from_mm_deg(120.0, y + 1e-6, 0), status)
                .find("the inner (base or carriage) joint of strut 1 is at 30.000 deg"),
            std::string::npos);
  // Forward kinematics refuses the joints of that pose too.
  const auto& glide = dynamic_cast<const kinematics::GlideKinematics&>(machine.kinematics());
  ASSERT_TRUE(
      glide.inverse_without_leg_limits(geometry::Pose::from_mm_deg(0, -150, 0), joints).ok());
  geometry::Pose pose = machine.home();
  EXPECT_EQ(machine.forward(joints, pose).code, kinematics::StatusCode::joint_angle);
}

TEST(LegLimits, SegmentDistanceMatchesHandCases) {
  using V = Eigen::Vector3d;
  // Skew lines crossing at right angles, 7 mm apart, closest points inside both.
  EXPECT_NEAR(kinematics::segment_distance(V(-1, 0, 0), V(1, 0, 0), V(0, -1, 7), V(0, 1, 7)), 7.0,
              1e-12);
  // The same, the second segment's nearest point cut off: from (1, 0, 0) to (0, 2, 7) ... (0, 3,
  // 7): the end (0, 2, 7) is nearest, sqrt(1 + 4 + 49).
  EXPECT_NEAR(kinematics::segment_distance(V(-1, 0, 0), V(1, 0, 0), V(0, 2, 7), V(0, 3, 7)),
              std::sqrt(53.0), 1e-12);
  // Parallel, overlapping: the gap; end to end along a line: the gap between the ends.
  EXPECT_NEAR(kinematics::segment_distance(V(0, 0, 0), V(10, 0, 0), V(5, 3, 4), V(15, 3, 4)), 5.0,
              1e-12);
  EXPECT_NEAR(kinematics::segment_distance(V(0, 0, 0), V(10, 0, 0), V(12, 0, 0), V(20, 0, 0)), 2.0,
              1e-12);
  // Crossing segments touch.
  EXPECT_NEAR(kinematics::segment_distance(V(-1, -1, 0), V(1, 1, 0), V(-1, 1, 0), V(1, -1, 0)), 0.0,
              1e-12);
}

TEST(LegLimits, WithoutTheKeysNothingChanges) {
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  EXPECT_FALSE(machine.kinematics().has_mechanism_limits());
  std::vector<kinematics::MechanismLimit> limits;
  machine.kinematics().mechanism_limits(machine.home(), limits);
  EXPECT_TRUE(limits.empty());
  kinematics::JointVector joints;
  // Upside down, the hexapod without limits is refused by the machine's assembly mode only.
  const geometry::Pose flipped = geometry::Pose::from_mm_deg(0, 0, 1000, 0, 180, 0);
  EXPECT_TRUE(machine.kinematics().inverse(flipped, joints).ok());
  EXPECT_EQ(machine.inverse(flipped, joints).code, kinematics::StatusCode::other_assembly);
}

TEST(LegLimits, FileKeysAreChecked) {
  const auto refused = [](const std::string& keys) {
    try {
      // Refused before the legs' singularity is (the model reads its keys first).
      machine::parse_machine(
          test::hexapod_text(test::hexagon_points(), test::hexagon_points(), keys), "keys.toml");
    } catch (const machine::MachineFileError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refused("max_joint_angle = 190").find("max_joint_angle: must be between 0 and 180"),
            std::string::npos);
  EXPECT_NE(refused("max_joint_angle = [30]").find("two [inner, platform]"), std::string::npos);
  EXPECT_NE(refused("leg_diameter = -4").find("leg_diameter: must be a positive length"),
            std::string::npos);
  EXPECT_NE(refused("base_joint_axis = [0, 0, 1]").find("only read beside max_joint_angle"),
            std::string::npos);
  EXPECT_NE(refused("max_joint_angle = 30\nbase_joint_axis = [0, 0]").find("needs 3 numbers"),
            std::string::npos);
  // Axes given: all base joints vertical, platform joints tilted 10 deg about x at home.
  EXPECT_NE(refused("max_joint_angle = 9\nbase_joint_axis = [0, 0, 1]\n"
                    "platform_joint_axis = [0, -0.17364817766693, 0.98480775301221]")
                .find("home: is not a usable pose: pose x 0.000 y 0.000 z 500.000 mm a 0.000 b "
                      "0.000 c 0.000 deg: joint_angle: the platform joint of 'leg1' is at 10.000 "
                      "deg"),
            std::string::npos);
}

}  // namespace
}  // namespace pkm

namespace pkm {
namespace {

TEST(LegLimits, CalibrationWritesTheKeysBack) {
  // A fitted geometry replaces [kinematics]: the limits the file set must survive it.
  const std::string text = test::hexapod_text(
      test::hexagon_points(), test::platform_off_base(test::hexagon_points()),
      "max_joint_angle = [40, 30]\nleg_diameter = 20\nbase_joint_axis = [0, 0, 2]");
  const machine::Machine machine = machine::parse_machine(text, "limits.toml");
  const std::string rewritten = machine::replace_kinematics_section(
      text, "limits.toml", machine.kinematics(), machine::LengthUnit::mm);
  const machine::Machine reread = machine::parse_machine(rewritten, "limits.toml");
  const auto& settings = dynamic_cast<const kinematics::HexapodKinematics&>(reread.kinematics())
                             .leg_limits()
                             .settings();
  EXPECT_NEAR(geometry::radians_to_degrees(settings.max_joint_angle_rad[0]), 40.0, 1e-12);
  EXPECT_NEAR(geometry::radians_to_degrees(settings.max_joint_angle_rad[1]), 30.0, 1e-12);
  EXPECT_EQ(settings.leg_diameter_mm, 20.0);
  ASSERT_TRUE(settings.inner_axis.has_value());
  EXPECT_EQ(*settings.inner_axis, Eigen::Vector3d(0, 0, 1));
  EXPECT_FALSE(settings.platform_axis.has_value());
}

}  // namespace
}  // namespace pkm
