// pkm_linuxcnc_check: the verdict on a headless LinuxCNC run (tests/linuxcnc/run-linuxcnc).
// At every servo-thread sample after homing, LinuxCNC's joints must equal pkm's inverse
// kinematics of its commanded Cartesian pose within the tolerance (mm for linear joints, deg for
// rotary ones): in coordinated and teleop mode the joints are the module's inverse of the pose,
// in free mode the pose is the module's forward of the joints (of the sample before). At every rest
// pose, the actual pose (the module's forward kinematics of the joint feedback) must equal the
// commanded one.
//
//   pkm_linuxcnc_check --machine FILE [--units mm|inch] --samples samples.csv --rest rest.csv
//                      [--tolerance MM] [--allow-refused-poses]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/linuxcnc/kins_adapter.hpp"
#include "pkm/machine/machine.hpp"

namespace {

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int column(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  }
};

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  return fields;
}

Table read_csv(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error(path + ": cannot open");
  Table table;
  std::string line;
  if (std::getline(file, line)) table.header = split_csv_line(line);
  while (std::getline(file, line)) {
    if (!line.empty()) table.rows.push_back(split_csv_line(line));
  }
  return table;
}

struct Options {
  std::string machine;
  std::optional<pkm::machine::LengthUnit> units;
  std::string samples;
  std::string rest;
  double tolerance = 1e-6;
  // A run that is to fail (run-linuxcnc --expect-error): the samples at the poses the module
  // refused are reported, not failed.
  bool allow_refused = false;
};

Options parse_options(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(word + ": needs a value");
      return argv[++i];
    };
    if (word == "--machine") {
      options.machine = value();
    } else if (word == "--units") {
      const std::string text = value();
      options.units = pkm::linuxcnc::parse_world_unit(text);
      if (!options.units) throw std::runtime_error("--units " + text + ": must be mm or inch");
    } else if (word == "--samples") {
      options.samples = value();
    } else if (word == "--rest") {
      options.rest = value();
    } else if (word == "--allow-refused-poses") {
      options.allow_refused = true;
    } else if (word == "--tolerance") {
      options.tolerance = std::stod(value());
    } else {
      throw std::runtime_error("unknown option " + word);
    }
  }
  if (options.machine.empty() || options.samples.empty() || options.rest.empty()) {
    throw std::runtime_error("give --machine, --samples and --rest");
  }
  return options;
}

// The worst difference seen, and where.
struct Worst {
  double error = 0.0;
  std::string where;
  long count = 0;
  long over = 0;
  void add(double value, double tolerance, const std::string& place) {
    ++count;
    if (!(value <= tolerance)) ++over;
    if (count == 1 || !(value <= error)) {
      error = value;
      where = place;
    }
  }
};

class Checker {
 public:
  explicit Checker(const Options& options)
      : options_(options),
        machine_(pkm::machine::load_machine(options.machine)),
        units_(options.units.value_or(machine_.units())),
        mm_per_unit_(units_ == pkm::machine::LengthUnit::inch ? 25.4 : 1.0) {}

  // A LinuxCNC pose (world unit, deg) from a row's columns named prefix + x..c.
  pkm::geometry::Pose pose_of(const Table& table, const std::vector<std::string>& row,
                              const std::string& prefix) const {
    pkm::geometry::Vector6d values = pkm::geometry::Vector6d::Zero();
    for (int axis = 0; axis < pkm::geometry::kPoseSize; ++axis) {
      const int column = table.column(prefix + std::string(pkm::geometry::kAxisNames[axis]));
      if (column < 0) continue;
      const double value = std::stod(row[static_cast<std::size_t>(column)]);
      values[axis] = axis < 3 ? value * mm_per_unit_ : pkm::geometry::degrees_to_radians(value);
    }
    return pkm::geometry::Pose::from_vector(values);
  }

  // |LinuxCNC joint - pkm IK joint| over the joints (mm or deg), or infinity where pkm refuses.
  double joint_error(const Table& table, const std::vector<std::string>& row,
                     const pkm::geometry::Pose& pose, const std::string& suffix,
                     std::string& refusal) const {
    pkm::kinematics::JointVector joints(static_cast<int>(machine_.joints().size()));
    const pkm::kinematics::Status status = machine_.inverse(pose, joints);
    if (!status.ok()) {
      refusal = machine_.explain(pose, status);
      return INFINITY;
    }
    double worst = 0.0;
    for (int n = 0; n < joints.size(); ++n) {
      const int column = table.column("j" + std::to_string(n) + suffix);
      if (column < 0) throw std::runtime_error("no column j" + std::to_string(n) + suffix);
      const double lcnc = std::stod(row[static_cast<std::size_t>(column)]);
      const bool rotary =
          machine_.joints()[static_cast<std::size_t>(n)].kind == pkm::kinematics::JointKind::rotary;
      const double ours =
          rotary ? pkm::geometry::radians_to_degrees(joints[n]) : joints[n] / mm_per_unit_;
      worst = std::max(worst, std::abs(lcnc - ours) * (rotary ? 1.0 : mm_per_unit_));
    }
    return worst;
  }

