// IK -> FK over the workspace of every example machine, Jacobians against finite differences,
// and FK along paths.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace pkm {
namespace {

// Round trips are asked of poses a machine works at. Within a few per cent of a singularity two
// assembly modes come within millimetres of each other and no seed tells them apart.
constexpr double kWorkingDexterity = 0.02;

class EveryExampleMachine : public ::testing::TestWithParam<std::string> {};

// Distance over the position coordinates the machine controls (the others stay as seeded).
double position_error(const machine::Machine& machine, const geometry::Pose& a,
                      const geometry::Pose& b) {
  double squared = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    const double difference = a.position_mm[axis] - b.position_mm[axis];
    squared += difference * difference;
  }
  return std::sqrt(squared);
}

double angle_error(const geometry::Pose& a, const geometry::Pose& b) {
  const Eigen::Matrix3d difference = geometry::rotation_from_abc(a.orientation_rad).transpose() *
                                     geometry::rotation_from_abc(b.orientation_rad);
  return Eigen::AngleAxisd(difference).angle();
}

TEST_P(EveryExampleMachine, InverseThenForwardReturnsThePose) {
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(2026);
  const std::vector<geometry::Pose> poses =
      test::sample_reachable_poses(machine, 10000, rng, 25.0, kWorkingDexterity);
  // Seeds near the answer, off by up to 1 mm and 0.5 deg: ten times a 1 ms servo step at
  // 6 m/min, what FK along a path or after a short jog starts from.
  std::uniform_real_distribution<double> offset(-1.0, 1.0);
  double worst_position = 0.0;
  double worst_angle = 0.0;
  int failures = 0;
  for (const geometry::Pose& pose : poses) {
    kinematics::JointVector joints;
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    geometry::Pose solved = pose;
    // Coordinates the model does not control stay as seeded (a pass-through machine's b).
    const geometry::Dof dof = machine.kinematics().dof();
    for (int k = 0; k < 3; ++k) {
      if (dof.controls(k)) solved.position_mm[k] += 1.0 * offset(rng);
      if (dof.controls(3 + k))
        solved.orientation_rad[k] += geometry::degrees_to_radians(0.5) * offset(rng);
    }
    const geometry::Pose seed = solved;
    const kinematics::Status status = machine.forward(joints, solved);
    if (!status.ok()) {
      if (failures == 0) {
        ADD_FAILURE() << "first failure: " << machine.describe(status) << " pose "
                      << pose.as_vector().transpose() << "\nseed " << seed.as_vector().transpose();
      }
      ++failures;
      continue;
    }
    if (position_error(machine, solved, pose) > 1e-9 && worst_position < 1e-9) {
      ADD_FAILURE() << "first miss: pose " << pose.as_vector().transpose() << "\nseed "
                    << seed.as_vector().transpose() << "\nsolved "
                    << solved.as_vector().transpose();
    }
    worst_position = std::max(worst_position, position_error(machine, solved, pose));
    if (machine.kinematics().dof().any_rotation()) {
      worst_angle = std::max(worst_angle, angle_error(solved, pose));
    }
  }
  EXPECT_EQ(failures, 0);
  EXPECT_LE(worst_position, 1e-9) << "mm";
  EXPECT_LE(worst_angle, 1e-9) << "rad";
}

// The closed-form models only (the iterative ones are held to their property test above): one
// test over the examples rather than a parameter each, so that no instance skips.
TEST(ClosedFormExampleMachines, ForwardFromHomeSeedMatches) {
  int closed_form = 0;
  for (const std::string& file : test::example_machine_files()) {
    const machine::Machine machine = test::load_example(file);
    if (machine.kinematics().dof().any_rotation() || machine.kinematics().type() == "formula") {
      continue;
    }
    ++closed_form;
    std::mt19937_64 rng(99);
    for (const geometry::Pose& pose :
         test::sample_reachable_poses(machine, 2000, rng, 0.0, kWorkingDexterity)) {
      kinematics::JointVector joints;
      ASSERT_TRUE(machine.inverse(pose, joints).ok()) << file;
      geometry::Pose solved = machine.home();
      ASSERT_TRUE(machine.forward(joints, solved).ok()) << file;
      EXPECT_LE(position_error(machine, solved, pose), 1e-9) << machine.name();
    }
  }
  EXPECT_GE(closed_form, 10);  // the plotters, glides, deltas and the matrix mill
}

