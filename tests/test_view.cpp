// The HTML views' data: decimation that keeps peaks, a path thinned within its spacing, moments
// evenly spread, the machine drawn to scale (legs, struts and cables as long as the joints say),
// and the page self-contained with the report's numbers inside. The pages in a browser:
// tests/browser/test_views.py.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "pkm/io/json_reports.hpp"
#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/rotary_delta.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/view/decimation.hpp"
#include "pkm/view/html_page.hpp"
#include "pkm/view/machine_drawing.hpp"
#include "pkm/view/recorders.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

TEST(MinMaxBuckets, KeepEverySamplesPeakAndHalveWhenFull) {
  view::MinMaxBuckets buckets(1, 4);
  // 100 samples of a flat line with one spike (sample 37) and one dip (sample 81).
  for (int i = 0; i < 100; ++i) {
    const double value = i == 37 ? 9.0 : i == 81 ? -4.0 : 1.0;
    const double values[] = {value};
    buckets.add(i * 0.1, values);
  }
  // 4 to 8 buckets remain; full ones hold a power of two samples: 16 each (7 buckets, the last 4).
  EXPECT_EQ(buckets.samples_per_bucket(), 16u);
  ASSERT_EQ(buckets.size(), 7u);
  double top = -1e9, bottom = 1e9;
  for (std::size_t b = 0; b < buckets.size(); ++b) {
    top = std::max(top, buckets.max(0)[b]);
    bottom = std::min(bottom, buckets.min(0)[b]);
  }
  EXPECT_EQ(top, 9.0);
  EXPECT_EQ(bottom, -4.0);
  EXPECT_EQ(buckets.max(0)[37 / 16], 9.0);  // in the bucket of its sample
  EXPECT_EQ(buckets.min(0)[81 / 16], -4.0);
  EXPECT_DOUBLE_EQ(buckets.x_first()[2], 3.2);
  EXPECT_DOUBLE_EQ(buckets.x_last()[2], 4.7);
  EXPECT_DOUBLE_EQ(buckets.x_last().back(), 9.9);
}

TEST(MinMaxBuckets, NaNIsSkippedAndABucketOfNaNStaysNaN) {
  view::MinMaxBuckets buckets(2, 1);  // two buckets at most, then pairs merge
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double first[] = {nan, 2.0}, second[] = {3.0, nan}, third[] = {nan, nan};
  buckets.add(0.0, first);
  buckets.add(1.0, second);
  buckets.add(2.0, third);  // merges the first two, starts a bucket of its own
  ASSERT_EQ(buckets.size(), 2u);
  EXPECT_EQ(buckets.min(0)[0], 3.0);
  EXPECT_EQ(buckets.max(1)[0], 2.0);
  EXPECT_TRUE(std::isnan(buckets.min(0)[1]));
  EXPECT_TRUE(std::isnan(buckets.max(1)[1]));
}

TEST(PathThinner, KeepsPointsASpacingApartAndEveryNewLine) {
  view::PathThinner path(1.0, 1000);
  // A straight line at 0.1 mm steps on line 1, then a corner on line 2.
  for (int i = 0; i <= 50; ++i) path.add(i, Eigen::Vector3d(0.1 * i, 0, 0), i == 33 ? 7.0 : 1.0, 1);
  path.add(51, Eigen::Vector3d(5.0, 0.05, 0), 1.0, 2);
  path.finish();
  const auto& points = path.points();
  // x = 0, 1.0, 2.0, ... 5.0 (line 1, 6 points), the corner (new line): 7 points.
  ASSERT_EQ(points.size(), 7u);
  for (std::size_t k = 1; k + 1 < points.size(); ++k) {
    EXPECT_NEAR((points[k].position - points[k - 1].position).norm(), 1.0, 1e-9);
  }
  EXPECT_EQ(points[4].colour, 7.0);  // sample 33 (x 3.3) belongs to the point at x 4.0
  EXPECT_EQ(points[3].colour, 1.0);
}

TEST(PathThinner, DoublesItsSpacingPastTheCap) {
  view::PathThinner path(0.5, 20);
  for (int i = 0; i <= 1000; ++i) path.add(i, Eigen::Vector3d(0.5 * i, 0, 0), i, 1);
  path.finish();
  EXPECT_LE(path.points().size(), 21u);
  EXPECT_GE(path.spacing_mm(), 500.0 / 20.0);
  EXPECT_EQ(path.points().back().position.x(), 500.0);  // the end stays
  EXPECT_EQ(path.points().back().colour, 1000.0);       // with the largest colour since
}