  bool check_samples() {
    const Table table = read_csv(options_.samples);
    Worst inverse, forward;
    long before_homing = 0;
    long refused = 0;

    std::string first_refusal;
    const auto flag = [&](const std::vector<std::string>& row, const char* name) {
      const int column = table.column(name);
      return column >= 0 && row[static_cast<std::size_t>(column)] == "1";
    };
    const int line_column = table.column("line");
    for (std::size_t k = 0; k < table.rows.size(); ++k) {
      const std::vector<std::string>& row = table.rows[k];
      if (!flag(row, "enabled") || !flag(row, "all_homed")) {
        ++before_homing;  // (motion reports all homed for a moment at start, joints at 0)
        continue;
      }

      const pkm::geometry::Pose pose = pose_of(table, row, "");
      // In free mode LinuxCNC 2.9's motion computes the pose of a cycle from the joints of the
      // cycle before (it copies them before its joint planners step): compare with those.
      const bool coordinated = flag(row, "coord") || flag(row, "teleop");
      const std::vector<std::string>& joints_row = coordinated || k == 0 ? row : table.rows[k - 1];
      std::string refusal;
      const double error = joint_error(table, joints_row, pose, "", refusal);
      if (!refusal.empty() && first_refusal.empty()) first_refusal = refusal;
      if (!refusal.empty() && options_.allow_refused) {
        ++refused;
        continue;
      }
      const std::string place =
          "sample " + std::to_string(k) +
          (line_column >= 0 ? " (line " + row[static_cast<std::size_t>(line_column)] + ")" : "");
      (coordinated ? inverse : forward).add(error, options_.tolerance, place);
    }
    std::printf("samples: %zu (%ld before the machine is on and homed)\n", table.rows.size(),
                before_homing);
    report("joints = pkm IK of the commanded pose (coordinated: the module's inverse)", inverse);
    report("joints = pkm IK of the commanded pose (free mode: the module's forward)", forward);
    if (!first_refusal.empty()) {
      std::printf("  pkm refuses %s sampled pose: %s\n", refused > 0 ? "(as expected) a" : "a",
                  first_refusal.c_str());
    }
    bool ok = inverse.over == 0 && forward.over == 0 && inverse.count > 0;
    if (inverse.count == 0) std::printf("  no sample in coordinated mode: nothing ran\n");
    return ok;
  }

  bool check_rest() {
    const Table table = read_csv(options_.rest);
    Worst forward, inverse;
    for (const std::vector<std::string>& row : table.rows) {
      const pkm::geometry::Pose commanded = pose_of(table, row, "cmd_");
      const pkm::geometry::Pose actual = pose_of(table, row, "act_");
      const pkm::geometry::Vector6d difference = actual.as_vector() - commanded.as_vector();
      double error = 0.0;
      for (int axis = 0; axis < pkm::geometry::kPoseSize; ++axis) {
        error = std::max(error,
                         std::abs(axis < 3 ? difference[axis]
                                           : pkm::geometry::radians_to_degrees(difference[axis])));
      }
      forward.add(error, options_.tolerance, row[0]);
      std::string refusal;
      inverse.add(joint_error(table, row, commanded, "", refusal), options_.tolerance, row[0]);
    }
    std::printf("rest poses: %zu\n", table.rows.size());
    report("actual pose (the module's FK of the joint feedback) = commanded pose", forward);
    report("joints = pkm IK of the commanded pose", inverse);
    return forward.over == 0 && inverse.over == 0 && forward.count > 0;
  }

 private:
  void report(const char* what, const Worst& worst) const {
    if (worst.count == 0) return;
    std::printf("  %s: %ld checked, worst %.3g mm/deg at %s, %ld over %.3g\n", what, worst.count,
                worst.error, worst.where.c_str(), worst.over, options_.tolerance);
  }

  Options options_;
  pkm::machine::Machine machine_;
  pkm::machine::LengthUnit units_;
  double mm_per_unit_;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options options = parse_options(argc, argv);
    Checker checker(options);
    const bool samples_ok = checker.check_samples();
    const bool rest_ok = checker.check_rest();
    std::printf("verdict: %s\n", samples_ok && rest_ok ? "pass" : "FAIL");
    return samples_ok && rest_ok ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pkm_linuxcnc_check: %s\n", error.what());
    return 2;
  }
}