TEST_P(EveryExampleMachine, JacobianMatchesFiniteDifferences) {
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(5);
  for (const geometry::Pose& pose : test::sample_reachable_poses(machine, 500, rng)) {
    kinematics::JointJacobian analytic;
    ASSERT_TRUE(machine.kinematics().jacobian(pose, analytic).ok());
    ASSERT_EQ(analytic.rows(), machine.kinematics().joint_count());
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (!machine.kinematics().dof().controls(axis)) {
        EXPECT_EQ(analytic.col(axis).cwiseAbs().maxCoeff(), 0.0);
        continue;
      }
      // Richardson-extrapolated central difference, independent of numerical_jacobian().
      const double step = axis < 3 ? 1e-3 : 1e-5;
      const auto difference = [&](double h) {
        geometry::Vector6d plus = pose.as_vector(), minus = pose.as_vector();
        plus[axis] += h;
        minus[axis] -= h;
        kinematics::JointVector joints_plus, joints_minus;
        EXPECT_TRUE(
            machine.kinematics().inverse(geometry::Pose::from_vector(plus), joints_plus).ok());
        EXPECT_TRUE(
            machine.kinematics().inverse(geometry::Pose::from_vector(minus), joints_minus).ok());
        return kinematics::JointVector((joints_plus - joints_minus) / (2 * h));
      };
      const kinematics::JointVector numeric = (4.0 * difference(step / 2) - difference(step)) / 3.0;
      const double scale = 1.0 + numeric.cwiseAbs().maxCoeff();
      EXPECT_LT((numeric - analytic.col(axis)).cwiseAbs().maxCoeff(), 1e-6 * scale)
          << "axis " << geometry::kAxisNames[axis];
    }
  }
}

TEST_P(EveryExampleMachine, ForwardAlongAPathAlwaysSucceeds) {
  // A circle of radius 20 mm about home in the first two controlled axes (a tilt circle of 5 deg
  // on 6-DOF machines), sampled finely, solved by FK seeded with the previous sample.
  const machine::Machine machine = test::load_example(GetParam());
  const geometry::Dof dof = machine.kinematics().dof();
  std::vector<geometry::Pose> path;
  for (int i = 0; i <= 5000; ++i) {
    const double phase = 2 * M_PI * i / 5000.0;
    geometry::Vector6d values = machine.home().as_vector();
    int used = 0;
    for (int axis = 0; axis < 3 && used < 2; ++axis) {
      if (!dof.controls(axis)) continue;
      values[axis] += 20.0 * (used == 0 ? std::cos(phase) - 1.0 : std::sin(phase));
      ++used;
    }
    if (dof.any_rotation()) {
      values[3] += geometry::degrees_to_radians(5.0) * std::sin(phase);
      values[4] += geometry::degrees_to_radians(5.0) * (std::cos(phase) - 1.0);
    }
    path.push_back(geometry::Pose::from_vector(values));
  }
  std::vector<kinematics::JointVector> joints(path.size());
  std::vector<kinematics::Status> statuses(path.size());
  machine.kinematics().inverse_batch(path, joints, statuses);
  for (const kinematics::Status& status : statuses) ASSERT_TRUE(status.ok());
  std::vector<geometry::Pose> solved(path.size());
  machine.kinematics().forward_path(joints, machine.home(), solved, statuses);
  for (std::size_t i = 0; i < path.size(); ++i) {
    ASSERT_TRUE(statuses[i].ok()) << "sample " << i;
    EXPECT_LE(position_error(machine, solved[i], path[i]), 1e-9);
  }
}