TEST(MomentSampler, KeepsEvenlySpacedMomentsAndTheLast) {
  view::MomentSampler moments(10);
  for (int i = 0; i < 1001; ++i) moments.add(i, geometry::Pose{}, kinematics::JointVector::Zero(1));
  moments.finish();
  const auto& kept = moments.moments();
  ASSERT_GE(kept.size(), 10u);
  ASSERT_LE(kept.size(), 21u);
  const double step = kept[1].t - kept[0].t;
  for (std::size_t k = 1; k + 1 < kept.size(); ++k) EXPECT_EQ(kept[k].t - kept[k - 1].t, step);
  EXPECT_EQ(kept.front().t, 0.0);
  EXPECT_EQ(kept.back().t, 1000.0);
}

double length_of(const view::Segment& segment) {
  return (segment.to - segment.from).norm();
}

// The drawn legs are as long as inverse kinematics makes them, at random reachable poses.
TEST(MachineDrawing, HexapodLegsAreAsLongAsTheJointsSay) {
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  const auto& hexapod = dynamic_cast<const kinematics::HexapodKinematics&>(machine.kinematics());
  std::mt19937_64 rng(7);
  const std::vector<geometry::Pose> poses = test::sample_reachable_poses(machine, 20, rng, 15.0);
  ASSERT_EQ(poses.size(), 20u);
  for (const geometry::Pose& pose : poses) {
    kinematics::JointVector joints;
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    int leg = 0;
    for (const view::Segment& segment : view::moving_parts(machine, pose, joints)) {
      if (segment.part != view::Part::link) continue;
      EXPECT_NEAR(length_of(segment) + hexapod.geometry().leg_offset_mm[leg], joints[leg], 1e-9);
      ++leg;
    }
    EXPECT_EQ(leg, 6);
  }
  EXPECT_FALSE(view::drawn_planar(machine));
}

TEST(MachineDrawing, GlideStrutsKeepTheirLengthAndCarriagesSitOnTheRails) {
  const machine::Machine machine = test::load_example("triaglide.toml");
  const auto& glide = dynamic_cast<const kinematics::GlideKinematics&>(machine.kinematics());
  std::mt19937_64 rng(11);
  const std::vector<geometry::Pose> poses = test::sample_reachable_poses(machine, 20, rng);
  ASSERT_EQ(poses.size(), 20u);
  for (const geometry::Pose& pose : poses) {
    kinematics::JointVector joints;
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    std::size_t rail = 0;
    for (const view::Segment& segment : view::moving_parts(machine, pose, joints)) {
      if (segment.part != view::Part::link) continue;
      const kinematics::GlideRail& r = glide.rails()[rail];
      EXPECT_NEAR(length_of(segment), r.strut_mm, 1e-9);
      EXPECT_NEAR(
          (segment.from - (r.origin_mm + joints[static_cast<int>(rail)] * r.direction)).norm(), 0.0,
          1e-9);
      ++rail;
    }
    EXPECT_EQ(rail, 3u);
  }
}

// A rotary delta's arms and forearms keep their lengths: the elbows are where the joints put them.
TEST(MachineDrawing, RotaryDeltaArmsAndForearmsKeepTheirLengths) {
  const machine::Machine machine = test::load_example("linuxcnc-rdelta.toml");
  const auto& delta = dynamic_cast<const kinematics::RotaryDeltaKinematics&>(machine.kinematics());
  std::mt19937_64 rng(5);
  const std::vector<geometry::Pose> poses = test::sample_reachable_poses(machine, 20, rng);
  ASSERT_EQ(poses.size(), 20u);
  for (const geometry::Pose& pose : poses) {
    kinematics::JointVector joints;
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    int link = 0;
    for (const view::Segment& segment : view::moving_parts(machine, pose, joints)) {
      if (segment.part != view::Part::link) continue;
      EXPECT_NEAR(
          length_of(segment),
          link % 2 == 0 ? delta.geometry().arm_length_mm : delta.geometry().forearm_length_mm,
          1e-6);
      ++link;
    }
    EXPECT_EQ(link, 6);
  }
}

