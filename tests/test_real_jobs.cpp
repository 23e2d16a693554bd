// The real-job table: real jobs of ../shared/gcode/real on the example machines described from
// real configurations, each placed with an origin, posted in every dialect; pkm verify must pass
// the joint program, and an independent forward-kinematics check (tests/real_job_check.hpp, at
// 1,000 points per block) must find nothing above the tolerance and agree with verify's maximum
// within 1 %. docs/real-jobs.md lists the table and what a run measured.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "pkm/post/joint_program.hpp"
#include "pkm/verify/joint_path.hpp"
#include "real_corpus.hpp"
#include "real_job_check.hpp"
#include "test_support.hpp"

namespace pkm::test {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = real_corpus();
constexpr double kToleranceMm = 0.01;

// A file of this process: test processes run side by side (ctest -j) and must not share one.
fs::path scratch(const std::string& name) {
  return fs::path(::testing::TempDir()) / ("pkm-real-" + std::to_string(::getpid()) + "-" + name);
}
constexpr int kPointsPerBlock = 1000;

struct RealJob {
  const char* job;       // relative to the corpus
  const char* machine;   // in examples/machines
  double origin[3];      // where the job's X0 Y0 Z0 sits on the machine, mm
  const char* revisits;  // how the job comes back to where it was ("" when it does not)
};

// Each job on a machine it suits, placed inside that machine's reach.
const RealJob kTable[] = {
    {"plotter/svg2gcode/smooth_curves_circular_interpolation.gcode",
     "linuxcnc-polargraph-2366.toml",
     {1000.0, -1200.0, 0.0},
     "closed curves"},
    {"plotter/dexarm-inkscape/vitruvianMan.gcode",
     "linuxcnc-polargraph-2366.toml",
     {1150.0, -1100.0, 0.0},
     "closed circles, pen-up travel back across drawn lines"},
    {"plotter/inkscape/mandala_cnc_0001.gcode",
     "linuxcnc-polargraph-2366.toml",
     {1130.0, -1200.0, 0.0},
     "closed contours, pen-up travel back across drawn lines"},
    {"plotter/inkscape/btc_laser_qr_unbt_0001.gcode",
     "linuxcnc-polargraph-2366.toml",
     {1130.0, -1200.0, 0.0},
     "hatching: lines 0.2 mm apart, travel between them"},
    {"cam/maslow/calibration-benchmark-test.nc",
     "maslow.toml",
     {1489.2, -1072.6, 0.0},
     "marks retraced, travel back through the sheet's centre"},
    {"cam/maslow/Dragon.nc",
     "maslow.toml",
     {1489.2, -1072.6, 0.0},
     "closed profile cut in several passes at the same place"},
    {"cam/bcnc/sample.gcode", "linuxcnc-ldelta.toml", {-15.0, -12.0, 0.0}, "closed contours"},
    {"cam/cncjs/jsdc.gcode", "linuxcnc-ldelta.toml", {-50.0, 30.0, 0.0}, "closed contours"},
    {"cam/pcb2gcode/milldrill.ngc",
     "linuxcnc-hexapod-sim.toml",
     {-65.0, 50.0, 480.0},
     "stacked helices: full circles stepping down in Z"},
    {"linuxcnc/tort.ngc",
     "matrix-mill.toml",
     {300.0, 200.0, -150.0},
     "helices in G17, G18 and G19 crossing each other"},
    {"linuxcnc-5axis/boat-xyzac.ngc",
     "linuxcnc-xyzac-trt.toml",
     {0.0, 0.0, 0.0},
     "passes back and forth over the hull"},
};

struct Case {
  const RealJob* row;
  post::Dialect dialect;
};

std::string case_name(const Case& c) {
  return test_name(fs::path(c.row->job).filename().string()) + "_on_" + test_name(c.row->machine) +
         "_" + std::string(post::dialect_name(c.dialect));
}

void PrintTo(const Case& c, std::ostream* out) {
  *out << case_name(c);
}

// Stock grbl reads X Y Z only: a machine with more joints is posted for LinuxCNC and Mach3.
bool grbl_takes(const machine::Machine& machine) {
  for (const machine::JointSpec& joint : machine.joints()) {
    if (std::string("XYZ").find(joint.axis_letter) == std::string::npos) return false;
  }
  return true;
}

std::vector<Case> cases() {
  std::vector<Case> all;
  for (const RealJob& row : kTable) {
    all.push_back({&row, post::Dialect::linuxcnc});
    all.push_back({&row, post::Dialect::mach3});
    if (grbl_takes(load_example(row.machine))) all.push_back({&row, post::Dialect::grbl});
  }
  return all;
}

geometry::Vector6d origin_of(const RealJob& row) {
  geometry::Vector6d origin = geometry::Vector6d::Zero();
  origin << row.origin[0], row.origin[1], row.origin[2], 0.0, 0.0, 0.0;
  return origin;
}

// Posts the job into `output` (the body pkm post writes after its header).
post::PostReport post_to_file(const machine::Machine& machine, const fs::path& job,
                              const post::PostOptions& options, const fs::path& output) {
  std::ofstream file(output);
  post::PostReport report = post::post_program(
      machine, job, {}, options, [&](const std::string& line) { file << line << '\n'; });
  return report;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class RealJobTable : public ::testing::TestWithParam<Case> {};

TEST_P(RealJobTable, PostedProgramIsVerifiedAndAgreesWithAnIndependentCheck) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const RealJob& row = *GetParam().row;
  const machine::Machine machine = load_example(row.machine);
  const fs::path job = readable_real_job(row.job);
  const fs::path joints = scratch(case_name(GetParam()) + ".ngc");
  post::PostOptions options;
  options.tolerance_mm = kToleranceMm;
  options.dialect = GetParam().dialect;
  options.origin = origin_of(row);

  auto clock = std::chrono::steady_clock::now();
  const post::PostReport posted = post_to_file(machine, job, options, joints);
  const double post_s = seconds_since(clock);
  clock = std::chrono::steady_clock::now();
  verify::VerifyOptions verify_options;
  verify_options.origin = options.origin;
  verify_options.tolerance_mm = kToleranceMm;
  const verify::VerifyReport verified =
      verify::verify_joint_program(machine, joints, job, verify_options);
  const double verify_s = seconds_since(clock);
  clock = std::chrono::steady_clock::now();
  const Eigen::Vector3d origin = options.origin.head<3>();
  const IndependentReport mine =
      check_independently(machine, programmed_path(job, origin, machine.home().position_mm),
                          joint_blocks(machine, joints), kPointsPerBlock, kToleranceMm);
  const double check_s = seconds_since(clock);

  std::printf(
      "REAL-JOB | %s | %s | %g %g %g | %s | %ld | %.6f | %.6f | post %.1f s, verify %.1f s, "
      "check %.1f s\n",
      row.job, row.machine, row.origin[0], row.origin[1], row.origin[2],
      post::dialect_name(options.dialect).data(), posted.blocks, verified.max_deviation_mm,
      mine.max_deviation_mm, post_s, verify_s, check_s);

  // The independent check follows the whole job and finds every point within the tolerance.
  EXPECT_EQ(mine.blocks, posted.blocks);
  EXPECT_EQ(mine.lost_at_line, 0) << "no place on the path ahead for the block at this line";
  EXPECT_TRUE(mine.reached_end) << "the joint program stops before the job's end";
  EXPECT_EQ(mine.points_over_tolerance, 0)
      << "worst " << mine.max_deviation_mm << " mm at line " << mine.max_deviation_line;
  EXPECT_LE(mine.max_deviation_mm, kToleranceMm);
  EXPECT_LE(mine.max_untraced_mm, 2.0 * kToleranceMm)
      << "a stretch of the job is not traced, at line " << mine.max_untraced_line;
  // verify passes it, and its maximum is the independent one within 1 %.
  EXPECT_LE(verified.max_deviation_mm, kToleranceMm)
      << "at line " << verified.max_deviation_joint_line << " of the joint program";
  EXPECT_TRUE(verified.passed()) << verified.position.count + verified.velocity.count
                                 << " joint violations, " << verified.pen.count
                                 << " pen stretches, covered " << verified.covered;
  EXPECT_NEAR(verified.max_deviation_mm, mine.max_deviation_mm, 0.01 * mine.max_deviation_mm);
  fs::remove(joints);
}

INSTANTIATE_TEST_SUITE_P(Real, RealJobTable, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& case_info) {
                           return case_name(case_info.param);
                         });

