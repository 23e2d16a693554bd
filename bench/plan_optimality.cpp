// Issue 29's table: on its five jobs, the planner's motion time (the pieces' durations, without
// dwells or pen delays) against the time-optimal reference over the same path
// (tests/time_optimal_reference.hpp), their ratio, the planner's CPU time and the reference's;
// then the median ratio. A plain program: the reference takes seconds, not a benchmark loop.
//   bench_plan_optimality [grid_step_mm [runs|more|runs,more]] [--jerk mm_per_s3]
//   (default 0.05 mm; with `runs`, each job's runs from rest to rest where the planner is furthest
//   below and above the reference; with `more`, the real-job table's other jobs too; with
//   --jerk, the jerk-limited planner with that tool jerk, against the same reference: without a
//   jerk limit, its time is a lower bound of the jerk-limited optimum, so the ratio bounds how far
//   the jerk-limited plan is from that optimum from above)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "real_job_copy.hpp"
#include "time_optimal_reference.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kSource = PKM_SOURCE_DIR;

struct Job {
  const char* name;
  fs::path program;
  const char* machine;  // in examples/machines
  double origin[3];     // mm
};

std::vector<Job> issue_jobs() {
  const fs::path corpus = kSource.parent_path() / "shared" / "gcode" / "real";
  const auto real = [&](const std::string& relative) {
    return fs::exists(corpus / relative) ? pkm::test::readable_real_job(corpus, relative)
                                         : corpus / relative;
  };
  return {
      {"sphere", kSource / "examples" / "jobs" / "sphere.ngc", "hexapod-bit.toml", {0, 0, 0}},
      {"vitruvianMan",
       real("plotter/dexarm-inkscape/vitruvianMan.gcode"),
       "wall-plotter.toml",
       {750.0, -1100.0, 0.0}},
      {"calibration-benchmark",
       real("cam/maslow/calibration-benchmark-test.nc"),
       "maslow-frame.toml",
       {1489.2, -1072.6, 0.0}},
      {"tiny_cat_outline",
       real("cam/camotics/tiny_cat_outline.ngc"),
       "triaglide.toml",
       {-59.0, -54.0, 552.0}},
      {"Dragon", real("cam/maslow/Dragon.nc"), "maslow.toml", {1489.2, -1072.6, 0.0}},
  };
}

// With `more`: the real-job table's other jobs (tests/test_real_jobs.cpp), on the machines and at
// the origins it runs them.
std::vector<Job> more_jobs() {
  const fs::path corpus = kSource.parent_path() / "shared" / "gcode" / "real";
  const auto real = [&](const std::string& relative) {
    return fs::exists(corpus / relative) ? pkm::test::readable_real_job(corpus, relative)
                                         : corpus / relative;
  };
  return {
      {"smooth_curves",
       real("plotter/svg2gcode/smooth_curves_circular_interpolation.gcode"),
       "linuxcnc-polargraph-2366.toml",
       {1000.0, -1200.0, 0.0}},
      {"mandala",
       real("plotter/inkscape/mandala_cnc_0001.gcode"),
       "linuxcnc-polargraph-2366.toml",
       {1130.0, -1200.0, 0.0}},
      {"btc_laser_qr",
       real("plotter/inkscape/btc_laser_qr_unbt_0001.gcode"),
       "linuxcnc-polargraph-2366.toml",
       {1130.0, -1200.0, 0.0}},
      {"bcnc-sample", real("cam/bcnc/sample.gcode"), "linuxcnc-ldelta.toml", {-15.0, -12.0, 0.0}},
      {"jsdc", real("cam/cncjs/jsdc.gcode"), "linuxcnc-ldelta.toml", {-50.0, 30.0, 0.0}},
      {"milldrill",
       real("cam/pcb2gcode/milldrill.ngc"),
       "linuxcnc-hexapod-sim.toml",
       {-65.0, 50.0, 480.0}},
      {"tort", real("linuxcnc/tort.ngc"), "matrix-mill.toml", {300.0, 200.0, -150.0}},
      {"boat-xyzac",
       real("linuxcnc-5axis/boat-xyzac.ngc"),
       "linuxcnc-xyzac-trt.toml",
       {0.0, 0.0, 0.0}},
  };
}

// The CPU time (s) of the plan with its samples, which go nowhere.
double sampled_plan_cpu_s(const pkm::machine::Machine& machine, const fs::path& program,
                          const pkm::motion::PlanOptions& options) {
  struct Discard final : pkm::motion::SampleSink {
    void write(const pkm::motion::Sample&) override {}
  } discard;
  const std::clock_t start = std::clock();
  pkm::motion::plan_program(machine, program, {}, options, discard);
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

// The planner times each piece over its length_mm; the reference over its Segment::length().
void report_length_mismatch(const pkm::test::PlannedJob& planned) {
  double worst = 0.0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < planned.pieces.size(); ++k) {
    const pkm::motion::PlannedPiece& piece = planned.pieces[k];
    const double mismatch =
        std::abs(piece.length_mm - piece.segment.length()) / std::max(piece.length_mm, 1e-12);
    if (mismatch > worst) {
      worst = mismatch;
      at = k;
    }
  }
  if (worst > 1e-9) {
    std::printf("    piece %zu (line %d): length_mm %.9g but Segment::length() %.9g\n", at,
                planned.pieces[at].segment.line, planned.pieces[at].length_mm,
                planned.pieces[at].segment.length());
  }
}

// A stretch of pieces from rest to rest: both timings.
struct Run {
  std::size_t first = 0, last = 0;
  double planner_s = 0.0, reference_s = 0.0;
  double ratio() const { return planner_s / reference_s; }
};