// Hektor's ideal cables run from the anchors to the pen: as long as the joints, less offsets.
TEST(MachineDrawing, IdealCablesAreAsLongAsTheJoints) {
  const machine::Machine machine = test::load_example("hektor.toml");
  const auto& cables =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics());
  EXPECT_TRUE(view::drawn_planar(machine));
  const geometry::Pose pose = geometry::Pose::from_mm_deg(40.0, -50.0, 0.0);
  kinematics::JointVector joints;
  ASSERT_TRUE(machine.inverse(pose, joints).ok());
  int cable = 0;
  for (const view::Segment& segment : view::moving_parts(machine, pose, joints)) {
    if (segment.part != view::Part::link) continue;
    EXPECT_NEAR(length_of(segment) + cables.geometry().cable_offsets_mm[cable], joints[cable],
                1e-9);
    ++cable;
  }
  EXPECT_EQ(cable, 2);
}

// The job's outline for post's and verify's pages: along the job from home, its arc length the
// job's (verify's job_length_mm of this job is 97.2383047 mm), ending at the job's end.
TEST(FeedLimitText, SaysTheLimitAndItsNumbersInTheMachineFilesUnits) {
  // LinuxCNC's inch hexapod: F10 (in/min) lowered to F5 by leg2's velocity, which at F10 would
  // be 39.6 in/s against the 19.8 in/s (99 % of 20) a move may use: every number in inches, the
  // share of each limit the planner gave the move said as it is (the jerk-limited planner's).
  const machine::Machine hexapod = test::load_example("linuxcnc-hexapod-sim.toml");
  motion::FeedLimit limit;
  limit.line = 3;
  limit.joint = 2;
  limit.programmed_mm_per_s = 10.0 * 25.4 / 60.0;
  limit.allowed_mm_per_s = 5.0 * 25.4 / 60.0;
  limit.bound = motion::JointBound::velocity;
  limit.needed_at_programmed = 39.6 * 25.4;
  limit.usable = 0.99 * 20.0 * 25.4;
  EXPECT_EQ(io::feed_limit_text(hexapod, limit),
            "F10.0 lowered to F5.0: joint leg2's velocity would be 39.6 in/s at F10.0, over the "
            "19.8 in/s it may use (99.0 % of max_velocity 20.0)");
  // The same on an arc of 0.5 in: the curve, and what v^2/r within half of max_acceleration
  // (200 in/s^2) allows there, sqrt(100 * 0.5) in/s = F424.3.
  limit.bound = motion::JointBound::acceleration;
  limit.needed_at_programmed = 250.0 * 25.4;
  limit.usable = 0.5 * 0.8 * 200.0 * 25.4;
  limit.curve = motion::CurveKind::arc;
  limit.radius_mm = 0.5 * 25.4;
  limit.curve_acceleration_mm_per_s2 = 100.0 * 25.4;
  limit.curve_allowed_mm_per_s = std::sqrt(100.0 * 0.5) * 25.4;
  EXPECT_EQ(io::feed_limit_text(hexapod, limit),
            "F10.0 lowered to F5.0 on the arc (radius 0.5000 in): joint leg2's acceleration would "
            "be 250.0 in/s^2 at F10.0, over the 80.0 in/s^2 it may use on a bend (40.0 % of "
            "max_acceleration 200.0); the tool's own v^2/r allows F424.3 (within 100.0 in/s^2, "
            "50.0 % of max_acceleration 200.0)");
}

TEST(FeedLimitText, ThePlanReportCarriesTheBoundTheCurveAndTheReason) {
  // The first square of the real corpus' vitruvianMan on the Makelangelo with its joints' 1500
  // mm/s^2 lowered to 1000: its corner after line 7 is a G64 blend whose speed the right joint's
  // acceleration sets (tests/cli/units.cmake).
  const machine::Machine plotter = test::load_example_changed(
      "makelangelo.toml", "max_acceleration = 1500.0", "max_acceleration = 1000.0");
  motion::PlanOptions options;
  options.estimate_only = true;
  struct : motion::SampleSink {
    void write(const motion::Sample&) override {}
  } none;
  const motion::PlanReport report = motion::plan_program(
      plotter, std::string(PKM_SOURCE_DIR) + "/tests/data/vitruvian-first-square.ngc", {}, options,
      none);
  const nlohmann::json json = io::plan_report_json(plotter, report, "square.ngc", 0.001, true);
  const nlohmann::json& limit = json["feed_limited_by_joints"].at(0);
  EXPECT_EQ(limit["line"], 8);
  EXPECT_EQ(limit["bound"]["limit"], "acceleration");
  EXPECT_EQ(limit["bound"]["unit"], "mm/s^2");
  EXPECT_DOUBLE_EQ(limit["bound"]["usable"].get<double>(), 999.0);  // 99.9 %
  EXPECT_GT(limit["bound"]["at_programmed_feed"].get<double>(), 999.0);
  EXPECT_EQ(limit["curve"]["kind"], "blend");
  EXPECT_EQ(limit["curve"]["after_line"], 7);
  EXPECT_NEAR(limit["curve"]["radius_mm"].get<double>(), 0.034142, 3e-4);
  EXPECT_EQ(limit["reason"], io::feed_limit_text(plotter, report.feed_limits.at(0)));
}

