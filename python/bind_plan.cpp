// pkmkit.plan and pkmkit.plan_chunks: a G-code job planned on a machine (motion::plan_program, as
// `pkm plan` runs it) into NumPy structured arrays whose fields are the sample files' columns
// (io/sample_rows.hpp), number for number what `pkm plan -o OUT.npy` writes, with the report of
// `pkm plan --report` as a dict. plan() keeps every sample; plan_chunks() streams them in chunks
// from a planner running on its own thread, for jobs larger than memory.
#include <pybind11/stl.h>

#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bind_common.hpp"
#include "pkm/gcode/tool_table.hpp"
#include "pkm/io/json_reports.hpp"
#include "pkm/io/sample_rows.hpp"
#include "pkm/motion/planner.hpp"

namespace pkm::python {

namespace {

// The planner's inputs besides the machine, from the keyword arguments (as pkm plan's options).
struct PlanArguments {
  std::string program;
  gcode::InterpreterOptions interpreter;
  motion::PlanOptions plan;
};

PlanArguments plan_arguments(const machine::Machine& machine, const std::string& program,
                             double period_s, const std::vector<double>& origin,
                             const std::optional<Array>& start, const std::string& attitude,
                             double jerk_mm_per_s3, const std::optional<std::string>& tool_table,
                             long max_samples) {
  // The planner's bounds (motion/planner.hpp), as pkm plan's; the messages quote them.
  static_assert(motion::kMinPeriodS == 1e-6 && motion::kMaxPeriodS == 1.0 &&
                motion::kMaxJerkPerS3 == 1e12 && motion::kMaxSamplesBound == 1'000'000'000'000'000);
  if (!(period_s >= motion::kMinPeriodS && period_s <= motion::kMaxPeriodS)) {
    throw py::value_error("period must lie within [1e-06, 1] s");
  }
  if (!(jerk_mm_per_s3 >= 0.0 && jerk_mm_per_s3 <= motion::kMaxJerkPerS3)) {
    throw py::value_error("jerk must lie within [0, 1e12] mm/s^3 (0: no jerk limit)");
  }
  if (attitude != "linear" && attitude != "great-circle") {
    throw py::value_error("attitude must be 'linear' or 'great-circle'");
  }
  if (!(max_samples >= 0 && max_samples <= motion::kMaxSamplesBound)) {
    throw py::value_error("max_samples must lie within [0, 1e15] (0: no bound)");
  }
  PlanArguments arguments;
  arguments.program = program;
  arguments.plan.period_s = period_s;
  arguments.plan.origin = origin_argument(origin, "origin");
  if (start) arguments.plan.start = pose_argument(machine, *start, "start");
  arguments.plan.great_circle_attitude = attitude == "great-circle";
  arguments.plan.jerk_mm_per_s3 = jerk_mm_per_s3;
  arguments.plan.max_samples = max_samples;
  if (tool_table) arguments.interpreter.tool_table = gcode::read_tool_table(*tool_table);
  return arguments;
}

// The structured dtype of the machine's sample rows: one little-endian float64 field per column,
// named as the NPY file's.
py::dtype sample_dtype(const machine::Machine& machine) {
  py::list fields;
  for (const std::string& column : io::sample_columns(machine)) {
    fields.append(py::make_tuple(column, "<f8"));
  }
  return py::module_::import("numpy").attr("dtype")(fields).cast<py::dtype>();
}

// Rows of `columns` doubles as a structured array that owns them (no copy).
py::array sample_array(const py::dtype& dtype, std::vector<double>&& values, std::size_t columns) {
  auto* owned = new std::vector<double>(std::move(values));
  const py::capsule free_values(owned,
                                [](void* v) { delete static_cast<std::vector<double>*>(v); });
  const auto rows = static_cast<py::ssize_t>(owned->size() / columns);
  const auto stride = static_cast<py::ssize_t>(columns * sizeof(double));
  return py::array(dtype, {rows}, {stride}, owned->data(), free_values);
}

// Every sample's row, one after the other.
class RowCollector final : public motion::SampleSink {
 public:
  explicit RowCollector(const machine::Machine& machine) : rows_(machine) {}
  void write(const motion::Sample& sample) override {
    double row[io::SampleRows::kMaxColumns];
    const std::size_t n = rows_.fill(sample, row);
    values_.insert(values_.end(), row, row + n);
  }
  std::vector<double>& values() { return values_; }

 private:
  io::SampleRows rows_;
  std::vector<double> values_;
};

py::tuple plan(const machine::Machine& machine, const std::string& program, double period_s,
               const std::vector<double>& origin, const std::optional<Array>& start,
               const std::string& attitude, double jerk_mm_per_s3,
               const std::optional<std::string>& tool_table, long max_samples) {
  const PlanArguments arguments = plan_arguments(machine, program, period_s, origin, start,
                                                 attitude, jerk_mm_per_s3, tool_table, max_samples);
  const machine::Machine own =
      machine;  // the loop runs without the GIL: a copy of its own (pkmkit.cpp)
  RowCollector rows(own);
  motion::PlanReport report;
  try {
    const py::gil_scoped_release released;
    report =
        motion::plan_program(own, arguments.program, arguments.interpreter, arguments.plan, rows);
  } catch (const motion::PlanError& error) {
    raise_with_reach_hint("PlanError", error.what(), error.line(), own, arguments.program,
                          arguments.interpreter, arguments.plan.origin);
  }
  const nlohmann::json json = io::plan_report_json(own, report, arguments.program, period_s, false);
  return py::make_tuple(
      sample_array(sample_dtype(own), std::move(rows.values()), io::sample_columns(own).size()),
      json_to_python(json));
}

// Samples nobody keeps: the estimate makes none.
struct DiscardSamples final : motion::SampleSink {
  void write(const motion::Sample&) override {}
};

py::object estimate(const machine::Machine& machine, const std::string& program, double period_s,
                    const std::vector<double>& origin, const std::optional<Array>& start,
                    const std::string& attitude, double jerk_mm_per_s3,
                    const std::optional<std::string>& tool_table) {
  PlanArguments arguments = plan_arguments(machine, program, period_s, origin, start, attitude,
                                           jerk_mm_per_s3, tool_table, 0);
  arguments.plan.estimate_only = true;
  const machine::Machine own = machine;
  DiscardSamples none;
  motion::PlanReport report;
  {
    const py::gil_scoped_release released;
    report =
        motion::plan_program(own, arguments.program, arguments.interpreter, arguments.plan, none);
  }
  return json_to_python(io::plan_report_json(own, report, arguments.program, period_s, true));
}

// Thrown into the planner's thread when the iterator goes away before the plan has ended.
struct PlanAbandoned {};

// The planner on its own thread, handing over a chunk of rows at a time: it fills the next chunk
// while Python works on the last one, and waits while a full chunk has not been taken, so at most
// two chunks are held here whatever the job's length.
class PlanChunks final : public motion::SampleSink {
 public:
  PlanChunks(const machine::Machine& machine, PlanArguments arguments, std::size_t chunk_rows)
      : machine_(machine),
        arguments_(std::move(arguments)),
        rows_(machine_),
        columns_(rows_.columns()),
        chunk_values_(chunk_rows * columns_),
        dtype_(sample_dtype(machine_)) {
    arguments_.plan.on_line = [this](int) {
      if (abandoned()) throw PlanAbandoned{};
    };
    filling_.reserve(chunk_values_);
    worker_ = std::thread([this] { run(); });
  }
  ~PlanChunks() override {
    {
      const std::lock_guard lock(mutex_);
      abandon_ = true;
    }
    changed_.notify_all();
    const py::gil_scoped_release released;  // the planner may be between two lines
    worker_.join();
  }
  PlanChunks(const PlanChunks&) = delete;
  PlanChunks& operator=(const PlanChunks&) = delete;

  void write(const motion::Sample& sample) override {
    double row[io::SampleRows::kMaxColumns];
    const std::size_t n = rows_.fill(sample, row);
    filling_.insert(filling_.end(), row, row + n);
    if (filling_.size() >= chunk_values_) hand_over();
  }

  // The next chunk, or StopIteration after the last (the report is then set); the planner's
  // error where it failed. Several Python threads may share the iterator: each takes the GIL
  // back only once it has let go of the mutex, so that none holds the mutex while waiting for
  // the GIL another holds while waiting for the mutex (issue 26: four threads deadlocked).
  py::array next() {
    std::optional<std::vector<double>> values;
    std::exception_ptr error;
    {
      const py::gil_scoped_release released;
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [this] { return ready_ || finished_; });
      if (ready_) {
        values = std::move(ready_);
        ready_.reset();
      } else {
        error = std::exchange(error_, nullptr);
      }
      lock.unlock();
      changed_.notify_all();
    }
    if (values) return sample_array(dtype_, std::move(*values), columns_);
    if (error) {
      try {
        std::rethrow_exception(error);
      } catch (const motion::PlanError& plan_error) {
        raise_with_reach_hint("PlanError", plan_error.what(), plan_error.line(), machine_,
                              arguments_.program, arguments_.interpreter, arguments_.plan.origin);
      }
    }
    // finished_report_ was set before finished_, under the mutex taken above, and stays.
    if (report_.is_none() && finished_report_) {
      report_ = json_to_python(io::plan_report_json(machine_, *finished_report_, arguments_.program,
                                                    arguments_.plan.period_s, false));
    }
    throw py::stop_iteration();
  }

  // The report as pkm plan --report writes it, once every chunk has been taken; None before.
  py::object report() const { return report_; }
  py::dtype dtype() const { return dtype_; }

 private:
  bool abandoned() {
    const std::lock_guard lock(mutex_);
    return abandon_;
  }

  // Waits until the previous chunk has been taken, then offers this one.
  void hand_over() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !ready_ || abandon_; });
    if (abandon_) throw PlanAbandoned{};
    ready_ = std::move(filling_);
    filling_ = std::vector<double>();
    filling_.reserve(chunk_values_);
    lock.unlock();
    changed_.notify_all();
  }

  void run() {
    std::exception_ptr error;
    std::optional<motion::PlanReport> report;
    try {
      report = motion::plan_program(machine_, arguments_.program, arguments_.interpreter,
                                    arguments_.plan, *this);
      if (!filling_.empty()) hand_over();
    } catch (const PlanAbandoned&) {
    } catch (...) {
      error = std::current_exception();
    }
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !ready_ || abandon_; });  // the last chunk taken first
    error_ = error;
    finished_report_ = std::move(report);
    finished_ = true;
    lock.unlock();
    changed_.notify_all();
  }

  const machine::Machine machine_;  // its own copy: the planner runs on another thread
  PlanArguments arguments_;
  io::SampleRows rows_;
  std::size_t columns_;
  std::size_t chunk_values_;
  py::dtype dtype_;
  py::object report_ = py::none();
  std::vector<double> filling_;  // the planner's thread's alone

  std::mutex mutex_;  // guards what follows
  std::condition_variable changed_;
  std::optional<std::vector<double>> ready_;
  bool finished_ = false;
  bool abandon_ = false;
  std::exception_ptr error_;
  std::optional<motion::PlanReport> finished_report_;

  std::thread worker_;  // last: started once everything above is made
};