// CAMotics' raster of la_peinture (180,000 moves of 0.125 mm along rows, S on every one) on the
// polargraph for grbl: blocks spanning moves (docs/post.md, "Spanning moves") write 16 times
// fewer blocks than one covering per move, and the program verifies, the independent check (at
// 100 points per block, 11,000 blocks) agreeing.
TEST(RealJobTable, CamoticsRasterSpannedIsVerified) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const machine::Machine machine = load_example("linuxcnc-polargraph-2366.toml");
  const fs::path job = kCorpus / "plotter/camotics/la_peinture.gc";
  const fs::path joints = scratch("la_peinture.ngc");
  post::PostOptions options;
  options.tolerance_mm = kToleranceMm;
  options.dialect = post::Dialect::grbl;
  options.origin << 1130.0, -1200.0, 0.0, 0.0, 0.0, 0.0;
  options.span_moves = false;
  const post::PostReport per_move = post_to_file(machine, job, options, joints);
  options.span_moves = true;
  const post::PostReport spanned = post_to_file(machine, job, options, joints);
  EXPECT_EQ(spanned.moves, 180582);
  EXPECT_GE(per_move.moves, per_move.blocks - per_move.blocks / 50);  // about one block per move
  EXPECT_GT(per_move.blocks, 15 * spanned.blocks);
  EXPECT_LE(spanned.max_deviation_mm, kToleranceMm);
  verify::VerifyOptions verify_options;
  verify_options.origin = options.origin;
  verify_options.tolerance_mm = kToleranceMm;
  const verify::VerifyReport verified =
      verify::verify_joint_program(machine, joints, job, verify_options);
  EXPECT_TRUE(verified.passed()) << verified.position.count + verified.velocity.count
                                 << " joint violations, " << verified.pen.count
                                 << " pen stretches, covered " << verified.covered;
  EXPECT_LE(verified.max_deviation_mm, kToleranceMm);
  const IndependentReport mine = check_independently(
      machine, programmed_path(job, options.origin.head<3>(), machine.home().position_mm),
      joint_blocks(machine, joints), 100, kToleranceMm);
  EXPECT_EQ(mine.blocks, spanned.blocks);
  EXPECT_EQ(mine.lost_at_line, 0);
  EXPECT_TRUE(mine.reached_end);
  EXPECT_EQ(mine.points_over_tolerance, 0) << "worst " << mine.max_deviation_mm << " mm";
  EXPECT_LE(mine.max_untraced_mm, 2.0 * kToleranceMm) << "at line " << mine.max_untraced_line;
  std::printf(
      "REAL-JOB | plotter/camotics/la_peinture.gc | linuxcnc-polargraph-2366 | grbl | "
      "%ld blocks (per move %ld) | %.6f | %.6f\n",
      spanned.blocks, per_move.blocks, verified.max_deviation_mm, mine.max_deviation_mm);
  fs::remove(joints);
}

