#include "pkm/io/sample_files.hpp"

#include <cinttypes>
#include <cstdio>
#include <stdexcept>

namespace pkm {

namespace {

// The values of a row in column order and interface units (sample_rows.hpp).
using RowBuilder = SampleRows;

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
    const std::size_t reals = rows_.pen() ? n - 1 : n;  // the pen's 0 or 1 is no real number
    for (std::size_t i = 2; i < reals; ++i) std::fprintf(out, ",%.9f", row[i]);
    if (rows_.pen()) std::fprintf(out, ",%d", static_cast<int>(row[n - 1]));
    std::fputc('\n', out);
  }
  void commit() override { file_.commit(); }

 private:
  AtomicFileWriter file_;
  RowBuilder rows_;
};

// A Python string literal of `text` (the column names in the NPY header).
std::string python_string(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\\' || c == '\'') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {  // the header is one line
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "'";
}

// NPY version 1.0: magic, header length, a Python dict literal padded to 64 bytes, then the
// rows. Each row is one record of a structured dtype, one named little-endian float64 field per
// column, so NumPy reads the names with the numbers. The row count is only known at the end, so
// the header is written with room for it and rewritten on commit.
class NpyFile final : public SampleFile {
 public:
  NpyFile(const std::filesystem::path& path, const Machine& machine) : file_(path), rows_(machine) {
    for (const std::string& column : sample_columns(machine)) {
      descr_ += (descr_.empty() ? "[" : ", ") + ("(" + python_string(column) + ", '<f8')");
    }
    descr_ += "]";
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
    char shape[64];
    std::snprintf(shape, sizeof shape, "(%20ld,)", rows);
    std::string text =
        "{'descr': " + descr_ + ", 'fortran_order': False, 'shape': " + shape + ", }";
    const std::size_t preamble = 10;  // magic (6), version (2), header length (2)
    while ((preamble + text.size() + 1) % 64 != 0) text += ' ';
    text += '\n';
    std::string out = "\x93NUMPY";
    out += '\x01';
    out += '\x00';
    if (text.size() > 65535) throw std::invalid_argument("too many columns for an NPY header");
    const auto length = static_cast<std::uint16_t>(text.size());
    out += static_cast<char>(length & 0xff);
    out += static_cast<char>(length >> 8);
    return out + text;
  }

  AtomicFileWriter file_;
  RowBuilder rows_;
  std::string descr_;  // the structured dtype: [('t', '<f8'), ('line', '<f8'), ...]
  long count_ = 0;
};

}  // namespace

std::unique_ptr<SampleFile> SampleFile::open(const std::filesystem::path& path,
                                             const Machine& machine) {
  const std::string extension = path.extension().string();
  if (extension == ".csv") return std::make_unique<CsvFile>(path, machine);
  if (extension == ".npy") return std::make_unique<NpyFile>(path, machine);
  throw std::invalid_argument("output " + path.string() + ": give a .csv or .npy file name");
}

}  // namespace pkm
