#include "pkm/io/sample_files.hpp"

#include <cinttypes>
#include <cstdio>
#include <stdexcept>

namespace pkm {

namespace {

bool shows_orientation(const Machine& machine) {
  return machine.kinematics().dof().any_rotation();
}

// The values of a row in column order and interface units.
class RowBuilder {
 public:
  explicit RowBuilder(const Machine& machine)
      : machine_(machine), orientation_(shows_orientation(machine)) {}
  std::size_t fill(const motion::Sample& s, double* row) const {
    std::size_t n = 0;
    row[n++] = s.time_s;
    row[n++] = s.line;
    for (int axis = 0; axis < 3; ++axis) row[n++] = s.pose[axis];
    if (orientation_) {
      for (int axis = 3; axis < 6; ++axis) row[n++] = radians_to_degrees(s.pose[axis]);
    }
    for (int i = 0; i < s.joints.size(); ++i) {
      row[n++] = machine_.joints()[static_cast<std::size_t>(i)].to_interface(s.joints[i]);
    }
    return n;
  }

 private:
  const Machine& machine_;
  bool orientation_;
};

class CsvFile final : public SampleFile {
 public:
  CsvFile(const std::filesystem::path& path, const Machine& machine) : file_(path), rows_(machine) {
    std::string header;
    for (const std::string& column : sample_columns(machine)) {
      header += (header.empty() ? "" : ",") + column;
    }
    file_.write(header + "\n");
  }
  void write(const motion::Sample& sample) override {
    double row[32];
    const std::size_t n = rows_.fill(sample, row);
    std::FILE* out = file_.stream();
    std::fprintf(out, "%.6f,%d", row[0], static_cast<int>(row[1]));
    for (std::size_t i = 2; i < n; ++i) std::fprintf(out, ",%.9f", row[i]);
    std::fputc('\n', out);
  }
  void commit() override { file_.commit(); }

 private:
  AtomicFileWriter file_;
  RowBuilder rows_;
};

// NPY version 1.0: magic, header length, a Python dict literal padded to 64 bytes, then the
// rows. The row count is only known at the end, so the header is written with room for it and
// rewritten on commit.
class NpyFile final : public SampleFile {
 public:
  NpyFile(const std::filesystem::path& path, const Machine& machine)
      : file_(path), rows_(machine), columns_(sample_columns(machine).size()) {
    file_.write(header(0));
  }
  void write(const motion::Sample& sample) override {
    double row[32];
    const std::size_t n = rows_.fill(sample, row);
    if (std::fwrite(row, sizeof(double), n, file_.stream()) != n) {
      throw std::runtime_error("cannot write " + file_.path().string());
    }
    ++count_;
  }
  void commit() override {
    file_.write_at(0, header(count_));
    file_.commit();
  }

 private:
  std::string header(long rows) const {
    char dict[128];
    std::snprintf(dict, sizeof dict,
                  "{'descr': '<f8', 'fortran_order': False, 'shape': (%20ld, %zu), }", rows,
                  columns_);
    std::string text = dict;
    const std::size_t preamble = 10;  // magic (6), version (2), header length (2)
    while ((preamble + text.size() + 1) % 64 != 0) text += ' ';
    text += '\n';
    std::string out = "\x93NUMPY";
    out += '\x01';
    out += '\x00';
    const auto length = static_cast<std::uint16_t>(text.size());
    out += static_cast<char>(length & 0xff);
    out += static_cast<char>(length >> 8);
    return out + text;
  }

  AtomicFileWriter file_;
  RowBuilder rows_;
  std::size_t columns_;
  long count_ = 0;
};

}  // namespace

std::vector<std::string> sample_columns(const Machine& machine) {
  std::vector<std::string> columns = {"t", "line", "x", "y", "z"};
  if (shows_orientation(machine)) columns.insert(columns.end(), {"a", "b", "c"});
  for (const JointSpec& joint : machine.joints()) columns.push_back("j_" + joint.name);
  return columns;
}

std::unique_ptr<SampleFile> SampleFile::open(const std::filesystem::path& path,
                                             const Machine& machine) {
  const std::string extension = path.extension().string();
  if (extension == ".csv") return std::make_unique<CsvFile>(path, machine);
  if (extension == ".npy") return std::make_unique<NpyFile>(path, machine);
  throw std::invalid_argument("output " + path.string() + ": give a .csv or .npy file name");
}

}  // namespace pkm
