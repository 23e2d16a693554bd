// The text outputs of issue 16, each beside the way it was written before (tests/
// legacy_text_formats.hpp): `pkm gcode --canon`'s formatting per command and over a whole real
// program (interpreting included, nothing written), and `pkm plan`'s sample files (CSV, NPY) in
// samples/s. The whole-command ratio against LinuxCNC's rs274 is bench/canon_vs_rs274.sh.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "legacy_text_formats.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/io/sample_files.hpp"
#include "pkm/io/sample_rows.hpp"
#include "pkm/text/decimal_text.hpp"

namespace {

const std::filesystem::path kSource = PKM_SOURCE_DIR;
const std::filesystem::path kProgram =
    kSource.parent_path() / "shared" / "gcode" / "real" / "linuxcnc" / "stellabee1.ngc";

std::vector<pkm::gcode::Canon> stellabee_commands() {
  std::vector<pkm::gcode::Canon> commands;
  pkm::gcode::Interpreter interpreter(kProgram);
  interpreter.run([&](const pkm::gcode::Canon& canon) { commands.push_back(canon); });
  return commands;
}

// Formatting alone, items = commands: every command of stellabee1.ngc (169k lines, mostly
// STRAIGHT_FEED and ARC_FEED) as a line of `pkm gcode --canon`.
void canon_per_command(benchmark::State& state, bool legacy) {
  if (!std::filesystem::exists(kProgram)) {
    state.SkipWithError("../shared/gcode/real/linuxcnc/stellabee1.ngc not found");
    return;
  }
  const std::vector<pkm::gcode::Canon> commands = stellabee_commands();
  pkm::text::TextBuffer out(1 << 17);
  std::string legacy_out;
  long bytes = 0;
  for (auto _ : state) {
    int sequence = 0;
    for (const pkm::gcode::Canon& canon : commands) {
      if (legacy) {
        legacy_out =
            pkm::legacy::canon_line(++sequence, canon.n_label, pkm::legacy::canon_text(canon));
        bytes += static_cast<long>(legacy_out.size());
        continue;
      }
      pkm::gcode::append_canon_line_start(++sequence, canon.n_label, out);
      pkm::gcode::append_canon_text(canon, out);
      out.push_back('\n');
      if (out.size() >= (1 << 16)) {
        bytes += static_cast<long>(out.size());
        benchmark::DoNotOptimize(out.view().data());
        out.clear();
      }
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(commands.size()));
  state.counters["bytes"] = static_cast<double>(bytes);
}
BENCHMARK_CAPTURE(canon_per_command, snprintf_before, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(canon_per_command, to_text_now, false)->Unit(benchmark::kMillisecond);

// The whole of `pkm gcode --canon` but the process and the write: interpret stellabee1.ngc and
// format each command as it comes. items = commands.
void canon_whole_file(benchmark::State& state, bool legacy) {
  if (!std::filesystem::exists(kProgram)) {
    state.SkipWithError("../shared/gcode/real/linuxcnc/stellabee1.ngc not found");
    return;
  }
  pkm::text::TextBuffer out(1 << 17);
  std::string legacy_out;
  long commands = 0;
  for (auto _ : state) {
    int sequence = 0;
    pkm::gcode::Interpreter interpreter(kProgram);
    interpreter.run([&](const pkm::gcode::Canon& canon) {
      ++commands;
      if (legacy) {
        legacy_out =
            pkm::legacy::canon_line(++sequence, canon.n_label, pkm::legacy::canon_text(canon));
        return;
      }
      pkm::gcode::append_canon_line_start(++sequence, canon.n_label, out);
      pkm::gcode::append_canon_text(canon, out);
      out.push_back('\n');
      if (out.size() >= (1 << 16)) out.clear();
    });
  }
  state.SetItemsProcessed(commands);
}
BENCHMARK_CAPTURE(canon_whole_file, snprintf_before, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(canon_whole_file, to_text_now, false)->Unit(benchmark::kMillisecond);

// One number as %.4f / %.9f, over values spread as a job's coordinates are. items = numbers.
template <int Decimals>
void fixed_number(benchmark::State& state) {
  std::vector<double> values(4096);
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = 1234.5678 * std::sin(0.37 * static_cast<double>(i));
  }
  char digits[pkm::text::kMaxFixedChars];
  const bool legacy = state.range(0) != 0;
  const char* pattern = Decimals == 4 ? "%.4f" : "%.9f";
  for (auto _ : state) {
    for (const double value : values) {
      if (legacy) {
        benchmark::DoNotOptimize(std::snprintf(digits, sizeof digits, pattern, value));
      } else {
        benchmark::DoNotOptimize(pkm::text::write_fixed<Decimals>(digits, value));
      }
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(values.size()));
}
BENCHMARK(fixed_number<4>)->ArgName("snprintf")->Arg(1)->Arg(0);
BENCHMARK(fixed_number<9>)->ArgName("snprintf")->Arg(1)->Arg(0);

// The samples of a slow circle on the paper's hexapod (t, line, x y z a b c, six legs: 14
// columns).
std::vector<pkm::motion::Sample> circle_samples() {
  std::vector<pkm::motion::Sample> samples(1000);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double angle = 0.001 * static_cast<double>(i);
    pkm::motion::Sample& s = samples[i];
    s.line = 12 + static_cast<int>(i / 100);
    s.pose << 50.0 * std::cos(angle), 50.0 * std::sin(angle), 1000.0 - 0.01 * angle, 0.0,
        0.02 * angle, -0.01;
    s.joints.resize(6);
    for (int j = 0; j < 6; ++j) s.joints[j] = 1060.531484 + 3.0 * std::sin(angle + j);
  }
  return samples;
}

// Where the samples go: a file in the temporary directory (range(0) != 0: the disk's part
// included), or a link named .csv/.npy to /dev/null, which the file writes in place (the
// formatting and the write calls alone).
std::filesystem::path sample_output(const benchmark::State& state, const char* extension) {
  const bool to_disk = state.range(0) != 0;
  const std::filesystem::path output =
      std::filesystem::temp_directory_path() /
      ((to_disk ? "pkm-bench-samples" : "pkm-bench-null") + std::string(extension));
  if (!to_disk && !std::filesystem::is_symlink(output)) {
    std::filesystem::create_symlink("/dev/null", output);
  }
  return output;
}

constexpr int kSamplesPerFile = 100000;

// pkm::io::SampleFile as `pkm plan -o` writes it. items = samples.
void sample_file(benchmark::State& state, const char* extension) {
  const pkm::machine::Machine machine =
      pkm::machine::load_machine(kSource / "examples" / "machines" / "hexapod-bit.toml");
  const std::filesystem::path output = sample_output(state, extension);
  std::vector<pkm::motion::Sample> samples = circle_samples();
  for (auto _ : state) {
    auto file = pkm::io::SampleFile::open(output, machine);
    for (int i = 0; i < kSamplesPerFile; ++i) {
      pkm::motion::Sample& s = samples[static_cast<std::size_t>(i) % samples.size()];
      s.time_s = 0.001 * i;
      file->write(s);
    }
    file->commit();
  }
  std::filesystem::remove(output);
  state.SetItemsProcessed(state.iterations() * kSamplesPerFile);
}
BENCHMARK_CAPTURE(sample_file, csv, ".csv")
    ->ArgName("disk")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(sample_file, npy, ".npy")
    ->ArgName("disk")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);

// The same rows written as before issue 16: fprintf per CSV value, an fwrite per NPY row, to a
// plain stream (no header, no temporary and rename: a little less work than the file above).
void sample_file_before(benchmark::State& state, const char* extension) {
  const pkm::machine::Machine machine =
      pkm::machine::load_machine(kSource / "examples" / "machines" / "hexapod-bit.toml");
  const pkm::io::SampleRows rows(machine);
  const bool csv = std::string(extension) == ".csv";
  const std::filesystem::path output = sample_output(state, extension);
  std::vector<pkm::motion::Sample> samples = circle_samples();
  for (auto _ : state) {
    std::FILE* file = std::fopen(output.c_str(), "wb");
    for (int i = 0; i < kSamplesPerFile; ++i) {
      pkm::motion::Sample& s = samples[static_cast<std::size_t>(i) % samples.size()];
      s.time_s = 0.001 * i;
      double row[pkm::io::SampleRows::kMaxColumns];
      const std::size_t n = rows.fill(s, row);
      if (csv) {
        pkm::legacy::write_csv_row(file, row, n, rows.pen());
      } else {
        std::fwrite(row, sizeof(double), n, file);
      }
    }
    std::fflush(file);
    if (state.range(0) != 0) ::fsync(::fileno(file));  // as the file's commit does
    std::fclose(file);
  }
  std::filesystem::remove(output);
  state.SetItemsProcessed(state.iterations() * kSamplesPerFile);
}
BENCHMARK_CAPTURE(sample_file_before, csv, ".csv")
    ->ArgName("disk")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(sample_file_before, npy, ".npy")
    ->ArgName("disk")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