// The reproducer: both of the spheres' intersections lie 0.09 mm apart across the
// struts' plane, and home lies on the other side of the spheres' centres from the one in home's
// assembly mode. FK chose by that side and refused the pose IK accepts.
TEST(TriaglideForward, ChoosesTheCandidateInTheSeedsAssemblyMode) {
  const machine::Machine machine = test::load_example("triaglide.toml");
  kinematics::JointVector joints(3);
  joints << -55.255987, 78.861922, 144.881560;
  geometry::Pose solved = machine.home();
  const kinematics::Status status = machine.forward(joints, solved);
  ASSERT_TRUE(status.ok()) << machine.describe(status);
  EXPECT_NEAR(solved.position_mm.x(), -69.584789, 1e-6);
  EXPECT_NEAR(solved.position_mm.y(), 39.474569, 1e-6);
  EXPECT_NEAR(solved.position_mm.z(), 174.179306, 1e-6);
  kinematics::JointVector back;
  ASSERT_TRUE(machine.inverse(solved, back).ok());
  EXPECT_LE((back - joints).cwiseAbs().maxCoeff(), 1e-9);
  // The mirror image (the other intersection) gives the same joints in the other assembly mode:
  // IK refuses it, and FK seeded there at the model's level returns it, not home's.
  geometry::Pose mirror = geometry::Pose::from_vector(geometry::Vector6d::Zero());
  mirror.position_mm = {-69.49546134602504, 39.44374538926106, 174.14889118928411};
  EXPECT_EQ(machine.inverse(mirror, back).code, kinematics::StatusCode::other_assembly);
  geometry::Pose from_mirror = mirror;
  ASSERT_TRUE(machine.kinematics().forward(joints, from_mirror).ok());
  EXPECT_LE((from_mirror.position_mm - mirror.position_mm).norm(), 1e-9);
}

// The Python batch's case along a track (forward_path, what pkmkins and verify use): a helix
// from the triaglide pose through the struts' plane, with one row of joints no strut
// reaches in the middle. Only that row fails; the next is solved from the last good pose.
TEST(TriaglideForward, AFailedRowOfAPathFailsAlone) {
  const machine::Machine machine = test::load_example("triaglide.toml");
  const Eigen::Vector3d start(-69.5847887844257, 39.47456913822882, 174.17930640982385);
  std::vector<geometry::Pose> path;
  for (int i = 0; i < 4000; ++i) {
    const double turn = 4.0 * M_PI * i / 3999.0;
    geometry::Pose pose = geometry::Pose::from_vector(geometry::Vector6d::Zero());
    pose.position_mm =
        start + Eigen::Vector3d(20.0 * std::cos(turn + M_PI / 2),
                                20.0 * std::sin(turn + M_PI / 2) - 20.0, 5.0 * turn / (2.0 * M_PI));
    path.push_back(pose);
  }
  std::vector<kinematics::JointVector> joints(path.size());
  std::vector<kinematics::Status> statuses(path.size());
  machine.kinematics().inverse_batch(path, joints, statuses);
  for (const kinematics::Status& status : statuses) ASSERT_TRUE(status.ok());
  const std::size_t bad = path.size() / 2;
  joints[bad] << -400.0, 800.0, -400.0;  // within the rails' limits, too far apart to meet
  std::vector<geometry::Pose> solved(path.size());
  machine.kinematics().forward_path(joints, machine.home(), solved, statuses);
  int failed = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i == bad) {
      EXPECT_EQ(statuses[i].code, kinematics::StatusCode::unreachable);
      continue;
    }
    failed += statuses[i].ok() ? 0 : 1;
    // The first rows are within 0.05 mm of the struts' plane: the joints pin them to 1e-8 mm.
    if (statuses[i].ok()) {
      EXPECT_LE(position_error(machine, solved[i], path[i]), 1e-8) << i;
    }
  }
  EXPECT_EQ(failed, 0);
}

// The sign of det(d joints / d pose) over the controlled coordinates: which side of the
// singularities a pose is on.
// d joints / d pose over the controlled coordinates only; empty where there is no Jacobian.
Eigen::MatrixXd controlled_jacobian(const machine::Machine& machine, const geometry::Pose& pose) {
  kinematics::JointJacobian jacobian;
  if (!machine.kinematics().jacobian(pose, jacobian).ok()) return {};
  const geometry::Dof dof = machine.kinematics().dof();
  Eigen::MatrixXd reduced(jacobian.rows(), dof.count());
  for (int axis = 0, k = 0; axis < geometry::kPoseSize; ++axis) {
    if (dof.controls(axis)) reduced.col(k++) = jacobian.col(axis);
  }
  return reduced;
}