TEST(JobOutline, FollowsTheJobFromHomeToItsEnd) {
  const machine::Machine machine = test::load_example("hektor.toml");
  geometry::Vector6d origin = geometry::Vector6d::Zero();
  origin.head<2>() << 40.0, -80.0;
  const std::vector<view::PathPoint> outline = view::job_outline(
      machine, PKM_SOURCE_DIR "/tests/data/square.ngc", gcode::InterpreterOptions{}, origin);
  ASSERT_GE(outline.size(), 6u);
  EXPECT_NEAR((outline.front().position - Eigen::Vector3d(50.0, -50.0, 0.0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((outline.back().position - Eigen::Vector3d(40.0, -80.0, 0.0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(outline.back().t, std::hypot(10.0, 30.0) + std::hypot(5.0, 20.0) + 10 + 20 + 15,
              1e-9);
  for (std::size_t k = 1; k < outline.size(); ++k) EXPECT_GE(outline[k].t, outline[k - 1].t);
}

// A Maslow's sled, off the centre line, is drawn tilted as its balance tilts it, and stays rigid.
TEST(MachineDrawing, SledTiltsAsItsBalanceSays) {
  const machine::Machine machine = test::load_example("maslow-frame.toml");
  const auto& cables =
      dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics());
  const geometry::Pose pose = geometry::Pose::from_mm_deg(900.0, -700.0, 5.0);
  kinematics::JointVector joints;
  ASSERT_TRUE(machine.inverse(pose, joints).ok());
  kinematics::CableStatics statics;
  ASSERT_TRUE(cables.statics(pose, Eigen::Vector2d::Zero(), statics).ok());
  ASSERT_GT(std::abs(statics.tilt_rad), 1e-3);  // off the centre line the sled tilts
  const std::vector<view::Segment> parts = view::moving_parts(machine, pose, joints);
  const auto sled = std::find_if(parts.begin(), parts.end(), [](const view::Segment& segment) {
    return segment.part == view::Part::platform;
  });
  ASSERT_NE(sled, parts.end());
  const Eigen::Vector3d across = sled->to - sled->from;  // attach 0 to attach 1: 310 mm along x
  EXPECT_NEAR(across.norm(), 310.0, 1e-9);
  EXPECT_NEAR(std::atan2(across.y(), across.x()), statics.tilt_rad, 1e-12);
}

// A plan's page: one file with the report's numbers and no reference to anything outside it.
TEST(PlanPage, IsSelfContainedAndCarriesTheReport) {
  const machine::Machine machine = test::load_example("hektor.toml");
  test::TempProgram job("G21 G90 F1200\nG1 X20 Y-60\nG1 X80 Y-60\nM2\n");
  view::PlanRecorder recorder(machine);
  const motion::PlanReport report =
      motion::plan_program(machine, job.path(), {}, motion::PlanOptions{}, recorder);
  recorder.finish();
  const nlohmann::json json = {{"duration_s", report.duration_s},
                               {"path_length_mm", report.path_length_mm},
                               {"samples", report.samples},
                               {"joints", nlohmann::json::array()},
                               {"feed_limited_by_joints", nlohmann::json::array()},
                               {"acceleration_limited_by_tensions", nlohmann::json::array()},
                               {"program", "</script><script>alert(1)</script>"}};
  const std::string page = view::plan_page(json, recorder, "a <b> title");
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_EQ(page.find(" src="), std::string::npos);
  EXPECT_EQ(page.find("@PKM_"), std::string::npos);
  EXPECT_EQ(page.find("<script><script>alert"), std::string::npos);  // '<' escaped in the data
  EXPECT_NE(page.find("a &lt;b&gt; title"), std::string::npos);
  const std::size_t start = page.find("type=\"application/json\">") + 24;
  const nlohmann::json data =
      nlohmann::json::parse(page.substr(start, page.find("</script>", start) - start));
  EXPECT_EQ(data["report"], json);
  EXPECT_EQ(data["summary"][0]["value"].get<double>(), report.duration_s);
  EXPECT_EQ(data["summary"][2]["value"].get<long>(), report.samples);
  EXPECT_EQ(data["path"]["t"].back().get<double>(), data["drawing"]["t"].back().get<double>());
  EXPECT_TRUE(data["planar"].get<bool>());
}

}  // namespace
}  // namespace pkm

namespace pkm {
namespace {

nlohmann::json page_data(const std::string& page) {
  const std::size_t start = page.find("type=\"application/json\">") + 24;
  return nlohmann::json::parse(page.substr(start, page.find("</script>", start) - start));
}

const nlohmann::json* summary_row(const nlohmann::json& data, const std::string& key) {
  for (const nlohmann::json& row : data["summary"]) {
    if (row["key"] == key) return &row;
  }
  return nullptr;
}

// A plotter's page: the speed is the pen's over the paper (its Z is the pen channel: lifting
// 5 mm in one period is no 5000 mm/s), pen-up travel is told from drawing, the pen row is there;
// and a slowed move without a sample of its own (line 3, a comment) is still marked, at the
// next line's first sample.
TEST(PlanPage, PlotterSpeedIsOverThePaperAndThePenIsShown) {
  const machine::Machine machine = test::load_example("pen-plotter.toml");
  test::TempProgram job(
      "G21 G90\nG0 Z5 X750 Y-700\n(nothing moves here)\nG0 X760\nG1 Z-1 F600\nG1 X800 F1200\n"
      "G0 Z5\nG0 X750\nM2\n");
  view::PlanRecorder recorder(machine);
  const motion::PlanReport report =
      motion::plan_program(machine, job.path(), {}, motion::PlanOptions{}, recorder);
  recorder.finish();
  const nlohmann::json slowed = {{"line", 3},
                                 {"programmed_mm_per_min", 1200.0},
                                 {"allowed_mm_per_min", 600.0},
                                 {"joint", "left"},
                                 {"cause", "joint"}};
  const nlohmann::json json = {{"duration_s", report.duration_s},
                               {"path_length_mm", report.path_length_mm},
                               {"samples", report.samples},
                               {"pen_changes", report.pen_changes},
                               {"joints", nlohmann::json::array()},
                               {"feed_limited_by_joints", nlohmann::json::array({slowed})},
                               {"acceleration_limited_by_tensions", nlohmann::json::array()}};
  const nlohmann::json data = page_data(view::plan_page(json, recorder, "plotter"));
  double fastest = 0.0;
  for (const nlohmann::json& c : data["path"]["c"]) fastest = std::max(fastest, c.get<double>());
  EXPECT_LE(fastest, 100.0 + 1e-6);  // the machine's max_feed, 6000 mm/min
  EXPECT_GT(fastest, 19.0);          // G1 X800 F1200 reaches 20 mm/s
  const nlohmann::json& pen = data["path"]["p"];
  EXPECT_NE(std::find(pen.begin(), pen.end(), 0), pen.end());
  EXPECT_NE(std::find(pen.begin(), pen.end(), 1), pen.end());
  EXPECT_EQ(report.pen_changes, 2);
  ASSERT_NE(summary_row(data, "pen_changes"), nullptr);
  EXPECT_EQ((*summary_row(data, "pen_changes"))["value"], 2);
  EXPECT_EQ(summary_row(data, "pen_never_down"), nullptr);
  ASSERT_EQ(data["marks"].size(), 1u);
  EXPECT_NEAR(data["marks"][0]["t"].get<double>(), recorder.line_starts().at(4).t, 1e-5);
  EXPECT_EQ(data["marks"][0]["label"], "line 3: F1200 slowed to F600 by joint left");
  // With the report's reason (feed_limit_text) the mark says the cause, not just a joint.
  nlohmann::json reasoned = json;
  reasoned["feed_limited_by_joints"][0]["reason"] =
      "F1200.0 lowered to F600.0: joint left's velocity would be 300.0 mm/s at F1200.0, over the "
      "148.5 mm/s it may use (99 % of max_velocity 150.0)";
  const nlohmann::json with_reason = page_data(view::plan_page(reasoned, recorder, "plotter"));
  EXPECT_EQ(with_reason["marks"][0]["label"],
            "line 3: F1200.0 lowered to F600.0: joint left's velocity would be 300.0 mm/s at "
            "F1200.0, over the 148.5 mm/s it may use (99 % of max_velocity 150.0)");
}

// A plotter job that never lowers its pen draws nothing: the page says so in words.
TEST(PlanPage, SaysWhenThePenNeverGoesDown) {
  const machine::Machine machine = test::load_example("pen-plotter.toml");
  test::TempProgram job("G21 G90\nG0 Z5\nG0 X760 Y-700\nG1 X800 F1200\nM2\n");
  view::PlanRecorder recorder(machine);
  const motion::PlanReport report =
      motion::plan_program(machine, job.path(), {}, motion::PlanOptions{}, recorder);
  recorder.finish();
  const nlohmann::json json = {{"duration_s", report.duration_s},
                               {"path_length_mm", report.path_length_mm},
                               {"samples", report.samples},
                               {"pen_changes", report.pen_changes},
                               {"joints", nlohmann::json::array()},
                               {"feed_limited_by_joints", nlohmann::json::array()},
                               {"acceleration_limited_by_tensions", nlohmann::json::array()}};
  const nlohmann::json data = page_data(view::plan_page(json, recorder, "plotter"));
  const nlohmann::json* never = summary_row(data, "pen_never_down");
  ASSERT_NE(never, nullptr);
  EXPECT_EQ((*never)["value"], "never down: this job draws nothing");
  const nlohmann::json& pen = data["path"]["p"];
  EXPECT_EQ(std::find(pen.begin(), pen.end(), 1), pen.end());  // every point travelled pen up
}

// A failing verification's page: the deviations listed worst first (not the first few), each
// with its joint-program and job line; the reason in a sentence; one block still drawn from home.
TEST(VerifyPage, ListsTheWorstFirstAndSaysWhy) {
  const machine::Machine machine = test::load_example("hektor.toml");
  view::BlockRecorder recorder(machine);
  const double deviations[] = {0.5, 3.0, 0.02, 2.0};
  for (int i = 0; i < 4; ++i) {
    verify::VerifiedBlock block;
    block.line = 10 + i;
    block.job_line = 100 + i;
    block.end_pose = machine.home();
    block.end_pose.position_mm.x() += 10.0 * (i + 1);
    ASSERT_TRUE(machine.inverse(block.end_pose, block.joints).ok());
    block.deviation_mm = deviations[i];
    recorder.add(block);
  }
  recorder.finish();
  const nlohmann::json none = {{"count", 0}, {"first", nlohmann::json::array()}};
  const nlohmann::json report = {
      {"blocks", 4},
      {"tolerance_mm", 0.1},
      {"max_deviation_mm", 3.0},
      {"rms_deviation_mm", 1.0},
      {"max_deviation_joint_line", 11},
      {"max_deviation_job_line", 101},
      {"coverage",
       {{"complete", false},
        {"job_length_mm", 500.0},
        {"traced_mm", 40.0},
        {"stopped_at_job_line", 104},
        {"stopped_at_joint_line", 13}}},
      {"violations",
       {{"deviation", {{"count", 3}, {"first", nlohmann::json::array()}}},
        {"position", none},
        {"velocity", none},
        {"pen", none}}},
      {"pen_downs", {{"joint_program", 0}, {"job", 0}}},
      {"passed", false}};
  const nlohmann::json data =
      page_data(view::blocks_page("verify", report, recorder, 0.1, {}, "verify"));
  ASSERT_EQ(data["marks"].size(), 3u);  // the 0.02 mm block is within the tolerance
  EXPECT_EQ(data["marks"][0]["label"],
            "deviation 3 mm (tolerance 0.1 mm) at joint-program line 11, job line 101");
  EXPECT_NE(data["marks"][1]["label"].get<std::string>().find("deviation 2 mm"), std::string::npos);
  EXPECT_NE(data["marks"][2]["label"].get<std::string>().find("deviation 0.5 mm"),
            std::string::npos);
  EXPECT_EQ(data["marks_note"], "deviation: all 3 (worst first)");
  const std::string verdict = data["verdict"];
  EXPECT_NE(verdict.find("ends at its line 13: it traces the job only to job line 104 "
                         "(40.0 of 500.0 mm)"),
            std::string::npos);
  EXPECT_NE(verdict.find("3 blocks stray beyond the tolerance 0.1 mm"), std::string::npos);
  // Home and four block ends: the path starts where the program does.
  ASSERT_EQ(data["path"]["x"].size(), 5u);
  EXPECT_EQ(data["path"]["x"][0].get<double>(), machine.home().position_mm.x());
  EXPECT_EQ(data["path"]["t"][1].get<double>(), 10.0);
}

}  // namespace
}  // namespace pkm
