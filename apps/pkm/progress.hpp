// A progress bar on stderr for commands that work through a long file (plan, post, verify): the
// share of the file's lines done and the time elapsed, redrawn at most ten times a second and
// cleared at the end. Only on a terminal: on a pipe or a file the bar does nothing, and the
// library's line hook is left empty, so it costs nothing.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>

namespace pkm::app {

class ProgressBar {
 public:
  // `what` names the work ("post job.ngc"); `file` is the file whose lines are counted.
  ProgressBar(std::string what, const std::string& file);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // The hook for a library's `on_line` option: empty when no bar is shown.
  std::function<void(int line)> on_line();
  void update(int line);
  void clear();  // removes the bar; nothing is drawn after it

 private:
  void draw(int line, double elapsed_s);
  std::string what_;
  long lines_ = 0;
  int furthest_line_ = 0;  // loops and subroutines go back: the bar does not
  bool active_ = false;
  int drawn_width_ = 0;  // characters on the terminal's line now (0: nothing shown)
  std::chrono::steady_clock::time_point start_, last_;
};

// The line `pkm stream` keeps on stderr while it sends: lines sent and answered, the time left
// (from the controller's predicted time, when known; else the time elapsed), grbl's state, the
// tool's position. On a terminal only, like the bar.
class StreamProgress {
 public:
  explicit StreamProgress(std::string what);
  ~StreamProgress();
  StreamProgress(const StreamProgress&) = delete;
  StreamProgress& operator=(const StreamProgress&) = delete;

  bool active() const { return active_; }
  // The program starts now and is predicted to take `predicted_s` (s of this computer's clock):
  // the line shows the time left from here on.
  void start_program(double predicted_s);
  // `state_and_position` is what follows the counts ("Run  x 12.300 y -4.500 mm").
  void update(long sent, long answered, const std::string& state_and_position);
  void clear();

 private:
  std::string what_;
  bool active_ = false;
  int drawn_width_ = 0;
  std::chrono::steady_clock::time_point start_, last_;
  std::optional<std::chrono::steady_clock::time_point> program_start_;
  double predicted_s_ = 0.0;
};

}  // namespace pkm::app
