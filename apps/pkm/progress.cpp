// The progress bar of long commands: see progress.hpp.
#include "progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace pkm::app {

namespace {

// Runs shorter than this show no bar at all: it would only flicker. PKM_PROGRESS_AFTER_MS sets
// another wait (the terminal test draws at once, however fast the machine runs its job).
std::chrono::milliseconds first_draw() {
  static const std::chrono::milliseconds wait = [] {
    const char* text = std::getenv("PKM_PROGRESS_AFTER_MS");
    const long ms = text != nullptr ? std::strtol(text, nullptr, 10) : 500;
    return std::chrono::milliseconds(std::clamp(ms, 0L, 60000L));
  }();
  return wait;
}
constexpr std::chrono::milliseconds kRedraw{100};
constexpr int kBarWidth = 30, kNarrowestBar = 10;

long lines_in(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return 0;
  char buffer[1 << 16];
  long lines = 0;
  char last = '\n';
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) {
    lines += std::count(buffer, buffer + n, '\n');
    last = buffer[n - 1];
  }
  std::fclose(file);
  return lines + (last == '\n' ? 0 : 1);  // a last line without its newline counts too
}

// Columns of the terminal on stderr (80 when it does not say): a bar wider than its line would
// wrap, and the carriage return would no longer take it back to its start.
int terminal_columns() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}

}  // namespace

ProgressBar::ProgressBar(std::string what, const std::string& file) : what_(std::move(what)) {
  if (::isatty(STDERR_FILENO) == 0) return;
  lines_ = lines_in(file);
  active_ = lines_ > 0;
  start_ = last_ = std::chrono::steady_clock::now();
}

ProgressBar::~ProgressBar() {
  clear();
}

std::function<void(int line)> ProgressBar::on_line() {
  if (!active_) return {};
  return [this](int line) { update(line); };
}

void ProgressBar::update(int line) {
  if (!active_) return;
  furthest_line_ = std::max(furthest_line_, line);
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < first_draw() || now - last_ < kRedraw) return;
  last_ = now;
  draw(furthest_line_, std::chrono::duration<double>(now - start_).count());
}

void ProgressBar::draw(int line, double elapsed_s) {
  const double fraction = std::min(1.0, static_cast<double>(line) / static_cast<double>(lines_));
  char numbers[96];
  std::snprintf(numbers, sizeof numbers, " %3.0f%%  line %d of %ld  %.1f s", 100.0 * fraction, line,
                lines_, elapsed_s);
  // Within the terminal's line: the bar narrows, then goes, then the name is cut at its end.
  const int room = std::max(terminal_columns() - 1, 20);
  std::string text = "pkm " + what_;
  const int bar =
      std::min(kBarWidth, room - static_cast<int>(text.size() + std::strlen(numbers)) - 3);
  if (bar >= kNarrowestBar) {
    const int filled = static_cast<int>(fraction * bar);
    text += " [" + std::string(static_cast<std::size_t>(filled), '=') +
            std::string(static_cast<std::size_t>(bar - filled), ' ') + "]";
  }
  text += numbers;
  if (static_cast<int>(text.size()) > room) {
    text = "pkm " +
           what_.substr(0, static_cast<std::size_t>(
                               std::max(0, room - 7 - static_cast<int>(std::strlen(numbers))))) +
           "..." + numbers;
    text = text.substr(0, static_cast<std::size_t>(room));
  }
  const int width = static_cast<int>(text.size());
  // A shorter line than the last leaves no characters of it behind.
  std::fprintf(stderr, "\r%s%*s", text.c_str(), std::max(0, drawn_width_ - width), "");
  drawn_width_ = std::max(width, drawn_width_);
  std::fflush(stderr);
}

void ProgressBar::clear() {
  if (drawn_width_ > 0) {
    std::fprintf(stderr, "\r%*s\r", drawn_width_, "");
    std::fflush(stderr);
  }
  drawn_width_ = 0;
  active_ = false;
}

StreamProgress::StreamProgress(std::string what) : what_(std::move(what)) {
  active_ = ::isatty(STDERR_FILENO) != 0;
  start_ = last_ = std::chrono::steady_clock::now();
}

StreamProgress::~StreamProgress() {
  clear();
}

void StreamProgress::start_program(double predicted_s) {
  program_start_ = std::chrono::steady_clock::now();
  predicted_s_ = predicted_s;
}

void StreamProgress::update(long sent, long answered, const std::string& state_and_position) {
  if (!active_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < first_draw() || now - last_ < kRedraw) return;
  last_ = now;
  char numbers[128];
  const double elapsed_s = std::chrono::duration<double>(now - start_).count();
  if (program_start_) {
    const double left_s =
        predicted_s_ - std::chrono::duration<double>(now - *program_start_).count();
    if (left_s >= 0.0) {
      std::snprintf(numbers, sizeof numbers, ": %ld lines sent, %ld done  about %.0f s left  ",
                    sent, answered, std::ceil(left_s));
    } else {
      std::snprintf(numbers, sizeof numbers,
                    ": %ld lines sent, %ld done  %.1f s (predicted %.0f)  ", sent, answered,
                    elapsed_s, std::ceil(predicted_s_));
    }
  } else {
    std::snprintf(numbers, sizeof numbers, ": %ld lines sent, %ld done  %.1f s  ", sent, answered,
                  elapsed_s);
  }
  std::string text = "pkm " + what_ + numbers + state_and_position;
  text = text.substr(0, static_cast<std::size_t>(std::max(terminal_columns() - 1, 20)));
  const int width = static_cast<int>(text.size());
  std::fprintf(stderr, "\r%s%*s", text.c_str(), std::max(0, drawn_width_ - width), "");
  drawn_width_ = std::max(width, drawn_width_);
  std::fflush(stderr);
}

void StreamProgress::clear() {
  if (drawn_width_ > 0) {
    std::fprintf(stderr, "\r%*s\r", drawn_width_, "");
    std::fflush(stderr);
  }
  drawn_width_ = 0;
}

}  // namespace pkm::app