// The independent check itself, on a case computed by hand: a quarter circle of radius 10 mm
// cut as one joint-linear block on an identity machine is its chord, which misses the arc by the
// sagitta 10 (1 - cos 45 deg) = 2.928932 mm at its middle, both ways.
TEST(RealJobTable, TheIndependentCheckMeasuresAChordAgainstItsArc) {
  const machine::Machine machine = load_example("linuxcnc-xyzac-trt.toml");
  const fs::path job = scratch("quarter-circle.ngc");
  const fs::path joints = scratch("quarter-circle-chord.ngc");
  std::ofstream(job) << "G21 G90\nG0 X0 Y0 Z0\nG2 X10 Y-10 I0 J-10 F100\nM2\n";
  std::ofstream(joints) << "G21 G90 G94\nG0 X0 Y0 Z0 A0 C0\nG1 X10 Y-10 Z0 A0 C0 F100\nM2\n";
  const IndependentReport report =
      check_independently(machine, programmed_path(job, Eigen::Vector3d::Zero(), {0, 0, 100}),
                          joint_blocks(machine, joints), kPointsPerBlock, kToleranceMm);
  const double sagitta = 10.0 * (1.0 - std::cos(std::numbers::pi / 4.0));
  EXPECT_EQ(report.blocks, 2);
  EXPECT_TRUE(report.reached_end);
  EXPECT_NEAR(report.max_deviation_mm, sagitta, 1e-6);
  EXPECT_EQ(report.max_deviation_line, 3);
  EXPECT_NEAR(report.max_untraced_mm, sagitta, 1e-6);
  EXPECT_GT(report.points_over_tolerance, 900);
}