void print_runs(const pkm::test::PlannedJob& planned, const pkm::test::ReferenceResult& reference) {
  std::vector<Run> runs;
  Run run;
  for (std::size_t k = 0; k < planned.pieces.size(); ++k) {
    run.planner_s += planned.pieces[k].duration_s;
    run.reference_s += reference.piece_durations_s[k];
    if (planned.pieces[k].stop_after || k + 1 == planned.pieces.size()) {
      run.last = k;
      if (run.reference_s > 0.0) runs.push_back(run);
      run = Run{k + 1, k + 1};
    }
  }
  std::sort(runs.begin(), runs.end(),
            [](const Run& a, const Run& b) { return a.ratio() < b.ratio(); });
  const auto show = [&](const Run& r) {
    const pkm::motion::PlannedPiece& first = planned.pieces[r.first];
    std::printf(
        "    pieces %zu..%zu (lines %d..%d, first %s %.4f mm at %.3f mm/s): planner %.5f s, "
        "reference %.5f s, ratio %.6f\n",
        r.first, r.last, first.segment.line, planned.pieces[r.last].segment.line,
        first.segment.rapid ? "rapid" : "feed", first.length_mm, first.segment.feed_mm_per_s,
        r.planner_s, r.reference_s, r.ratio());
  };
  for (std::size_t k = 0; k < std::min<std::size_t>(5, runs.size()); ++k) show(runs[k]);
  std::printf("    ...\n");
  for (std::size_t k = runs.size() - std::min<std::size_t>(5, runs.size()); k < runs.size(); ++k) {
    show(runs[k]);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> arguments;
  double jerk_mm_per_s3 = 0.0;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--jerk" && i + 1 < argc) {
      jerk_mm_per_s3 = std::atof(argv[++i]);
      if (!(jerk_mm_per_s3 > 0.0)) {
        std::fprintf(stderr, "bench_plan_optimality: --jerk (mm/s^3) must be > 0\n");
        return 2;
      }
    } else {
      arguments.emplace_back(argv[i]);
    }
  }
  const double grid_mm = !arguments.empty() ? std::atof(arguments[0].c_str()) : 0.05;
  if (!(grid_mm > 0.0)) {
    std::fprintf(stderr, "bench_plan_optimality: the grid step (mm) must be > 0\n");
    return 2;
  }
  const std::string mode = arguments.size() > 1 ? arguments[1] : "";
  const bool runs = mode.find("runs") != std::string::npos;
  std::vector<Job> jobs = issue_jobs();
  if (mode.find("more") != std::string::npos) {
    const std::vector<Job> more = more_jobs();
    jobs.insert(jobs.end(), more.begin(), more.end());
  }
  std::printf("grid %.4g mm, servo period 1 ms", grid_mm);
  if (jerk_mm_per_s3 > 0.0) {
    std::printf(", planner jerk-limited at %g mm/s^3 (the reference has no jerk limit)",
                jerk_mm_per_s3);
  }
  std::printf("\n");
  // report_s: the plan's whole duration (with dwells and pen delays); planner_s: its motion.
  // plan_cpu_s: the estimate's CPU time; sampled_cpu_s: the plan with every sample (discarded).
  std::printf("%-22s %-18s %7s %10s %12s %12s %8s %10s %13s %10s\n", "job", "machine", "pieces",
              "report_s", "planner_s", "reference_s", "ratio", "plan_cpu_s", "sampled_cpu_s",
              "ref_cpu_s");
  std::vector<double> ratios;
  int failures = 0;
  for (const Job& job : jobs) {
    try {
      if (!fs::exists(job.program)) throw std::runtime_error("no " + job.program.string());
      const pkm::machine::Machine machine =
          pkm::machine::load_machine(kSource / "examples" / "machines" / job.machine);
      pkm::motion::PlanOptions options;
      options.origin << job.origin[0], job.origin[1], job.origin[2], 0.0, 0.0, 0.0;
      options.jerk_mm_per_s3 = jerk_mm_per_s3;
      const pkm::test::PlannedJob planned = pkm::test::plan_pieces(machine, job.program, options);
      const double sampled_cpu = sampled_plan_cpu_s(machine, job.program, options);
      const std::clock_t start = std::clock();
      const pkm::test::ReferenceResult reference =
          pkm::test::solve_reference(machine, planned.pieces, options.period_s, grid_mm);
      const double reference_cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
      const double ratio = planned.motion_time_s / reference.duration_s;
      ratios.push_back(ratio);
      std::printf("%-22s %-18s %7zu %10.3f %12.3f %12.3f %8.4f %10.3f %10.3f %10.2f\n", job.name,
                  job.machine, planned.pieces.size(), planned.report.duration_s,
                  planned.motion_time_s, reference.duration_s, ratio, planned.cpu_s, sampled_cpu,
                  reference_cpu);
      if (runs) print_runs(planned, reference);
      report_length_mismatch(planned);
    } catch (const std::exception& error) {
      std::printf("%-22s %-18s failed: %s\n", job.name, job.machine, error.what());
      ++failures;
    }
    std::fflush(stdout);
  }
  if (!ratios.empty()) {
    std::sort(ratios.begin(), ratios.end());
    const std::size_t n = ratios.size();
    const double median = n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
    std::printf("median ratio %.4f, worst %.4f (issue 29: <= 1.01 and <= 1.02)\n", median,
                ratios.back());
  }
  return failures == 0 ? 0 : 1;
}
