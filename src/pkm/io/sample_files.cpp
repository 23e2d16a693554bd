#include "pkm/io/sample_files.hpp"

#include <cinttypes>
#include <cstdio>
#include <stdexcept>

#include "pkm/text/decimal_text.hpp"

namespace pkm::io {

namespace {

// Rows gather in memory and reach the file in blocks of about this many bytes: a write per
// row (and a printf per value) cost several times the formatting (issue 16).
constexpr std::size_t kBlockBytes = std::size_t{1} << 16;

// A CSV row's longest text: every value at its longest %.9f, a comma or newline after each.
constexpr std::size_t kMaxRowChars = SampleRows::kMaxColumns * (text::kMaxFixedChars + 1);

// A row of `n` values as the CSV has always had it (printf's digits): t as %.6f, the line and
// the pen's 0 or 1 as %d, every other value as %.9f.
void append_csv_row(const double* row, std::size_t n, bool pen, text::TextBuffer& out) {
  char* end = text::write_fixed<6>(out.room(kMaxRowChars), row[0]);
  *end++ = ',';
  end = text::write_int(end, static_cast<int>(row[1]));
  const std::size_t reals = pen ? n - 1 : n;  // the pen's 0 or 1 is no real number
  for (std::size_t i = 2; i < reals; ++i) {
    *end++ = ',';
    end = text::write_fixed<9>(end, row[i]);
  }
  if (pen) {
    *end++ = ',';
    end = text::write_int(end, static_cast<int>(row[n - 1]));
  }
  *end++ = '\n';
  out.commit(end);
}

class CsvFile final : public SampleFile {
 public:
  CsvFile(const std::filesystem::path& path, const machine::Machine& machine)
      : file_(path), rows_(machine), pending_(kBlockBytes + kMaxRowChars) {
    std::string header;
    for (const std::string& column : sample_columns(machine)) {
      header += (header.empty() ? "" : ",") + column;
    }
    file_.write(header + "\n");
  }
  void write(const motion::Sample& sample) override {
    double row[SampleRows::kMaxColumns];
    const std::size_t n = rows_.fill(sample, row);
    append_csv_row(row, n, rows_.pen(), pending_);
    if (pending_.size() >= kBlockBytes) write_pending();
  }
  void commit() override {
    write_pending();
    file_.commit();
  }

 private:
  void write_pending() {
    file_.write(pending_.view());
    pending_.clear();
  }

  files::AtomicFileWriter file_;
  SampleRows rows_;  // a row's values in column order and interface units
  text::TextBuffer pending_;
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
  NpyFile(const std::filesystem::path& path, const machine::Machine& machine)
      : file_(path),
        rows_(machine),
        block_rows_(kBlockBytes / (sizeof(double) * rows_.columns())),
        pending_(block_rows_ * rows_.columns() + SampleRows::kMaxColumns) {
    for (const std::string& column : sample_columns(machine)) {
      descr_ += (descr_.empty() ? "[" : ", ") + ("(" + python_string(column) + ", '<f8')");
    }
    descr_ += "]";
    file_.write(header(0));
  }
  void write(const motion::Sample& sample) override {
    // Straight into the block: a row is its values' bytes (little-endian, as the header says).
    if (rows_.fill(sample, pending_.data() + pending_rows_ * rows_.columns()) != rows_.columns()) {
      throw std::logic_error("a sample with another number of joints than the machine's");
    }
    if (++pending_rows_ == block_rows_) write_pending();
    ++count_;
  }
  void commit() override {
    write_pending();
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

  void write_pending() {
    file_.write(std::string_view(reinterpret_cast<const char*>(pending_.data()),
                                 pending_rows_ * rows_.columns() * sizeof(double)));
    pending_rows_ = 0;
  }

  files::AtomicFileWriter file_;
  SampleRows rows_;              // a row's values in column order and interface units
  std::size_t block_rows_;       // rows in about kBlockBytes
  std::vector<double> pending_;  // block_rows_ rows, and room for a row too long
  std::size_t pending_rows_ = 0;
  std::string descr_;  // the structured dtype: [('t', '<f8'), ('line', '<f8'), ...]
  long count_ = 0;
};

}  // namespace

std::unique_ptr<SampleFile> SampleFile::open(const std::filesystem::path& path,
                                             const machine::Machine& machine) {
  const std::string extension = path.extension().string();
  if (extension == ".csv") return std::make_unique<CsvFile>(path, machine);
  if (extension == ".npy") return std::make_unique<NpyFile>(path, machine);
  throw std::invalid_argument("output " + path.string() + ": give a .csv or .npy file name");
}

}  // namespace pkm::io