// A joint program that cuts a corner short: the corner (10, 0) it never visits is 5 sqrt 2 mm from
// its diagonal, whose middle is 5 mm from the programmed path.
TEST(RealJobTable, TheIndependentCheckFindsACornerCutShort) {
  const machine::Machine machine = load_example("linuxcnc-xyzac-trt.toml");
  const fs::path job = scratch("corner.ngc");
  const fs::path joints = scratch("corner-cut.ngc");
  std::ofstream(job) << "G21 G90\nG0 X0 Y0 Z0\nG1 X10 F100\nG1 Y10\nM2\n";
  std::ofstream(joints) << "G21 G90 G94\nG0 X0 Y0 Z0 A0 C0\nG1 X10 Y10 Z0 A0 C0 F100\nM2\n";
  const IndependentReport report =
      check_independently(machine, programmed_path(job, Eigen::Vector3d::Zero(), {0, 0, 100}),
                          joint_blocks(machine, joints), kPointsPerBlock, kToleranceMm);
  EXPECT_TRUE(report.reached_end);
  EXPECT_NEAR(report.max_deviation_mm, 5.0, 1e-9);
  EXPECT_NEAR(report.max_untraced_mm, 5.0 * std::sqrt(2.0), 1e-9);
  EXPECT_EQ(report.max_untraced_line, 3);
}

// A joint program cut short, or empty, does not reach the job's end.
TEST(RealJobTable, TheIndependentCheckSeesATruncatedProgram) {
  const machine::Machine machine = load_example("linuxcnc-xyzac-trt.toml");
  const fs::path job = scratch("square.ngc");
  const fs::path joints = scratch("square-cut-short.ngc");
  const fs::path empty = scratch("square-empty.ngc");
  std::ofstream(job) << "G21 G90\nG0 X0 Y0 Z0\nG1 X10 F100\nG1 Y10\nG1 X0\nG1 Y0\nM2\n";
  std::ofstream(joints) << "G21 G90 G94\nG0 X0 Y0 Z0 A0 C0\nG1 X10 Y0 Z0 A0 C0 F100\nM2\n";
  std::ofstream(empty) << "G21 G90 G94\nM2\n";
  const std::vector<PathMove> path = programmed_path(job, Eigen::Vector3d::Zero(), {0, 0, 100});
  const IndependentReport cut_short = check_independently(
      machine, path, joint_blocks(machine, joints), kPointsPerBlock, kToleranceMm);
  EXPECT_FALSE(cut_short.reached_end);
  EXPECT_NEAR(cut_short.max_deviation_mm, 0.0, 1e-9);  // what it does trace is right
  const IndependentReport nothing = check_independently(machine, path, joint_blocks(machine, empty),
                                                        kPointsPerBlock, kToleranceMm);
  EXPECT_EQ(nothing.blocks, 0);
  EXPECT_FALSE(nothing.reached_end);
}

// Pen commands that move an axis no joint uses (the 2366 polargraph's servo on Z) are not blocks.
TEST(RealJobTable, PenServoMovesAreNotJointBlocks) {
  const machine::Machine machine = load_example("linuxcnc-polargraph-2366.toml");
  const fs::path joints = scratch("pen-servo.ngc");
  std::ofstream(joints) << "G21 G90\nG0 X1300 Y1250\nG0 Z90\nG1 X1310 Y1240 F600\nG0 Z0\nM2\n";
  const std::vector<JointBlock> blocks = joint_blocks(machine, joints);
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[1].line, 4);
  EXPECT_DOUBLE_EQ(blocks[1].joints[0], 1310.0);
  EXPECT_DOUBLE_EQ(blocks[1].joints[1], 1240.0);
}