double determinant_sign(const machine::Machine& machine, const geometry::Pose& pose) {
  const Eigen::MatrixXd reduced = controlled_jacobian(machine, pose);
  if (reduced.size() == 0) return 0.0;
  return reduced.rows() == reduced.cols() ? std::copysign(1.0, reduced.determinant()) : 0.0;
}

std::string text(const geometry::Pose& pose) {
  std::ostringstream out;
  out << pose.as_vector().transpose();
  return out.str();
}

// The smallest singular value of d joints / d pose over the controlled coordinates (mm per mm,
// rad per rad): how much the joints move per unit of the least visible pose motion.
double smallest_singular_value(const machine::Machine& machine, const geometry::Pose& pose) {
  Eigen::MatrixXd reduced = controlled_jacobian(machine, pose);
  if (reduced.size() == 0) return 0.0;
  // A rotary joint's rad on a 100 mm lever (test::dexterity's scale; a delta's arm is 100-300).
  for (int joint = 0; joint < machine.kinematics().joint_count(); ++joint) {
    if (machine.kinematics().joint_kind(joint) == kinematics::JointKind::rotary)
      reduced.row(joint) *= 100.0;
  }
  return reduced.jacobiSvd().singularValues().minCoeff();
}

// FK solves the joints to 1e-11 (ForwardOptions): that pins the pose down to 1e-9 mm where the
// joints move at least 1e-2 mm per mm the pose moves. Nearer a singularity FK must give a pose
// whose joints are the given ones, not the pose itself.
constexpr double kPinnedSingularValue = 1e-2;

// Issue 25: FK returns every pose IK accepts on home's side of the singularities, seeded at home
// and at the previous pose of a path that jumps across the workspace, poses near singularities
// included. A pose IK accepts across a singularity from home (det J of the other sign: a hexapod
// or hexaglide at the corners of its box) is another assembly branch: FK never returns it.
TEST_P(EveryExampleMachine, ForwardReturnsEveryPoseInverseAcceptsFromHomeAndAlongAPath) {
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(31);
  const std::vector<geometry::Pose> poses =
      test::sample_reachable_poses(machine, 3000, rng, 25.0, 0.0);
  const double home_sign = determinant_sign(machine, machine.home());
  geometry::Pose previous = machine.home();
  int failures = 0;
  int other_branch = 0;
  double worst_mm = 0.0;
  for (const geometry::Pose& pose : poses) {
    kinematics::JointVector joints;
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    const bool pinned = smallest_singular_value(machine, pose) >= kPinnedSingularValue;
    const bool home_side = home_sign == 0.0 || determinant_sign(machine, pose) == home_sign;
    other_branch += home_side ? 0 : 1;
    for (const geometry::Pose& seed : {machine.home(), previous}) {
      geometry::Pose solved = seed;
      const kinematics::Status status = machine.forward(joints, solved);
      if (!home_side) {
        const double error = position_error(machine, solved, pose) + angle_error(solved, pose);
        EXPECT_TRUE(!status.ok() || error > 1e-3) << "the other branch's pose " << text(pose);
        continue;
      }
      if (!status.ok()) {
        if (failures++ == 0) {
          ADD_FAILURE() << machine.describe(status) << " at " << text(pose) << " from "
                        << text(seed);
        }
        continue;
      }
      const double error =
          position_error(machine, solved, pose) +
          (machine.kinematics().dof().any_rotation() ? angle_error(solved, pose) : 0.0);
      if (pinned) {
        EXPECT_LE(error, 1e-9) << text(pose) << " from " << text(seed);
        worst_mm = std::max(worst_mm, error);
      } else {
        kinematics::JointVector back;
        ASSERT_TRUE(machine.inverse(solved, back).ok()) << text(pose);
        EXPECT_LE((back - joints).cwiseAbs().maxCoeff(), 1e-10)
            << text(pose) << " from " << text(seed);
      }
      previous = solved;
    }
  }
  EXPECT_EQ(failures, 0);
  RecordProperty("worst_mm", kinematics::formatted_number("%.3g", worst_mm));
  RecordProperty("other_branch", other_branch);
}

INSTANTIATE_TEST_SUITE_P(Examples, EveryExampleMachine,
                         ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& test_info) { return test::test_name(test_info.param); });

}  // namespace
}  // namespace pkm