std::unique_ptr<PlanChunks> plan_chunks(const machine::Machine& machine, const std::string& program,
                                        long chunk, double period_s,
                                        const std::vector<double>& origin,
                                        const std::optional<Array>& start,
                                        const std::string& attitude, double jerk_mm_per_s3,
                                        const std::optional<std::string>& tool_table,
                                        long max_samples) {
  if (chunk < 1) throw py::value_error("chunk must be at least 1 sample");
  PlanArguments arguments = plan_arguments(machine, program, period_s, origin, start, attitude,
                                           jerk_mm_per_s3, tool_table, max_samples);
  return std::make_unique<PlanChunks>(machine, std::move(arguments),
                                      static_cast<std::size_t>(chunk));
}

}  // namespace

void bind_plan(py::module_& module) {
  py::class_<PlanChunks>(module, "PlanChunks",
                         "The samples of a plan in chunks (structured arrays); .report once "
                         "the last has been taken.")
      .def("__iter__", [](PlanChunks& chunks) -> PlanChunks& { return chunks; })
      .def("__next__", &PlanChunks::next)
      .def_property_readonly("report", &PlanChunks::report)
      .def_property_readonly("dtype", &PlanChunks::dtype);
  module.def("plan", &plan, py::arg("machine"), py::arg("program"), py::kw_only(),
             py::arg("period") = 0.001, py::arg("origin") = std::vector<double>{},
             py::arg("start") = py::none(), py::arg("attitude") = "linear", py::arg("jerk") = 0.0,
             py::arg("tool_table") = py::none(),
             py::arg("max_samples") = motion::kDefaultMaxSamples,
             "Plans a G-code job as pkm plan does: (samples, report). samples is a structured "
             "array, one float64 field per column of pkm plan's NPY (t, line, x y z [a b c] in "
             "mm and deg, j_<joint> in mm or deg, [pen]); report the dict of pkm plan --report. "
             "period in s, origin x y [z [a b c]] (mm, deg) where the program's zero sits, start "
             "a pose of the machine's coordinates (default home), jerk in mm/s^3 (0: none).");
  module.def("estimate", &estimate, py::arg("machine"), py::arg("program"), py::kw_only(),
             py::arg("period") = 0.001, py::arg("origin") = std::vector<double>{},
             py::arg("start") = py::none(), py::arg("attitude") = "linear", py::arg("jerk") = 0.0,
             py::arg("tool_table") = py::none(),
             "The report of pkm plan --estimate as a dict: the job's duration, samples, joint "
             "ranges and feed-limited moves, without making the samples (a fraction of plan's "
             "time). Options as plan's.");
  module.def("plan_chunks", &plan_chunks, py::arg("machine"), py::arg("program"), py::kw_only(),
             py::arg("chunk") = 65536, py::arg("period") = 0.001,
             py::arg("origin") = std::vector<double>{}, py::arg("start") = py::none(),
             py::arg("attitude") = "linear", py::arg("jerk") = 0.0,
             py::arg("tool_table") = py::none(), py::arg("max_samples") = 0,
             "plan() as an iterator of structured arrays of at most `chunk` samples each, "
             "planned while they are used (a job larger than memory); .report after the last. "
             "max_samples 0: no bound.");
}

}  // namespace pkm::python