// Moves the end of the joint block at `line` by `offset_mm` across the path (in the XY plane):
// the block's end joints are replaced by those of the displaced tool tip.
void displace_block_end(const machine::Machine& machine, const fs::path& program, int line,
                        double offset_mm) {
  std::ifstream in(program);
  std::vector<std::string> lines;
  for (std::string text; std::getline(in, text);) lines.push_back(text);
  const std::vector<JointBlock> blocks = joint_blocks(machine, program);
  std::size_t k = 0;
  while (blocks[k].line != line) ++k;
  geometry::Pose before = machine.home(), after = machine.home();
  ASSERT_TRUE(machine.forward(blocks[k - 1].joints, before).ok());
  ASSERT_TRUE(machine.forward(blocks[k].joints, after).ok());
  // Across the block's chord: in the XY plane where it can be (a plotter has no other).
  const Eigen::Vector3d along = (after.position_mm - before.position_mm).normalized();
  Eigen::Vector3d across = along.cross(Eigen::Vector3d::UnitZ());
  if (across.norm() < 0.1) across = along.cross(Eigen::Vector3d::UnitX());
  after.position_mm += offset_mm * across.normalized();
  kinematics::JointVector displaced;
  ASSERT_TRUE(machine.inverse(after, displaced).ok());
  std::istringstream words(lines[static_cast<std::size_t>(line - 1)]);
  std::string rewritten;
  for (std::string word; words >> word;) {
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const machine::JointSpec& joint = machine.joints()[i];
      if (word[0] != joint.axis_letter) continue;
      char number[48];
      std::snprintf(number, sizeof number, "%c%.5f", joint.axis_letter,
                    joint.to_interface(displaced[static_cast<int>(i)]));
      word = number;
    }
    rewritten += (rewritten.empty() ? "" : " ") + word;
  }
  lines[static_cast<std::size_t>(line - 1)] = rewritten;
  std::ofstream out(program);
  for (const std::string& text : lines) out << text << '\n';
}

// A joint program off by 0.05 mm in one block is caught at that block's line, by verify and by
// the independent check alike. The block's end is moved, so the next block starts off the path
// by as much: the first of the two is the one to report. The block is the first from the middle
// of the program that ends inside a straight stretch (it and the next at least 0.5 mm long, in
// line), so that the moved end is 0.05 mm from the path.
void expect_block_off_caught_at_its_line(const RealJob& row) {
  const machine::Machine machine = load_example(row.machine);
  const fs::path job = readable_real_job(row.job);
  const fs::path joints = scratch("real-job-off-by-0.05.ngc");
  post::PostOptions options;
  options.tolerance_mm = kToleranceMm;
  options.origin = origin_of(row);
  post_to_file(machine, job, options, joints);
  const std::vector<JointBlock> blocks = joint_blocks(machine, joints);
  ASSERT_GT(blocks.size(), 100u);
  std::size_t k = blocks.size() / 2;
  for (;; ++k) {
    ASSERT_LT(k + 2, blocks.size());
    geometry::Pose p0 = machine.home(), p1 = machine.home(), p2 = machine.home();
    ASSERT_TRUE(machine.forward(blocks[k - 1].joints, p0).ok());
    ASSERT_TRUE(machine.forward(blocks[k].joints, p1).ok());
    ASSERT_TRUE(machine.forward(blocks[k + 1].joints, p2).ok());
    const Eigen::Vector3d in = p1.position_mm - p0.position_mm;
    const Eigen::Vector3d out = p2.position_mm - p1.position_mm;
    if (in.norm() >= 0.5 && out.norm() >= 0.5 && in.normalized().dot(out.normalized()) > 0.9999) {
      break;
    }
  }
  const int line = blocks[k].line;
  displace_block_end(machine, joints, line, 0.05);

  verify::VerifyOptions verify_options;
  verify_options.origin = options.origin;
  verify_options.tolerance_mm = kToleranceMm;
  const verify::VerifyReport verified =
      verify::verify_joint_program(machine, joints, job, verify_options);
  EXPECT_NEAR(verified.max_deviation_mm, 0.05, 0.002);
  EXPECT_EQ(verified.max_deviation_joint_line, line);
  const IndependentReport mine = check_independently(
      machine, programmed_path(job, options.origin.head<3>(), machine.home().position_mm),
      joint_blocks(machine, joints), kPointsPerBlock, kToleranceMm);
  EXPECT_NEAR(mine.max_deviation_mm, 0.05, 0.002);
  EXPECT_EQ(mine.max_deviation_line, line);
  EXPECT_TRUE(mine.reached_end);
  fs::remove(joints);
}

TEST(RealJobTable, ABlockOffByFiveHundredthsIsCaughtAtItsLineOnThePolargraph) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  expect_block_off_caught_at_its_line(kTable[0]);  // svg2gcode's curves
}

TEST(RealJobTable, ABlockOffByFiveHundredthsIsCaughtAtItsLineOnTheDelta) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  expect_block_off_caught_at_its_line(kTable[5]);  // bCNC's sample
}

}  // namespace
}  // namespace pkm::test
