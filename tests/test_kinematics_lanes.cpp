// The models' two IK paths, AVX2 lanes (four poses at once, libmvec's sines and cosines) and
// scalar, agree on every example machine; forward kinematics along real planned jobs with a
// ForwardTrack meets the FK tolerance at every sample in about one Newton step each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "pkm/kinematics/lanes.hpp"
#include "pkm/motion/planner.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

// The scalar paths for its lifetime.
class ScalarPathOnly {
 public:
  ScalarPathOnly() : previous_(kinematics::lanes::set_avx2_enabled(false)) {}
  ~ScalarPathOnly() { kinematics::lanes::set_avx2_enabled(previous_); }
  ScalarPathOnly(const ScalarPathOnly&) = delete;
  ScalarPathOnly& operator=(const ScalarPathOnly&) = delete;

 private:
  bool previous_;
};

struct Solved {
  std::vector<kinematics::JointVector> batch, single;
  std::vector<kinematics::Status> batch_status, single_status;
};

Solved solve(const kinematics::Kinematics& kinematics, const std::vector<geometry::Pose>& poses) {
  Solved solved;
  solved.batch.resize(poses.size());
  solved.batch_status.resize(poses.size());
  kinematics.inverse_batch(poses, solved.batch, solved.batch_status);
  for (const geometry::Pose& pose : poses) {
    solved.single.emplace_back();
    solved.single_status.push_back(kinematics.inverse(pose, solved.single.back()));
  }
  return solved;
}

double largest_difference(const kinematics::JointVector& a, const kinematics::JointVector& b) {
  return a.size() == b.size() ? (a - b).cwiseAbs().maxCoeff() : INFINITY;
}

class KinematicsLanes : public ::testing::TestWithParam<std::string> {};

TEST_P(KinematicsLanes, VectorAndScalarPathsAgree) {
  // Without AVX2 the "vector" calls take the scalar path too: the test still holds (and runs),
  // rather than skipping, which scripts/test would count as a part of the suite not run.
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(2027);
  // Across the workspace, tilted up to 30 deg; 1001 poses, so the last block of four is partial.
  std::vector<geometry::Pose> poses = test::sample_reachable_poses(machine, 1001, rng, 30.0);
  const std::size_t reachable = poses.size();
  // Poses beyond the reach, so that the lanes' refusals are checked against the scalar ones (the
  // same code, the same rail or cable), and a NaN.
  for (std::size_t i = 0; i < 40; ++i) {
    geometry::Pose far = poses[i];
    far.position_mm *= 1.0 + 0.1 * static_cast<double>(i);
    poses.push_back(far);
  }
  poses[500].orientation_rad.y() = std::nan("");
  const Solved vector = solve(machine.kinematics(), poses);
  Solved scalar;
  {
    const ScalarPathOnly scalar_only;
    scalar = solve(machine.kinematics(), poses);
  }
  int agreeing = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const kinematics::StatusCode code = scalar.single_status[i].code;
    ASSERT_EQ(vector.batch_status[i].code, code) << "pose " << i;
    ASSERT_EQ(vector.single_status[i].code, code) << "pose " << i;
    ASSERT_EQ(scalar.batch_status[i].code, code) << "pose " << i;
    ASSERT_EQ(vector.batch_status[i].joint, scalar.single_status[i].joint) << "pose " << i;
    if (code != kinematics::StatusCode::ok) continue;
    // mm, or rad for a rotary joint; beyond the reach, where a leg can be metres long, a few ulp
    // of its length (the lanes' fused multiply-adds round differently: 1 ulp of 8 m is 1.8e-12).
    const double tolerance =
        i < reachable ? 1e-12 : std::max(1e-12, 4e-16 * scalar.single[i].cwiseAbs().maxCoeff());
    EXPECT_LE(largest_difference(vector.batch[i], scalar.single[i]), tolerance) << "pose " << i;
    EXPECT_LE(largest_difference(vector.single[i], scalar.single[i]), tolerance) << "pose " << i;
    EXPECT_LE(largest_difference(scalar.batch[i], scalar.single[i]), tolerance) << "pose " << i;
    ++agreeing;
  }
  EXPECT_GE(agreeing, 1000);
  EXPECT_EQ(vector.batch_status[500].code, kinematics::StatusCode::invalid_input);
}

INSTANTIATE_TEST_SUITE_P(Examples, KinematicsLanes,
                         ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& test_info) { return test::test_name(test_info.param); });

// A real job, planned at LinuxCNC's servo period, on a machine it fits.
struct RealPath {
  const char* job;      // in the real corpus
  const char* machine;  // in examples/machines
  Eigen::Vector3d origin_mm;
};

class Collect : public motion::SampleSink {
 public:
  void write(const motion::Sample& sample) override { samples.push_back(sample); }
  std::vector<motion::Sample> samples;
};

class AlongARealJob : public ::testing::TestWithParam<RealPath> {};

TEST_P(AlongARealJob, WarmForwardMeetsTheToleranceInAboutOneStep) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const RealPath& row = GetParam();
  const machine::Machine machine = test::load_example(row.machine);
  motion::PlanOptions options;
  options.origin.head<3>() = row.origin_mm;
  options.max_samples = 40000;
  Collect collect;
  motion::plan_program(machine, test::real_corpus() / row.job, {}, options, collect);
  ASSERT_GE(collect.samples.size(), 5000u);
  const double tolerance_mm = machine.kinematics().forward_options().tolerance_mm;
  kinematics::ForwardTrack track;
  geometry::Pose pose = geometry::Pose::from_vector(collect.samples.front().pose);
  long steps = 0;
  double worst_residual_mm = 0.0, worst_position_mm = 0.0;
  for (const motion::Sample& sample : collect.samples) {
    const kinematics::Status status = machine.forward(sample.joints, pose, track);
    ASSERT_TRUE(status.ok()) << machine.describe(status) << " at line " << sample.line;
    steps += status.iterations;
    kinematics::JointVector back;
    ASSERT_TRUE(machine.kinematics().inverse(pose, back).ok());
    worst_residual_mm = std::max(worst_residual_mm, largest_difference(back, sample.joints));
    worst_position_mm = std::max(worst_position_mm,
                                 (pose.position_mm - sample.pose.head<3>()).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst_residual_mm, tolerance_mm);
  EXPECT_LE(worst_position_mm, 1e-8);
  const double steps_per_sample =
      static_cast<double>(steps) / static_cast<double>(collect.samples.size());
  EXPECT_LE(steps_per_sample, 1.5) << row.job << " on " << row.machine;
}

INSTANTIATE_TEST_SUITE_P(
    RealJobs, AlongARealJob,
    ::testing::Values(
        RealPath{"cam/pcb2gcode/milldrill.ngc", "linuxcnc-hexapod-sim.toml", {-65.0, 50.0, 480.0}},
        RealPath{"cam/pcb2gcode/milldrill.ngc", "hexapod-bit.toml", {-30.0, 30.0, 1000.0}},
        RealPath{"cam/pcb2gcode/milldrill.ngc", "hexaglide.toml", {-30.0, 30.0, 0.0}},
        RealPath{"cam/bcnc/sample.gcode", "linuxcnc-ldelta.toml", {-15.0, -12.0, 0.0}},
        RealPath{"cam/bcnc/sample.gcode", "linear-delta.toml", {-15.0, -12.0, 50.0}}),
    [](const auto& test_info) { return test::test_name(test_info.param.machine); });

}  // namespace
}  // namespace pkm
