// RS274/NGC as LinuxCNC reads it, streamed: the program is read a line at a time (control flow
// seeks back in the file), and each canonical command goes to a sink as soon as it is made, so a
// program of any length runs in constant memory.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pkm/gcode/block.hpp"
#include "pkm/gcode/canon.hpp"
#include "pkm/gcode/line_source.hpp"  // kMaxLineBytes
#include "pkm/gcode/tool_table.hpp"

namespace pkm::gcode {

struct InterpreterOptions {
  std::optional<ToolTable> tool_table;  // without one, T words select tools with no offsets
  bool block_delete = false;            // skip lines starting with '/'
  // Where the machine is when the program starts, program coordinates in mm and deg (LinuxCNC
  // starts from the machine's position; rs274 from 0). Axes a program never names stay there.
  Position start_position{};
  // Lines handed on as they are, as an `event` with the trimmed line as its text, instead of being
  // interpreted: codes no rs274 dialect knows that a machine's controller takes (a plotter's pen
  // commands such as "M280 P0 S30"). A line is one of them when it equals one after trimming.
  std::vector<std::string> event_lines;
  // Bounds on the work one program may ask for (docs/gcode.md, "Bounds"): the iterations of one
  // loop (while, do, repeat), and of the whole program (every loop iteration, subroutine call
  // and canned-cycle hole or peck). Beyond either the program ends in an error naming the line.
  long max_loop_iterations = 100'000;
  long max_program_iterations = 1'000'000;
  // Directories where `o<name> call` looks for name.ngc (and M98 P100 for 100.ngc) when the
  // program does not define it, after the program's own directory, in this order.
  std::vector<std::filesystem::path> subroutine_path;
  // LinuxCNC's [RS274NGC] ORIENT_OFFSET, deg: added to M19's R (the spindle's orientation).
  double orient_offset_deg = 0.0;
  // When not empty, every probing move (G38.2-G38.5) is refused at its column with this reason:
  // `pkm post`'s joint program cannot stop on contact (docs/post.md, "Probing").
  std::string probe_refusal;
};

// The deepest subroutine calls nest: LinuxCNC's 10 levels, the main program one of them.
inline constexpr std::size_t kMaxCallDepth = 9;
// The most subroutine files one program may open (each holds a file handle and a buffer).
inline constexpr std::size_t kMaxSubroutineFiles = 256;

struct Warning {
  int line = 0;
  std::string message;
};

using CanonSink = std::function<void(const Canon&)>;

// A progress hook called once per source line that canonical commands come from (a long run's
// bar): the commands of one line reach it once, not once each. An empty hook costs a test.
class LineProgress {
 public:
  explicit LineProgress(const std::function<void(int line)>& on_line) : on_line_(on_line) {}
  void see(int line) {
    if (on_line_ && line != line_) {
      line_ = line;
      on_line_(line);
    }
  }

 private:
  const std::function<void(int line)>& on_line_;
  int line_ = 0;
};

class Interpreter {
 public:
  Interpreter(std::filesystem::path program, InterpreterOptions options = {});
  ~Interpreter();
  Interpreter(const Interpreter&) = delete;
  Interpreter& operator=(const Interpreter&) = delete;

  // Runs the program to its end, handing every canonical command to `sink`. Throws GcodeError
  // (file:line:column) at the first error; what was handed on before it stands.
  void run(const CanonSink& sink);
  // The same a line at a time, for a reader that pulls commands as it needs them: start() once,
  // then each step() executes the next line (handing its commands to `sink`, which must outlive
  // the steps) and returns false once the program has ended. run() is start() and every step().
  void start(const CanonSink& sink);
  bool step();

  const std::vector<Warning>& warnings() const { return warnings_; }
  // The program and every subroutine file it has opened so far: the inputs an output written
  // from it must not replace.
  std::vector<std::filesystem::path> files_read() const;

 private:
  struct State;
  std::filesystem::path program_;
  InterpreterOptions options_;
  std::unique_ptr<State> state_;
  std::vector<Warning> warnings_;
};

}  // namespace pkm::gcode
