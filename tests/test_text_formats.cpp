// The text outputs are byte for byte what they were when printf wrote them (issue 16): the
// number formatter against snprintf, `pkm gcode --canon`'s lines against the snprintf formatter
// kept in legacy_text_formats.hpp over every command of the test programs and the real corpus,
// CSV rows and NPY records against the rows' values.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "legacy_text_formats.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/io/sample_files.hpp"
#include "pkm/text/decimal_text.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

namespace fs = std::filesystem;

template <int Decimals>
std::string fixed(double value) {
  char digits[text::kMaxFixedChars];
  return std::string(digits, text::write_fixed<Decimals>(digits, value));
}

template <int Decimals>
std::string printf_fixed(double value) {
  char digits[512];
  std::snprintf(digits, sizeof digits, "%.*f", Decimals, value);
  return digits;
}

TEST(FixedDecimal, HandComputedCases) {
  EXPECT_EQ(fixed<4>(0.0), "0.0000");
  EXPECT_EQ(fixed<4>(-0.0), "-0.0000");
  EXPECT_EQ(fixed<4>(-0.00001), "-0.0000");  // the sign survives rounding to zero, as in printf
  EXPECT_EQ(fixed<4>(3.339), "3.3390");
  EXPECT_EQ(fixed<4>(-0.15685), "-0.1568");  // the double is just below ...685
  EXPECT_EQ(fixed<4>(0.03125), "0.0312");    // an exact tie goes to the even digit
  EXPECT_EQ(fixed<4>(0.09375), "0.0938");
  EXPECT_EQ(fixed<4>(999.99995), "1000.0000");  // just above the tie: the carry runs through
  EXPECT_EQ(fixed<0>(2.5), "2");
  EXPECT_EQ(fixed<0>(3.5), "4");
  EXPECT_EQ(fixed<6>(0.001), "0.001000");
  EXPECT_EQ(fixed<9>(1060.531484), "1060.531484000");
  EXPECT_EQ(fixed<9>(5e-10), "0.000000001");  // 5e-10 is a little above its decimal
  EXPECT_EQ(fixed<9>(-1e-300), "-0.000000000");
  EXPECT_EQ(fixed<9>(std::numeric_limits<double>::denorm_min()), "0.000000000");
  EXPECT_EQ(fixed<4>(1e15), "1000000000000000.0000");  // past the 64-bit path
  EXPECT_EQ(fixed<4>(-123456789012345678.0), "-123456789012345680.0000");
  EXPECT_EQ(fixed<4>(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(fixed<4>(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(fixed<4>(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(fixed<4>(-std::numeric_limits<double>::quiet_NaN()), "-nan");
  EXPECT_EQ(fixed<4>(DBL_MAX).size(), 309u + 5u);
}

// Values of every kind a job or a sample holds, and the edges of the formatter's paths.
template <int Decimals>
void expect_printf_digits() {
  std::mt19937_64 rng(Decimals);
  std::vector<double> values = {0.0,
                                -0.0,
                                DBL_MAX,
                                -DBL_MAX,
                                DBL_MIN,
                                -DBL_MIN,
                                std::numeric_limits<double>::denorm_min(),
                                1e18 / std::pow(10.0, Decimals),  // the 64-bit path's limit
                                std::nextafter(1e18 / std::pow(10.0, Decimals), 0.0),
                                9007199254740992.0,
                                0.5,
                                -0.5,
                                1.5};
  std::uniform_real_distribution<double> coordinate(-2000.0, 2000.0);
  std::uniform_int_distribution<std::uint64_t> any_bits;
  for (int i = 0; i < 200000; ++i) {
    values.push_back(coordinate(rng));
    // Any magnitude from 1e-30 up to 1e20, any mantissa.
    const double exponent = std::uniform_real_distribution<double>(-30.0, 20.0)(rng);
    const double mantissa = std::bit_cast<double>((any_bits(rng) >> 12) | 0x3ff0000000000000);
    values.push_back((i % 2 ? -1.0 : 1.0) * mantissa * std::pow(10.0, exponent));
    // Exact ties at `Decimals` places, (2k + 1) / 2^(Decimals + 1), and their neighbours.
    const double tie =
        std::ldexp(static_cast<double>(2 * (any_bits(rng) >> 24) + 1), -(Decimals + 1));
    values.insert(values.end(), {tie, -tie, std::nextafter(tie, 0.0), std::nextafter(tie, 1e300)});
  }
  for (int i = 0; i < 2000; ++i) values.push_back(std::bit_cast<double>(any_bits(rng)));
  int mismatches = 0;
  for (const double value : values) {
    if (fixed<Decimals>(value) != printf_fixed<Decimals>(value) && ++mismatches <= 5) {
      ADD_FAILURE() << std::hexfloat << value << ": " << fixed<Decimals>(value) << " against "
                    << printf_fixed<Decimals>(value);
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(FixedDecimal, SameDigitsAsPrintfAt4) {
  expect_printf_digits<4>();
}
TEST(FixedDecimal, SameDigitsAsPrintfAt6) {
  expect_printf_digits<6>();
}
TEST(FixedDecimal, SameDigitsAsPrintfAt9) {
  expect_printf_digits<9>();
}
TEST(FixedDecimal, SameDigitsAsPrintfAt0) {
  expect_printf_digits<0>();
}

TEST(FixedDecimal, IntegersAndPaddingAsPrintf) {
  for (const long value :
       {0L, 7L, -7L, 12345L, 123456L, -99999L, long{INT_MAX}, long{INT_MIN}, LONG_MAX, LONG_MIN}) {
    text::TextBuffer out(1);  // grows as it goes
    text::append_int(out, value);
    out.push_back('|');
    text::append_int_right(out, value, 5);
    char expected[128];
    std::snprintf(expected, sizeof expected, "%ld|%5ld", value, value);
    EXPECT_EQ(out.view(), expected);
  }
  for (const char* label : {"", "1", "12345", "123456"}) {
    text::TextBuffer out;
    text::append_left(out, label, 5);
    char expected[64];
    std::snprintf(expected, sizeof expected, "%-5s", label);
    EXPECT_EQ(out.view(), expected);
  }
}

// The conformance tests' tool table, which the test programs' G41 and G43 need, and their
// subroutine files.
gcode::InterpreterOptions with_tool_table() {
  gcode::InterpreterOptions options;
  options.tool_table =
      gcode::read_tool_table(fs::path(PKM_SOURCE_DIR) / "tests" / "conformance" / "conformance.tbl",
                             gcode::LengthUnits::inch);
  options.subroutine_path = {fs::path(PKM_SOURCE_DIR) / "tests" / "gcode" / "subroutines"};
  return options;
}

// Every line `pkm gcode --canon` prints for `program`, formatted now and as before. Returns the
// error that stopped the program part-way ("" when it ran to the end).
std::string expect_canon_lines_as_before(const fs::path& program) {
  SCOPED_TRACE(program.string());
  text::TextBuffer now;
  std::string before;
  int sequence = 0;
  long commands = 0;
  std::string refused;
  try {
    gcode::Interpreter interpreter(program, with_tool_table());
    interpreter.run([&](const gcode::Canon& canon) {
      ++sequence;
      ++commands;
      gcode::append_canon_line_start(sequence, canon.n_label, now);
      gcode::append_canon_text(canon, now);
      now.push_back('\n');
      before += legacy::canon_line(sequence, canon.n_label, legacy::canon_text(canon));
    });
  } catch (const gcode::GcodeError& error) {
    refused = error.what();  // the lines before the error are compared
  }
  EXPECT_GT(commands, 0);
  EXPECT_EQ(now.size(), before.size());
  if (now.size() != before.size()) return refused;
  const auto [differs, _] = std::mismatch(before.begin(), before.end(), now.view().begin());
  if (differs != before.end()) {
    const auto line_start = before.rfind('\n', static_cast<std::size_t>(differs - before.begin()));
    ADD_FAILURE() << "first difference in the line after: "
                  << before.substr(line_start == std::string::npos ? 0 : line_start, 120);
  }
  return refused;
}

TEST(CanonText, TestProgramsAsBefore) {
  for (const auto& entry : fs::directory_iterator(fs::path(PKM_SOURCE_DIR) / "tests" / "gcode")) {
    if (entry.path().extension() == ".ngc") {
      EXPECT_EQ(expect_canon_lines_as_before(entry.path()), "");
    }
  }
}

TEST(CanonText, RealCorpusAsBefore) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  int programs = 0;
  for (const auto& entry : fs::recursive_directory_iterator(test::real_corpus())) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".ngc" || extension == ".nc" || extension == ".gcode") {
      expect_canon_lines_as_before(entry.path());
      ++programs;
    }
  }
  EXPECT_GT(programs, 50);
}

// Every kind of command, with numbers past the ordinary: each line as before.
TEST(CanonText, EveryKindAsBefore) {
  gcode::Canon canon;
  canon.end = {-0.0, 1e-7, -123456.78915, 0.00005, 99999.99995, -1e13, 3.0, -4.5, 6.25};
  canon.center = {-0.15685, 12.5};
  canon.value = 0.03125;
  canon.turns = -2;
  canon.integer = 64;
  canon.text = "G04 P3";
  canon.n_label = "1234567";
  for (int kind = 0; kind <= static_cast<int>(gcode::CanonKind::wait_orient_spindle); ++kind) {
    canon.kind = static_cast<gcode::CanonKind>(kind);
    for (const gcode::Plane plane : {gcode::Plane::xy, gcode::Plane::xz, gcode::Plane::yz}) {
      canon.plane = plane;
      canon.units = plane == gcode::Plane::xy ? gcode::LengthUnits::inch : gcode::LengthUnits::mm;
      canon.feed_mode = plane == gcode::Plane::xz ? gcode::FeedMode::inverse_time
                                                  : gcode::FeedMode::units_per_minute;
      canon.integer = plane == gcode::Plane::xy ? 64 : plane == gcode::Plane::xz ? 61 : 611;
      EXPECT_EQ(gcode::canon_text(canon), legacy::canon_text(canon)) << "kind " << kind;
    }
  }
  canon.kind = gcode::CanonKind::feed;
  EXPECT_EQ(
      gcode::canon_text(canon),
      "STRAIGHT_FEED(-0.0000, 0.0000, -123456.7891, 0.0001, 99999.9999, -10000000000000.0000)");
  canon.kind = gcode::CanonKind::orient_spindle;
  canon.value = 87.5;
  canon.integer = 2;
  EXPECT_EQ(gcode::canon_text(canon), "ORIENT_SPINDLE(0, 87.5000, 2)");  // as rs274 prints it
}

// The rows of a CSV file after its header.
std::vector<std::string> csv_rows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> rows;
  for (std::string row; std::getline(in, row);) rows.push_back(row + "\n");
  if (!rows.empty()) rows.erase(rows.begin());
  return rows;
}

// Samples whose values are every kind a CSV row must keep: negatives, -0, tiny, huge, ties.
std::vector<motion::Sample> edge_samples(const machine::Machine& machine, int count) {
  // 0.0078125 and 0.0009765625 are exact ties at 6 and 9 decimals (even digit: down).
  const double edges[] = {-0.0,   1e-10,     -5e-10,           1.0000000005, 0.001953125,
                          -1e300, 0.0078125, 0.0009765625,     1e15,         -1060.531484,
                          0.1,    -2e-9,     123456789.123456, 0.0000000015};
  std::vector<motion::Sample> samples(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    motion::Sample& s = samples[static_cast<std::size_t>(i)];
    const auto edge = [&](int k) {
      return edges[static_cast<std::size_t>(i + k) % std::size(edges)];
    };
    s.time_s = i % 7 == 0 ? edge(0) : 0.001 * i;
    s.line = i % 5 == 0 ? -i : i;
    s.pose << edge(1), edge(2) * (i % 3), edge(3) + i, edge(4), edge(5), edge(6);
    s.joints.resize(static_cast<int>(machine.joints().size()));
    for (int j = 0; j < s.joints.size(); ++j) s.joints[j] = edge(7 + j) * (1 + i % 11);
    s.pen_down = i % 2 == 1;
  }
  return samples;
}

TEST(SampleFilesText, CsvRowsAsPrintfWroteThem) {
  for (const char* machine_file : {"hektor.toml", "pen-plotter.toml", "hexapod-bit.toml"}) {
    SCOPED_TRACE(machine_file);
    const machine::Machine machine = test::load_example(machine_file);
    const io::SampleRows rows(machine);
    const fs::path path =
        fs::temp_directory_path() / ("pkm-text-rows-" + std::to_string(::getpid()) + ".csv");
    // More rows than one block of the file holds.
    const std::vector<motion::Sample> samples = edge_samples(machine, 3000);
    {
      auto file = io::SampleFile::open(path, machine);
      for (const motion::Sample& s : samples) file->write(s);
      file->commit();
    }
    const std::vector<std::string> written = csv_rows(path);
    fs::remove(path);
    ASSERT_EQ(written.size(), samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      double row[io::SampleRows::kMaxColumns];
      const std::size_t n = rows.fill(samples[i], row);
      ASSERT_EQ(written[i], legacy::csv_row(row, n, rows.pen())) << "row " << i;
    }
  }
}

TEST(SampleFilesText, NpyRecordsAreTheRowsBytes) {
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  const io::SampleRows rows(machine);
  const fs::path path =
      fs::temp_directory_path() / ("pkm-text-rows-" + std::to_string(::getpid()) + ".npy");
  const std::vector<motion::Sample> samples = edge_samples(machine, 5000);
  {
    auto file = io::SampleFile::open(path, machine);
    for (const motion::Sample& s : samples) file->write(s);
    file->commit();
  }
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  fs::remove(path);
  ASSERT_GT(bytes.size(), 10u);
  const std::size_t header =
      10 + static_cast<unsigned char>(bytes[8]) + 256u * static_cast<unsigned char>(bytes[9]);
  EXPECT_NE(bytes.substr(0, header).find("'shape': (                5000,), }"), std::string::npos);
  std::string expected;
  for (const motion::Sample& s : samples) {
    double row[io::SampleRows::kMaxColumns];
    const std::size_t n = rows.fill(s, row);
    expected.append(reinterpret_cast<const char*>(row), n * sizeof(double));
  }
  ASSERT_EQ(bytes.size(), header + expected.size());
  EXPECT_TRUE(bytes.compare(header, std::string::npos, expected) == 0);
}

}  // namespace
}  // namespace pkm
