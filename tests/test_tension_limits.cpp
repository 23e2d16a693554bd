// Tension-limited motion of a hanging cable machine: the acceleration bound along a move against
// a symmetric V by hand, the junction speed, and planned jobs (a real Maslow job and a hand-made
// aggressive one) whose every sample, with its acceleration by finite differences, keeps both
// cables within their tension limits, where the same jobs planned without the limits do not.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/tension_limit.hpp"
#include "real_corpus.hpp"

namespace pkm::motion {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(PKM_SOURCE_DIR) / "tests" / "data";

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// The test frame (tests/data/maslow-tension.toml) as the ideal model sees it: chains tied at the
// bit, no mass, no tension limits; the same joints and Cartesian limits. The planner bounds
// nothing by tensions on it.
Machine frame_without_tensions() {
  std::istringstream lines(read_text(kData / "maslow-tension.toml"));
  std::string text, line;
  while (std::getline(lines, line)) {
    if (line.starts_with("effector_") || line.starts_with("tension_limits")) continue;
    text += line + "\n";
  }
  return parse_machine(text, "maslow-tension.toml without tensions");
}

Machine frame() {
  return load_machine(kData / "maslow-tension.toml");
}

const CablePlotterKinematics& cables(const Machine& machine) {
  return dynamic_cast<const CablePlotterKinematics&>(machine.kinematics());
}

// Maslow jobs are written about the sheet's centre.
PlanOptions on_the_sheet() {
  PlanOptions options;
  options.origin << 1489.2, -1072.6, 0.0, 0.0, 0.0, 0.0;
  return options;
}

// A program in a temporary file, removed with the object.
class TempProgram {
 public:
  explicit TempProgram(const std::string& text) {
    static int counter = 0;
    path_ = fs::temp_directory_path() / ("pkm-tension-" + std::to_string(::getpid()) + "-" +
                                         std::to_string(counter++) + ".ngc");
    std::ofstream(path_) << text;
  }
  ~TempProgram() { fs::remove(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Checks each sample's tensions under its acceleration, by finite differences of the sampled
// positions (the samples before and after it), against the limits [min_N, max_N], from the
// statics of the machine alone: the planner's own bound is not used.
class TensionCheck final : public SampleSink {
 public:
  TensionCheck(const CablePlotterKinematics& kinematics, double min_N, double max_N)
      : kinematics_(kinematics), min_N_(min_N), max_N_(max_N) {}

  void write(const Sample& sample) override {
    window_[0] = window_[1];
    window_[1] = window_[2];
    window_[2] = sample;
    if (++count_ >= 3) check(window_[0], window_[1], window_[2]);
  }

  long outside = 0;               // samples with a tension outside [min_N, max_N]
  double worst_margin_N = 1e300;  // the least distance of a tension to its nearer limit
  double lowest_N = 1e300, highest_N = -1e300;
  std::string first_outside;
  long checked = 0;

 private:
  void check(const Sample& before, const Sample& at, const Sample& after) {
    const double dt0 = at.time_s - before.time_s, dt1 = after.time_s - at.time_s;
    if (!(dt0 > 0.0) || !(dt1 > 0.0)) return;
    const Eigen::Vector2d v0 = (at.pose.head<2>() - before.pose.head<2>()) / dt0;
    const Eigen::Vector2d v1 = (after.pose.head<2>() - at.pose.head<2>()) / dt1;
    const Eigen::Vector2d acceleration = 2.0 * (v1 - v0) / (dt0 + dt1);
    CableStatics statics;
    const Status status = kinematics_.statics(Pose::from_vector(at.pose), acceleration, statics);
    ++checked;
    double margin = -1.0;
    if (status.ok()) {
      for (int cable = 0; cable < 2; ++cable) {
        const std::size_t c = static_cast<std::size_t>(cable);
        lowest_N = std::min(lowest_N, statics.lowest_N[c]);
        highest_N = std::max(highest_N, statics.highest_N[c]);
        margin = cable == 0 ? 1e300 : margin;
        margin = std::min({margin, statics.lowest_N[c] - min_N_, max_N_ - statics.highest_N[c]});
      }
    }
    worst_margin_N = std::min(worst_margin_N, margin);
    if (margin < 0.0 && outside++ == 0) {
      std::ostringstream text;
      text << "t = " << at.time_s << " s, line " << at.line << ", x " << at.pose[0] << " y "
           << at.pose[1] << " mm, acceleration " << acceleration.transpose()
           << " mm/s^2: " << statics.lowest_N[0] << ".." << statics.highest_N[0] << " N, "
           << statics.lowest_N[1] << ".." << statics.highest_N[1] << " N";
      first_outside = text.str();
    }
  }

  const CablePlotterKinematics& kinematics_;
  double min_N_, max_N_;
  Sample window_[3];
  long count_ = 0;
};

// Fast zig-zags (F30000, 500 mm/s) in the sheet's top corners and down its sides, then rapids
// across the top and corner to corner: where one chain pulls almost sideways with little
// tension, and where both pull nearly level with much.
std::string aggressive_job() {
  std::ostringstream job;
  job << "G21 G90 G64 P1\nG0 X-1150 Y580\nG1 F30000\n";
  for (int k = 0; k <= 12; ++k) job << "X" << -1150 + 25 * k << " Y" << (k % 2 ? 420 : 580) << "\n";
  for (int k = 0; k <= 12; ++k) job << "X" << 1150 - 25 * k << " Y" << (k % 2 ? 420 : 580) << "\n";
  job << "G0 X1180 Y560\nG1\n";
  for (int k = 0; k <= 20; ++k) job << "X" << (k % 2 ? 1060 : 1190) << " Y" << 560 - 55 * k << "\n";
  job << "G0 X-1190 Y560\nG1\n";
  for (int k = 0; k <= 20; ++k)
    job << "X" << (k % 2 ? -1060 : -1190) << " Y" << 560 - 55 * k << "\n";
  // The top half of a circle of 150 mm radius in the top-left corner at F60000 in 3500 chords
  // (0.13 mm, turning 0.9 mrad at each: tangent joins, no blends), as CAM output gives curves:
  // its centripetal acceleration comes as the chords' changes of direction, several per period.
  job << std::setprecision(10) << "G0 X-919 Y460\nG1 F60000\n";
  for (int k = 1; k <= 3500; ++k) {
    const double angle = std::numbers::pi * k / 3500.0;
    job << "X" << -1069.0 + 150.0 * std::cos(angle) << " Y" << 460.0 + 150.0 * std::sin(angle)
        << "\n";
  }
  // The same circle as one arc in the top-right corner: v^2 / r bounds its speed.
  job << "G0 X1219 Y460\nG2 X1219 Y460 I-150 J0\n";
  job << "G61\nG0 X-1150 Y590\nX1150\nX-1150 Y-590\nX1150 Y590\nX0 Y0\nM2\n";
  return job.str();
}

struct Outcome {
  PlanReport report;
  long outside = 0;
  double worst_margin_N = 0.0, lowest_N = 0.0, highest_N = 0.0;
  long checked = 0;
  std::string first_outside;
};

// Plans `job` on `machine` and checks its samples with the test frame's statics against its
// limits, 5 and 300 N.
Outcome plan_and_check(const Machine& machine, const fs::path& job) {
  const Machine checked_on = frame();
  TensionCheck check(cables(checked_on), 5.0, 300.0);
  Outcome outcome;
  outcome.report = plan_program(machine, job, {}, on_the_sheet(), check);
  outcome.outside = check.outside;
  outcome.worst_margin_N = check.worst_margin_N;
  outcome.lowest_N = check.lowest_N;
  outcome.highest_N = check.highest_N;
  outcome.checked = check.checked;
  outcome.first_outside = check.first_outside;
  return outcome;
}

void expect_bound_and_binding(const fs::path& job) {
  const Outcome limited = plan_and_check(frame(), job);
  EXPECT_EQ(limited.outside, 0) << limited.first_outside;
  EXPECT_GT(limited.checked, 1000);
  // The same job with the limits out of the way: its accelerations take the cables beyond them.
  const Outcome free = plan_and_check(frame_without_tensions(), job);
  EXPECT_GT(free.outside, 0);
  EXPECT_GT(limited.report.duration_s, free.report.duration_s);
  EXPECT_FALSE(limited.report.tension_limits.empty());
  std::printf(
      "  %s: %.3f s with tension limits, %.3f s without; tensions %.2f..%.2f N with "
      "(worst margin %.3f N), %.2f..%.2f N without (%ld of %ld samples outside "
      "[5, 300] N); %zu moves' acceleration lowered by tensions, %zu feeds\n",
      job.filename().string().c_str(), limited.report.duration_s, free.report.duration_s,
      limited.lowest_N, limited.highest_N, limited.worst_margin_N, free.lowest_N, free.highest_N,
      free.outside, free.checked, limited.report.tension_limits.size(),
      limited.report.feed_limits.size());
}

TEST(TensionLimitedPlan, NoSampleOfAnAggressiveJobLeavesTheTensionLimits) {
  const TempProgram job(aggressive_job());
  expect_bound_and_binding(job.path());
}

TEST(TensionLimitedPlan, NoSampleOfARealMaslowJobLeavesTheTensionLimits) {
  // GroundControl's calibration benchmark: marks across the whole 8 x 4 ft sheet.
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  expect_bound_and_binding(test::real_corpus() / "cam" / "maslow" /
                           "calibration-benchmark-test.nc");
}

}  // namespace
}  // namespace pkm::motion
