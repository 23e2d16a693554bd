#include "pkm/gcode/interpreter.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "pkm/gcode/cutter_compensation.hpp"
#include "pkm/gcode/gcode_error.hpp"

namespace pkm::gcode {

namespace {

constexpr double kMmPerInch = 25.4;
// Tool numbers (T, H, D, M61 Q, G10 P) in magnitude: as a tool table holds them (tool_table.cpp).
constexpr double kMaxToolNumber = 1e6;
// The most turns a G2/G3 P word may ask for.
constexpr double kMaxArcTurns = 1e6;
constexpr int kX = 0, kY = 1, kZ = 2;

// The axis letters in Position order, the word slots (Block::words) they use, and the axis of
// each slot (-1: not an axis). The polar words @ and ^ use the slots of G and M.
constexpr char kAxisLetters[kAxes] = {'x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w'};
constexpr std::uint32_t kAxisSlots = [] {
  std::uint32_t mask = 0;
  for (const char letter : kAxisLetters) mask |= 1u << (letter - 'a');
  return mask;
}();
constexpr std::array<int, 26> kAxisOfSlot = [] {
  std::array<int, 26> axis_of{};
  axis_of.fill(-1);
  for (int axis = 0; axis < kAxes; ++axis) axis_of[kAxisLetters[axis] - 'a'] = axis;
  return axis_of;
}();
constexpr std::uint32_t kPolarSlots = (1u << ('g' - 'a')) | (1u << ('m' - 'a'));

// Codes times ten, by modal group; a block may hold at most one code of each group.
int g_group(int code) {
  switch (code) {
    case 0:
    case 10:
    case 20:
    case 30:
    case 330:
    case 331:
    case 760:
    case 730:
    case 800:
    case 810:
    case 820:
    case 830:
    case 840:
    case 850:
    case 860:
    case 870:
    case 880:
    case 890:
    case 382:
    case 383:
    case 384:
    case 385:
      return 1;
    case 40:
    case 100:
    case 280:
    case 281:
    case 300:
    case 301:
    case 530:
    case 920:
    case 921:
    case 922:
    case 923:
      return 0;
    case 170:
    case 180:
    case 190:
      return 2;
    case 900:
    case 910:
      return 3;
    case 901:
    case 911:
      return 4;
    case 930:
    case 940:
    case 950:
      return 5;
    case 200:
    case 210:
      return 6;
    case 400:
    case 410:
    case 411:
    case 420:
    case 421:
      return 7;
    case 430:
    case 431:
    case 432:
    case 490:
      return 8;
    case 980:
    case 990:
      return 10;
    case 540:
    case 550:
    case 560:
    case 570:
    case 580:
    case 590:
    case 591:
    case 592:
    case 593:
      return 12;
    case 610:
    case 611:
    case 640:
      return 13;
    case 960:
    case 970:
      return 14;
    case 70:
    case 80:
      return 15;
    default:
      return -1;
  }
}

int m_group(int code) {
  switch (code) {
    case 0:
    case 10:
    case 20:
    case 300:
    case 600:
      return 4;
    case 60:
    case 610:
      return 6;
    case 30:
    case 40:
    case 50:
    case 190:
      return 7;
    case 70:
    case 80:
    case 90:
      return 8;
    case 480:
    case 490:
    case 500:
    case 510:
    case 520:
    case 530:
      return 9;
    case 620:
    case 630:
    case 640:
    case 650:
    case 660:
    case 670:
    case 680:
      return 5;
    default:
      return code >= 1000 && code <= 1990 ? 10 : -1;
  }
}

// The codes of one block by modal group. One instance serves every block: starting a block
// clears a mask, not the slots (most blocks hold no code at all).
template <std::size_t Groups>
class CodesByGroup {
 public:
  const Code* operator[](int group) const {
    return (present_ >> group) & 1u ? &codes_[static_cast<std::size_t>(group)] : nullptr;
  }
  void set(int group, const Code& code) {
    codes_[static_cast<std::size_t>(group)] = code;
    present_ |= 1u << group;
  }
  void clear() { present_ = 0; }
  bool any() const { return present_ != 0; }

 private:
  static_assert(Groups <= 32);
  std::array<Code, Groups> codes_{};
  std::uint32_t present_ = 0;
};

std::string code_name(char letter, int tenths) {
  std::string name(1, letter);
  name += std::to_string(tenths / 10);
  if (tenths % 10 != 0) name += "." + std::to_string(tenths % 10);
  return name;
}

bool is_linear(int axis) {
  return axis < 3 || axis >= 6;
}

// "cannot open (reason)" for a program that did not open, or opened as a directory (which
// fopen allows and the first read refuses).
std::string cannot_open_reason(const std::filesystem::path& path, bool opened) {
  const int error = errno;
  std::error_code ignored;
  if (opened || std::filesystem::is_directory(path, ignored)) {
    return "cannot open (it is a directory)";
  }
  return std::string("cannot open (") + std::strerror(error) + ")";
}

// The program's lines, cut from large reads of the file. Control flow jumps back and forth; a
// jump into what was last read costs nothing, any other seeks.
class LineSource {
 public:
  explicit LineSource(const std::filesystem::path& path) : file_(std::fopen(path.c_str(), "rb")) {}
  bool is_open() const { return file_ != nullptr; }
  // A read or seek failed (read() then returned nothing, as at the end of the file).
  bool failed() const { return failed_; }
  // The line read was longer than kMaxLineBytes (read() then returned nothing, and failed()).
  bool too_long() const { return too_long_; }

  // The line starting at byte `offset`, without its "\n" or "\r\n", as a view into the
  // buffer with a NUL after it (what the block reader needs); valid until the next read.
  // Returns it and the offset of the line after it, or nothing at the end of the file.
  std::optional<std::pair<std::string_view, std::int64_t>> read(std::int64_t offset) {
    if (patched_ != nullptr) {
      // The previous line's NUL stood on its line end; a jump back must find that again.
      *patched_ = patched_character_;
      patched_ = nullptr;
    }
    if (offset < buffer_offset_ || offset > buffer_offset_ + static_cast<std::int64_t>(filled_)) {
      if (::fseeko(file_.get(), static_cast<off_t>(offset), SEEK_SET) != 0) {
        failed_ = true;
        return std::nullopt;
      }
      buffer_offset_ = offset;
      filled_ = 0;
      at_end_ = false;
    }
    std::size_t begin = static_cast<std::size_t>(offset - buffer_offset_);
    while (true) {
      char* start = buffer_.data() + begin;
      const std::size_t available = filled_ - begin;
      char* newline = static_cast<char*>(std::memchr(start, '\n', available));
      if (newline != nullptr || at_end_) {
        if (newline == nullptr && available == 0) return std::nullopt;
        std::size_t length =
            newline != nullptr ? static_cast<std::size_t>(newline - start) : available;
        const std::int64_t following =
            offset + static_cast<std::int64_t>(length + (newline != nullptr ? 1 : 0));
        if (length > 0 && start[length - 1] == '\r') --length;
        // The buffer always has a byte to spare after what was read: the NUL fits.
        patched_ = start + length;
        patched_character_ = *patched_;
        *patched_ = '\0';
        return std::pair{std::string_view(start, length), following};
      }
      // Keep the unfinished line at the front and read on (a longer line grows the buffer).
      // The file stays positioned at buffer_offset_ + filled_.
      std::memmove(buffer_.data(), start, available);
      buffer_offset_ += static_cast<std::int64_t>(begin);
      filled_ = available;
      begin = 0;
      if (filled_ + 1 >= buffer_.size()) {
        // The buffer holds at most kMaxLineBytes + 2: a line that fills it is too long, and any
        // line found in it is short enough without a test on the way.
        if (buffer_.size() >= kMaxLineBytes + 2) {
          too_long_ = failed_ = true;
          return std::nullopt;
        }
        buffer_.resize(std::min(2 * buffer_.size(), kMaxLineBytes + 2));
      }
      const std::size_t count =
          std::fread(buffer_.data() + filled_, 1, buffer_.size() - 1 - filled_, file_.get());
      filled_ += count;
      at_end_ = count == 0;
      if (at_end_ && std::ferror(file_.get()) != 0) {
        failed_ = true;
        return std::nullopt;
      }
    }
  }

 private:
  struct Close {
    void operator()(std::FILE* file) const { std::fclose(file); }
  };
  std::unique_ptr<std::FILE, Close> file_;
  std::vector<char> buffer_ = std::vector<char>(std::size_t{1} << 16);
  std::int64_t buffer_offset_ = 0;  // the file offset of buffer_[0]
  std::size_t filled_ = 0;          // bytes of buffer_ read from the file
  bool at_end_ = false;             // the file ends after them
  char* patched_ = nullptr;         // where the last line's NUL stands
  char patched_character_ = 0;      // and what stood there
  bool failed_ = false;
  bool too_long_ = false;
};

}  // namespace

struct Interpreter::State {
  struct Mark {
    std::int64_t position = 0;  // byte offset in the file
    int line = 0;
  };

  // The source, read a line at a time.
  LineSource source;
  std::string file_name;
  Mark next{0, 1};
  Mark current;  // the line being executed

  const InterpreterOptions& options;
  std::vector<Warning>& warnings;
  const CanonSink* sink = nullptr;
  CanonSink checked_sink;  // `sink` behind all_finite: what compensation hands commands to
  Parameters parameters;

  // Modal state. Lengths are in program units (those of G20/G21) where they are program
  // coordinates, in mm where they are offsets kept for the machine.
  LengthUnits units = LengthUnits::mm;
  Plane plane = Plane::xy;
  bool absolute = true;
  bool arc_absolute = false;
  FeedMode feed_mode = FeedMode::units_per_minute;
  double feed = 0.0;
  double speed = 0.0;
  int motion = 0;               // G code times ten of the active motion mode, -1 after G80
  bool retract_to_old = false;  // G99 (retract to R) until G98, as LinuxCNC starts
  Position pos{};               // program coordinates
  int coord_system = 1;
  Position g92_mm{};
  Position tool_offset_mm{};
  int tool_in_spindle = 0;
  int selected_tool = 0;
  int path_mode = 64;
  double path_tolerance = 0.0;
  // G41/G42: moves go through it, and every other command too (it holds them behind a move
  // whose end the next move settles). `pos` stays the programmed point.
  CutterCompensation compensation;
  bool straight_exit = false;  // offset moves ended at G40: the next move must be straight
  int move_column = 1;         // where the block's motion is, for errors found making it
  // After G40 the tool stays off the programmed point until the next move. A tool change
  // takes the machine's position as the program's (LinuxCNC re-reads it), so it matters then.
  std::optional<Position> tool_off_path;

  // Canned cycles: sticky words and the level the current series started from.
  double cycle_r = 0.0, cycle_z = 0.0;  // mm
  double cycle_q = 0.0, cycle_p = 0.0;
  double cycle_old_cc = 0.0;
  bool cycle_series = false;
  bool motion_changed = false;  // this block changes the motion mode

  // Control flow.
  struct Frame {
    enum class Type {
      if_,
      while_,
      do_,
      repeat,
    } type;
    std::string label;
    Mark start;           // the line that opened the frame
    long remaining = 0;   // repeat count
    bool taken = false;   // an if branch already ran
    long iterations = 0;  // times the loop went round (bounded by max_loop_iterations)
  };
  std::vector<Frame> flow;
  struct Call {
    std::string label;
    Mark return_to;
    std::size_t flow_depth;
  };
  std::vector<Call> calls;
  std::map<std::string, Mark> subroutines;
  Block block_;  // the line being executed; one block's storage serves every line
  Canon move_;   // see next_move()
  CodesByGroup<16> g_by_group;
  CodesByGroup<12> m_by_group;  // 11: M7 and M8 on one line
  long program_iterations = 0;  // bounded by max_program_iterations
  bool percent_program = false;
  bool first_content = true;  // no line with content read yet
  bool ended = false;
  bool saw_end = false;

  State(const std::filesystem::path& path, const InterpreterOptions& opts,
        std::vector<Warning>& warns)
      : source(path), file_name(path.string()), options(opts), warnings(warns) {
    if (!source.is_open()) throw GcodeError(file_name, 0, 0, cannot_open_reason(path, false));
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) {
      throw GcodeError(file_name, 0, 0, cannot_open_reason(path, true));
    }
    // G54 offsets start at zero; #5220 holds the active coordinate system.
    parameters.set_numbered(5220, 1.0);
    pos = options.start_position;
  }

  // ---- source -------------------------------------------------------------------------
  // The next line into `line`, a view valid until the next read.
  // Inlined: it is on the path of every line (the compiler stopped inlining it on its own).
  [[gnu::always_inline]] bool read_line(std::string_view& line) {
    current = next;
    const auto read = source.read(next.position);
    if (!read) {
      if (source.failed()) cannot_read();
      return false;
    }
    line = read->first;
    next = {read->second, current.line + 1};
    return true;
  }
  [[noreturn, gnu::cold, gnu::noinline]] void cannot_read() const {
    if (source.too_long()) {
      fail(0, "line longer than " + std::to_string(kMaxLineBytes) +
                  " bytes, the longest the interpreter reads");
    }
    fail(0, "cannot read the program");
  }
  void jump(const Mark& mark) { next = mark; }
  Mark after(const Mark& mark) {
    const Mark saved_next = next, saved_current = current;
    jump(mark);
    std::string_view ignored;
    read_line(ignored);
    const Mark result = next;
    jump(saved_next);
    current = saved_current;
    return result;
  }

  [[noreturn]] void fail(int column, const std::string& message) const {
    throw GcodeError(file_name, current.line, column, message);
  }
  void warn(const std::string& message) { warnings.push_back({current.line, message}); }

  // ---- units ----------------------------------------------------------------------------
  double to_mm(double value) const {
    return units == LengthUnits::inch ? value * kMmPerInch : value;
  }
  double from_mm(double value) const {
    return units == LengthUnits::inch ? value / kMmPerInch : value;
  }
  double axis_from_mm(int axis, double value) const {
    return is_linear(axis) ? from_mm(value) : value;
  }
  double axis_to_mm(int axis, double value) const { return is_linear(axis) ? to_mm(value) : value; }

  Position g5x_mm(int system) const {
    Position offset{};
    for (int axis = 0; axis < kAxes; ++axis) {
      offset[axis] = parameters.numbered(5201 + 20 * system + axis);
    }
    return offset;
  }
  // Everything between program and machine coordinates, mm.
  Position total_offset_mm() const {
    const Position g5x = g5x_mm(coord_system);
    Position total{};
    for (int axis = 0; axis < kAxes; ++axis) {
      total[axis] = g5x[axis] + g92_mm[axis] + tool_offset_mm[axis];
    }
    return total;
  }

  // ---- output ---------------------------------------------------------------------------
  Canon make(CanonKind kind, const Block& block) const {
    Canon c;
    c.kind = kind;
    c.line = current.line;
    c.n_label = block.n_label;
    c.units = units;
    c.plane = plane;
    c.end = pos;
    return c;
  }
  // The move being made: one Canon serves every move, keeping its strings' storage.
  Canon& next_move(CanonKind kind, const Block& block) {
    move_.kind = kind;
    move_.line = current.line;
    if (block.n_label.empty()) {
      move_.n_label.clear();  // most lines have no N word: no call into the string's assign
    } else {
      move_.n_label = block.n_label;
    }
    move_.units = units;
    move_.plane = plane;
    // Moves set value and feed_mode themselves and never value2, integer or text.
    move_.center = {};
    move_.turns = 0;
    return move_;
  }
  void emit(const Canon& canon) {
    // Behind held moves a command waits in compensation, whose output checked_sink checks.
    if (compensation.holding()) return compensation.pass(canon);
    if (!all_finite(canon)) not_finite(canon);
    (*sink)(canon);
  }
  void emit(CanonKind kind, const Block& block) { emit(make(kind, block)); }
  void dwell(const Block& block, double seconds) {
    Canon c = make(CanonKind::dwell, block);
    c.value = seconds;
    emit(c);
  }
  void emit_offsets(const Block& block) {
    Canon g5x = make(CanonKind::g5x_offset, block);
    g5x.integer = coord_system;
    const Position offset = g5x_mm(coord_system);
    for (int axis = 0; axis < kAxes; ++axis) g5x.end[axis] = axis_from_mm(axis, offset[axis]);
    emit(g5x);
    Canon g92 = make(CanonKind::g92_offset, block);
    for (int axis = 0; axis < kAxes; ++axis) g92.end[axis] = axis_from_mm(axis, g92_mm[axis]);
    emit(g92);
  }

  // Moves the program position so the machine position stays put when offsets change.
  void reexpress(const Position& old_total_mm) {
    const Position now = total_offset_mm();
    for (int axis = 0; axis < kAxes; ++axis) {
      pos[axis] += axis_from_mm(axis, old_total_mm[axis] - now[axis]);
    }
  }

  void start(const CanonSink& output);
  void run(const CanonSink& output);
  bool step();
  // The next line to execute (blank lines and the opening '%' skipped); false at the end.
  bool next_line(std::string_view& line);
  void execute(std::string_view line) {
    if (!options.event_lines.empty() && is_event_line(line)) return;
    execute_line(line);
  }
  // After the last line: the program end a file without M2, M30 or '%' lacks.
  void finish();
  bool is_event_line(std::string_view line);
  void execute_line(std::string_view line);
  void apply_assignments(const Block& block);
  void execute_o_word(const Block& block);
  // Bounds (docs/gcode.md): one more round of `loop`, one more unit of the program's work.
  void count_loop_iteration(Frame& loop, int column);
  void count_program_iteration(int column);
  void require_call_depth(const OWord& o) const;
  // A word that must hold a number in [low, high] before it is converted to an integer.
  void require_word_in_range(const Block& block, char letter, double low, double high,
                             const std::string& what) const;
  // Words no code of the block uses are refused, as rs274 refuses them.
  void refuse_unused_words(const Block& block) const;
  // Every value handed to the sink is finite: all_finite on each (inline, every command passes
  // it), not_finite refusing one that is not.
  static bool all_finite(const Canon& canon) {
    // x * 0 is 0 for a finite x and NaN otherwise: one test for all, no branch per number.
    double probe =
        canon.value * 0.0 + canon.value2 * 0.0 + canon.center[0] * 0.0 + canon.center[1] * 0.0;
    for (const double value : canon.end) probe += value * 0.0;
    return probe == 0.0;
  }
  [[noreturn, gnu::cold, gnu::noinline]] void not_finite(const Canon& canon) const;
  void require_finite_tool(const ToolEntry& entry, int column) const {
    bool finite = std::isfinite(entry.diameter);
    for (const double value : entry.offset) finite = finite && std::isfinite(value);
    if (!finite) fail(column, "calculation resulted in infinity or NaN (a tool offset too large)");
  }

  void execute_block(const Block& block);
  void skip_to(const std::string& label, std::initializer_list<std::string_view> keywords,
               std::string* found_keyword, int column);
  Mark find_subroutine(const std::string& label, int column);
  // Where the block's axis words lead, into `end` (the current point where a word is missing).
  void target(const Block& block, bool machine_coordinates, Position& end) const;
  Position target(const Block& block, bool machine_coordinates) const {
    Position end;
    target(block, machine_coordinates, end);
    return end;
  }
  void straight(CanonKind kind, const Block& block, const Position& end);
  // Runs `action` on cutter compensation; a path it refuses is an error at `column`.
  template <class Action>
  void compensating(int column, Action&& action) {
    try {
      action();
    } catch (const CompensationError& error) {
      fail(column, error.what());
    }
  }
  // Hands a move on, through cutter compensation (made by `compensate`, from the programmed
  // point `pos`) when that offsets moves, and makes its end the programmed point.
  void send_move(const Canon& move,
                 void (CutterCompensation::*compensate)(Canon, const Position&)) {
    tool_off_path.reset();
    if (compensation.offsetting()) {
      compensating(move_column, [&] { (compensation.*compensate)(move, pos); });
    } else {
      emit(move);
    }
    pos = move.end;
  }
  void start_compensation(const Block& block, const Code& code);
  // Held commands go out (program stops and ends): the last offset move ends where the tool is.
  void release_compensation(int column) {
    compensating(column, [&] { compensation.flush(); });
  }
  // Codes LinuxCNC refuses while compensation is on: they would move the path under it.
  void refuse_with_compensation(const Code& code, const std::string& what) const {
    if (compensation.on()) {
      fail(code.column, "cannot " + what + " with cutter radius compensation on (G40 first)");
    }
  }
  void arc(const Block& block, int code, const Position& end);
  void cycle(const Block& block, int code, const Position& end);
  void go_home(const Block& block, int code);
  void set_coordinates(const Block& block);
  void require_feed(const Block& block, int column) const {
    if (feed_mode == FeedMode::inverse_time ? !block.has('f') : !(feed > 0.0)) missing_feed(column);
  }
  [[noreturn, gnu::cold, gnu::noinline]] void missing_feed(int column) const;
};

void Interpreter::State::start(const CanonSink& output) {
  sink = &output;
  checked_sink = [this](const Canon& canon) {
    if (!all_finite(canon)) not_finite(canon);
    (*sink)(canon);
  };
  compensation.reset(checked_sink);
}

void Interpreter::State::run(const CanonSink& output) {
  start(output);
  std::string_view line;
  while (next_line(line)) execute(line);
  finish();
}

bool Interpreter::State::step() {
  std::string_view line;
  if (next_line(line)) {
    execute(line);
    return true;
  }
  finish();
  return false;
}

bool Interpreter::State::next_line(std::string_view& line) {
  while (!ended && read_line(line)) {
    if (first_content) {
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos) continue;
      first_content = false;
      if (line[first] == '%') {
        percent_program = true;
        continue;
      }
    }
    return true;
  }
  return false;
}

void Interpreter::State::finish() {
  if (!ended && !saw_end) {
    // The moves compensation still holds are part of the program (rs274 would drop them).
    release_compensation(1);
    warnings.push_back({current.line,
                        "program has no M2, M30 or closing %: ended at the end of "
                        "the file"});
    Block none;
    emit(CanonKind::program_end, none);
  }
  ended = true;
}

bool Interpreter::State::is_event_line(std::string_view line) {
  const auto first = line.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return false;
  const std::string_view trimmed = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
  for (const std::string& event_line : options.event_lines) {
    if (trimmed != event_line) continue;
    Canon event = make(CanonKind::event, Block{});
    event.text = std::string(trimmed);
    emit(event);
    return true;
  }
  return false;
}

void Interpreter::State::execute_line(std::string_view line) {
  Block& block = block_;
  // #5420..#5428: the current position in the active coordinate system, offsets included, in
  // program units, as LinuxCNC gives them to a line that reads them (pkm home's programs do).
  for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5420 + axis, pos[axis]);
  try {
    read_block(line, parameters, block);
  } catch (const SyntaxError& error) {
    fail(error.column, error.message);
  }
  if (block.percent) {
    if (percent_program) {
      saw_end = true;
      ended = true;
      release_compensation(1);
      Block none;
      emit(CanonKind::program_end, none);
      return;
    }
    fail(1, "'%' only opens and closes a program");
  }
  if (block.block_delete && options.block_delete) return;
  if (block.o_word) {
    execute_o_word(block);
    return;
  }
  execute_block(block);
}

void Interpreter::State::skip_to(const std::string& label,
                                 std::initializer_list<std::string_view> keywords,
                                 std::string* found_keyword, int column) {
  const int start_line = current.line;
  std::string_view line;
  while (read_line(line)) {
    std::string found_label;
    const std::string keyword = o_word_keyword(line, &found_label);
    if (keyword.empty() || found_label != label) continue;
    for (const std::string_view wanted : keywords) {
      if (keyword == wanted) {
        if (found_keyword != nullptr) *found_keyword = keyword;
        return;
      }
    }
  }
  std::string names;
  for (const std::string_view k : keywords) names += (names.empty() ? "" : "/") + std::string(k);
  throw GcodeError(file_name, start_line, column, "o" + label + ": no matching " + names);
}

Interpreter::State::Mark Interpreter::State::find_subroutine(const std::string& label, int column) {
  const auto known = subroutines.find(label);
  if (known != subroutines.end()) return known->second;
  // Not yet seen: look for its definition further on, then come back.
  const Mark saved_next = next, saved_current = current;
  std::string_view line;
  while (read_line(line)) {
    std::string found;
    if (o_word_keyword(line, &found) == "sub") {
      subroutines.emplace(found, current);
      if (found == label) {
        jump(saved_next);
        current = saved_current;
        return subroutines[label];
      }
    }
  }
  jump(saved_next);
  current = saved_current;
  fail(column, "unknown subroutine o" + label);
}

// Parameters set on a line take effect before it runs, with every value read before them.
void Interpreter::State::apply_assignments(const Block& block) {
  for (const Assignment& a : block.assignments) {
    if (a.name.empty()) {
      parameters.set_numbered(a.number, a.value);
    } else {
      parameters.set_named(a.name, a.value);
    }
  }
}

void Interpreter::State::execute_o_word(const Block& block) {
  apply_assignments(block);  // LinuxCNC programs set none on O-word lines in practice
  const OWord& o = *block.o_word;
  const auto value_of = [&]() {
    if (!o.value) fail(o.column, "o" + o.label + " " + o.keyword + " needs a [value]");
    return *o.value;
  };
  if (o.keyword == "sub") {
    subroutines.emplace(o.label, current);
    skip_to(o.label, {"endsub"}, nullptr, o.column);
  } else if (o.keyword == "call") {
    const Mark sub = find_subroutine(o.label, o.column);
    require_call_depth(o);
    count_program_iteration(o.column);
    calls.push_back({o.label, next, flow.size()});
    parameters.push_scope(o.arguments);
    jump(after(sub));
  } else if (o.keyword == "endsub" || o.keyword == "return") {
    if (calls.empty()) {
      if (o.keyword == "endsub") fail(o.column, "o" + o.label + " endsub outside a subroutine");
      fail(o.column, "o" + o.label + " return outside a subroutine");
    }
    if (o.value) parameters.set_named("_value", *o.value);
    const Call call = calls.back();
    calls.pop_back();
    flow.resize(std::min(flow.size(), call.flow_depth));
    parameters.pop_scope();
    jump(call.return_to);
  } else if (o.keyword == "if") {
    if (value_of() != 0.0) {
      flow.push_back({Frame::Type::if_, o.label, current, 0, true});
    } else {
      flow.push_back({Frame::Type::if_, o.label, current, 0, false});
      // Find the branch that runs: elseif (re-evaluated when reached), else, or endif.
      std::string keyword;
      skip_to(o.label, {"elseif", "else", "endif"}, &keyword, o.column);
      jump(current);  // execute that line itself
    }
  } else if (o.keyword == "elseif" || o.keyword == "else") {
    if (flow.empty() || flow.back().type != Frame::Type::if_ || flow.back().label != o.label) {
      fail(o.column, "o" + o.label + " " + o.keyword + " without its if");
    }
    Frame& frame = flow.back();
    if (frame.taken) {
      skip_to(o.label, {"endif"}, nullptr, o.column);
      flow.pop_back();
    } else if (o.keyword == "else" || value_of() != 0.0) {
      frame.taken = true;
    } else {
      skip_to(o.label, {"elseif", "else", "endif"}, nullptr, o.column);
      jump(current);
    }
  } else if (o.keyword == "endif") {
    if (!flow.empty() && flow.back().type == Frame::Type::if_ && flow.back().label == o.label) {
      flow.pop_back();
    }
  } else if (o.keyword == "do") {
    flow.push_back({Frame::Type::do_, o.label, current, 0, false});
  } else if (o.keyword == "while") {
    if (!flow.empty() && flow.back().type == Frame::Type::do_ && flow.back().label == o.label) {
      // The end of a do-while loop.
      if (value_of() != 0.0) {
        count_loop_iteration(flow.back(), o.column);
        jump(after(flow.back().start));
      } else {
        flow.pop_back();
      }
    } else if (value_of() != 0.0) {
      if (flow.empty() || flow.back().type != Frame::Type::while_ || flow.back().label != o.label) {
        flow.push_back({Frame::Type::while_, o.label, current, 0, false});
      }
    } else {
      if (!flow.empty() && flow.back().type == Frame::Type::while_ &&
          flow.back().label == o.label) {
        flow.pop_back();
      }
      skip_to(o.label, {"endwhile"}, nullptr, o.column);
    }
  } else if (o.keyword == "endwhile") {
    if (flow.empty() || flow.back().type != Frame::Type::while_ || flow.back().label != o.label) {
      fail(o.column, "o" + o.label + " endwhile without its while");
    }
    count_loop_iteration(flow.back(), o.column);
    jump(flow.back().start);  // re-evaluates the condition
  } else if (o.keyword == "repeat") {
    const double wanted = value_of();
    if (wanted > static_cast<double>(options.max_loop_iterations)) {
      fail(o.column, "o" + o.label + " repeat [" + written_number(wanted) + "]: more than the " +
                         std::to_string(options.max_loop_iterations) +
                         " iterations one loop may make");
    }
    const long count = std::lround(wanted);
    if (count <= 0) {
      skip_to(o.label, {"endrepeat"}, nullptr, o.column);
    } else {
      flow.push_back({Frame::Type::repeat, o.label, current, count, false});
    }
  } else if (o.keyword == "endrepeat") {
    if (flow.empty() || flow.back().type != Frame::Type::repeat || flow.back().label != o.label) {
      fail(o.column, "o" + o.label + " endrepeat without its repeat");
    }
    if (--flow.back().remaining > 0) {
      count_loop_iteration(flow.back(), o.column);
      jump(after(flow.back().start));
    } else {
      flow.pop_back();
    }
  } else if (o.keyword == "break" || o.keyword == "continue") {
    while (!flow.empty() && flow.back().label != o.label) flow.pop_back();
    if (flow.empty() || flow.back().type == Frame::Type::if_) {
      fail(o.column, "o" + o.label + " " + o.keyword + " outside its loop");
    }
    Frame frame = flow.back();
    if (o.keyword == "break") {
      flow.pop_back();
      const char* end = frame.type == Frame::Type::repeat ? "endrepeat"
                        : frame.type == Frame::Type::do_  ? "while"
                                                          : "endwhile";
      skip_to(o.label, {end}, nullptr, o.column);
    } else if (frame.type == Frame::Type::while_) {
      count_loop_iteration(flow.back(), o.column);
      jump(frame.start);
    } else if (frame.type == Frame::Type::repeat) {
      skip_to(o.label, {"endrepeat"}, nullptr, o.column);
      jump(current);
    } else {
      skip_to(o.label, {"while"}, nullptr, o.column);
      jump(current);
    }
  }
}

void Interpreter::State::count_loop_iteration(Frame& loop, int column) {
  if (++loop.iterations > options.max_loop_iterations) {
    throw GcodeError(file_name, loop.start.line, 0,
                     "the loop o" + loop.label + " went round more than " +
                         std::to_string(options.max_loop_iterations) +
                         " times (the bound on one loop: an endless loop?)");
  }
  count_program_iteration(column);
}

void Interpreter::State::count_program_iteration(int column) {
  if (++program_iterations > options.max_program_iterations) {
    fail(column, "the program made more than " + std::to_string(options.max_program_iterations) +
                     " loop iterations, subroutine calls and canned-cycle holes and pecks "
                     "(the bound on a whole program)");
  }
}

void Interpreter::State::require_call_depth(const OWord& o) const {
  if (calls.size() >= kMaxCallDepth) {
    fail(o.column, "o" + o.label + " call: subroutine calls nested deeper than " +
                       std::to_string(kMaxCallDepth) + " (LinuxCNC's limit)");
  }
}

void Interpreter::State::require_word_in_range(const Block& block, char letter, double low,
                                               double high, const std::string& what) const {
  const auto& word = block.word(letter);
  if (!word || (word->value >= low && word->value <= high)) return;
  fail(word->column, std::string(1, static_cast<char>(std::toupper(letter))) +
                         written_number(word->value) + " is out of range: " + what + " " +
                         written_number(low) + " to " + written_number(high));
}

namespace {
// The word letters and the codes that use them (rs274's check of "other" words), known from the
// block: `n` its non-modal G code, `m` the motion it makes (its own or the modal one), `g64`
// whether it sets G64 and `user_m` whether it holds a user M code (M100-M199).
struct WordUsers {
  int n = -1, m = -1;
  bool g64 = false, user_m = false;
  int m5 = -1, m6 = -1, m9 = -1;  // codes of M groups 5, 6 and 9, or -1
  bool arc() const { return m == 20 || m == 30; }
  bool cycle() const { return m >= 730 && m != 800; }
  bool threading() const { return m == 760; }  // G76: passed on with its words
};

// The message refusing `letter`, or nullptr when a code of the block uses it.
const char* unused_word_message(char letter, const WordUsers& u) {
  switch (letter) {
    case 'e':
      if (u.threading() || (u.m5 >= 660 && u.m5 <= 680)) return nullptr;
      return "E word with no G76, M66, M67 or M68 to use it (a number such as 1e-05 is not "
             "G-code: X1e-05 reads as X1 and an E word)";
    case 'i':
    case 'j':
      if (u.arc() || u.n == 100 || u.threading() || (letter == 'i' && u.m == 331)) return nullptr;
      return letter == 'i' ? "I word with no G2, G3, G10, G33.1 or G76 to use it"
                           : "J word with no G2, G3, G10 or G76 to use it";
    case 'k':
      if (u.arc() || u.m == 330 || u.m == 331 || u.threading()) return nullptr;
      return "K word with no G2, G3, G33, G33.1 or G76 to use it";
    case 'h':
      return nullptr;  // checked by refuse_unused_words: it needs the G43 of group 8
    case 'l':
      if (u.n == 100 || u.cycle() || u.m5 == 660) return nullptr;
      return "L word with no G10, cutter compensation, canned cycle or M66 to use it";
    case 'p':
      if (u.arc() || u.n == 40 || u.n == 100 || u.g64 || u.m == 820 || u.m == 860 || u.m == 880 ||
          u.m == 890 || u.threading() || u.user_m || (u.m9 >= 500 && u.m9 <= 530) ||
          (u.m5 >= 620 && u.m5 <= 660)) {
        return nullptr;
      }
      return "P word with no G2, G3, G4, G10, G64, G76, G82, G86, G88, G89, M50-M53, M62-M66 or "
             "user M code to use it";
    case 'q':
      if (u.n == 100 || u.g64 || u.m == 730 || u.m == 830 || u.threading() || u.user_m ||
          u.m6 == 610 || (u.m5 >= 660 && u.m5 <= 680)) {
        return nullptr;
      }
      return "Q word with no G10, G64, G73, G76, G83, M61, M66, M67, M68 or user M code to use it";
    case 'r':
      if (u.arc() || u.cycle() || u.n == 100 || u.threading()) return nullptr;
      return "R word with no G code that uses it";
    default:
      return nullptr;
  }
}
}  // namespace

void Interpreter::State::refuse_unused_words(const Block& block) const {
  for (const Code& code : block.m_codes) {
    if (m_group(code.tenths) < 0) return;  // a code with no meaning here: passed on, words and all
  }
  constexpr std::uint32_t kChecked =
      (1u << ('e' - 'a')) | (1u << ('h' - 'a')) | (1u << ('i' - 'a')) | (1u << ('j' - 'a')) |
      (1u << ('k' - 'a')) | (1u << ('l' - 'a')) | (1u << ('p' - 'a')) | (1u << ('q' - 'a')) |
      (1u << ('r' - 'a'));
  if ((block.letters & kChecked) == 0) return;
  WordUsers users;
  users.n = g_by_group[0] ? g_by_group[0]->tenths : -1;
  // G10, G28, G30 and G92 take the axis words: they make no motion of the modal mode.
  const bool axes_taken = users.n == 100 || users.n == 280 || users.n == 300 || users.n == 920;
  const bool has_axis = (block.letters & (kAxisSlots | kPolarSlots)) != 0;
  users.m = g_by_group[1] ? g_by_group[1]->tenths : (has_axis && !axes_taken ? motion : -1);
  users.g64 = g_by_group[13] && g_by_group[13]->tenths == 640;
  users.user_m = m_by_group[10] != nullptr;
  users.m5 = m_by_group[5] ? m_by_group[5]->tenths : -1;
  users.m6 = m_by_group[6] ? m_by_group[6]->tenths : -1;
  users.m9 = m_by_group[9] ? m_by_group[9]->tenths : -1;
  for (const char letter : std::string_view("ehijklpqr")) {
    const auto& word = block.word(letter);
    if (!word) continue;
    if (letter == 'h' && !(g_by_group[8] && g_by_group[8]->tenths == 430) && !users.threading()) {
      fail(word->column, "H word with no G43 or G76 to use it");
    }
    if (letter == 'l' && g_by_group[7]) continue;  // cutter compensation's tool orientation
    if (const char* message = unused_word_message(letter, users)) fail(word->column, message);
  }
}

void Interpreter::State::not_finite(const Canon& canon) const {
  // A move's column is its motion code's; other commands come from the line as a whole.
  const bool move = canon.kind == CanonKind::traverse || canon.kind == CanonKind::feed ||
                    canon.kind == CanonKind::arc || canon.kind == CanonKind::probe;
  throw GcodeError(file_name, canon.line, move ? move_column : 0,
                   "calculation resulted in infinity or NaN (a number too large to use)");
}

void Interpreter::State::target(const Block& block, bool machine_coordinates, Position& end) const {
  end = pos;
  const std::uint32_t axes = block.letters & kAxisSlots;
  if (machine_coordinates) {
    const Position offsets = total_offset_mm();
    for (std::uint32_t used = axes; used != 0; used &= used - 1) {
      const int slot = std::countr_zero(used);
      const int axis = kAxisOfSlot[static_cast<std::size_t>(slot)];
      end[axis] =
          block.words[static_cast<std::size_t>(slot)]->value - axis_from_mm(axis, offsets[axis]);
    }
  } else {
    for (std::uint32_t used = axes; used != 0; used &= used - 1) {
      const int slot = std::countr_zero(used);
      const int axis = kAxisOfSlot[static_cast<std::size_t>(slot)];
      const double value = block.words[static_cast<std::size_t>(slot)]->value;
      end[axis] = absolute ? value : pos[axis] + value;
    }
  }
  // Polar coordinates about the origin in XY: @ radius, ^ angle (deg). A missing one keeps the
  // current point's; in G91 both are increments to the current point's.
  const auto& radius = block.words['g' - 'a'];
  const auto& angle = block.words['m' - 'a'];
  if (radius || angle) {
    const double current_radius = std::hypot(pos[kX], pos[kY]);
    const double current_angle = std::atan2(pos[kY], pos[kX]) * 180.0 / std::numbers::pi;
    double r = current_radius, a = current_angle;
    if (absolute) {
      if (radius) r = radius->value;
      if (angle) a = angle->value;
    } else {
      if (radius) r += radius->value;
      if (angle) a += angle->value;
    }
    end[kX] = r * std::cos(a * std::numbers::pi / 180.0);
    end[kY] = r * std::sin(a * std::numbers::pi / 180.0);
  }
}

void Interpreter::State::missing_feed(int column) const {
  if (feed_mode == FeedMode::inverse_time) {
    fail(column, "F word missing with inverse time (G93) motion");
  }
  fail(column, "cannot do a feed move with zero feed rate: give an F word");
}

void Interpreter::State::straight(CanonKind kind, const Block& block, const Position& end) {
  Canon& canon = next_move(kind, block);
  if (&end != &canon.end) canon.end = end;
  canon.value = feed;  // the F in effect: the planner's programmed speed (or inverse time)
  canon.feed_mode = feed_mode;
  straight_exit = false;
  send_move(canon, &CutterCompensation::straight);
}

void Interpreter::State::arc(const Block& block, int code, const Position& end) {
  int first = 0, second = 1;
  char first_offset = 'i', second_offset = 'j';
  switch (plane) {
    case Plane::xy:
      first = kX, second = kY, first_offset = 'i', second_offset = 'j';
      break;
    case Plane::xz:
      first = kZ, second = kX, first_offset = 'k', second_offset = 'i';
      break;
    case Plane::yz:
      first = kY, second = kZ, first_offset = 'j', second_offset = 'k';
      break;
  }
  const int column = block.g_codes.empty() ? 1 : block.g_codes.front().column;
  if (straight_exit) {
    fail(column, "the move after G40 (cutter compensation off) must be straight, not an arc");
  }
  const double start_1 = pos[first], start_2 = pos[second];
  const double end_1 = end[first], end_2 = end[second];
  double centre_1 = 0.0, centre_2 = 0.0;
  const bool inch = units == LengthUnits::inch;
  int turns = code == 20 ? -1 : 1;
  if (block.has('p')) {
    const double p = block.value('p');
    if (p < 1.0 || p != std::floor(p))
      fail(block.word('p')->column, "P must be a whole number of turns, 1 or more");
    require_word_in_range(block, 'p', 1.0, kMaxArcTurns, "an arc's turns go from");
    turns *= static_cast<int>(p);
  }
  if (block.has('r')) {
    const double radius = block.value('r');
    if (end_1 == start_1 && end_2 == start_2) {
      fail(block.word('r')->column,
           "an R arc's end point equals its start: the centre is undefined");
    }
    const double abs_radius = std::abs(radius);
    const double mid_1 = (end_1 + start_1) / 2.0, mid_2 = (end_2 + start_2) / 2.0;
    double half = std::hypot(mid_1 - end_1, mid_2 - end_2);
    const double tolerance = inch ? 0.0005 : 0.005;
    if (half - abs_radius > tolerance) {
      fail(block.word('r')->column, "arc radius too small to reach the end point");
    }
    if (half / abs_radius > 1.0 - 1e-12) half = abs_radius;
    const double direction = std::atan2(end_2 - start_2, end_1 - start_1);
    const double theta = ((code == 20 && radius > 0) || (code == 30 && radius < 0))
                             ? direction - std::numbers::pi / 2
                             : direction + std::numbers::pi / 2;
    const double offset = abs_radius * std::cos(std::asin(half / abs_radius));
    centre_1 = mid_1 + offset * std::cos(theta);
    centre_2 = mid_2 + offset * std::sin(theta);
  } else {
    if (!block.has(first_offset) && !block.has(second_offset)) {
      fail(column, "R, I, J, K words all missing for the arc");
    }
    const double i = block.has(first_offset) ? block.value(first_offset) : 0.0;
    const double j = block.has(second_offset) ? block.value(second_offset) : 0.0;
    centre_1 = arc_absolute ? i : start_1 + i;
    centre_2 = arc_absolute ? j : start_2 + j;
    const double radius = std::hypot(centre_1 - start_1, centre_2 - start_2);
    const double radius2 = std::hypot(centre_1 - end_1, centre_2 - end_2);
    const double abs_tolerance = arc_radius_tolerance(units);
    if (radius < 0.1 * abs_tolerance || radius2 < 0.1 * abs_tolerance)
      fail(column, "zero radius arc");
    const double abs_err = std::abs(radius - radius2);
    const double rel_err = abs_err / std::max(radius, radius2);
    if (abs_err > abs_tolerance && rel_err > 0.001) {
      char message[256];
      std::snprintf(message, sizeof message,
                    "radius to end of arc differs from radius to start: r1=%.4f r2=%.4f "
                    "(LinuxCNC accepts %.4f or 0.1%%)",
                    radius, radius2, abs_tolerance);
      fail(column, message);
    }
  }
  Canon& canon = next_move(CanonKind::arc, block);
  canon.end = end;
  canon.value = feed;
  canon.feed_mode = feed_mode;
  canon.center = {centre_1, centre_2};
  canon.turns = turns;
  send_move(canon, &CutterCompensation::arc);
}

void Interpreter::State::cycle(const Block& block, int code, const Position& end) {
  int first = kX, second = kY, normal = kZ;
  char normal_letter = 'z';
  switch (plane) {
    case Plane::xy:
      break;
    case Plane::xz:
      first = kZ, second = kX, normal = kY, normal_letter = 'y';
      break;
    case Plane::yz:
      first = kY, second = kZ, normal = kX, normal_letter = 'x';
      break;
  }
  const int column = block.g_codes.empty() ? 1 : block.g_codes.front().column;
  // Sticky R and Z are kept in mm, as LinuxCNC keeps them in machine units: read back in
  // inches they may differ from the written value in the last bit, which decides whether the
  // cycle first climbs to R (rs274's output shows it).
  double r_value = 0.0, z_value = 0.0;
  if (block.has('r')) {
    r_value = block.value('r');
    cycle_r = to_mm(r_value);
  } else if (motion_changed) {
    fail(column, "R clearance plane unspecified in cycle");
  } else {
    r_value = from_mm(cycle_r);
  }
  if (block.has(normal_letter)) {
    z_value = block.value(normal_letter);
    cycle_z = to_mm(z_value);
  } else if (motion_changed) {
    fail(column, std::string(1, static_cast<char>(std::toupper(normal_letter))) +
                     " value unspecified in cycle");
  } else {
    z_value = from_mm(cycle_z);
  }
  if (block.has('q')) cycle_q = block.value('q');
  if (block.has('p')) cycle_p = block.value('p');
  if ((code == 830 || code == 730) && !(cycle_q > 0.0))
    fail(column, "Q must be positive for G83/G73");
  require_feed(block, column);
  if (!cycle_series) {
    cycle_old_cc = pos[normal];
    cycle_series = true;
  }
  require_word_in_range(block, 'l', 0.0, static_cast<double>(options.max_loop_iterations),
                        "a canned cycle's repeats (the bound on one loop) go from");
  const long repeats = block.has('l') ? std::lround(block.value('l')) : 1;
  double r = r_value, bottom = z_value;
  if (!absolute) {
    r = cycle_old_cc + r_value;
    bottom = r + z_value;
  }
  if (bottom > r) fail(column, "cycle bottom is above the R plane");
  const double clear = (retract_to_old && cycle_old_cc > r) ? cycle_old_cc : r;
  const double delta = units == LengthUnits::inch ? 0.010 : 0.254;  // peck clearance
  auto move = [&](CanonKind kind, double a, double b, double c) {
    Position p = pos;
    p[first] = a;
    p[second] = b;
    p[normal] = c;
    straight(kind, block, p);
  };
  // Below R when the series began: every block of the series climbs to R first (even from R).
  if (cycle_old_cc < r) move(CanonKind::traverse, pos[first], pos[second], r);
  // In G91 each repetition moves on by the programmed increment; with polar words the
  // increment is in radius and angle, applied to each hole's polar coordinates in turn.
  const double step_1 = end[first] - pos[first], step_2 = end[second] - pos[second];
  const auto& polar_radius = block.words['g' - 'a'];
  const auto& polar_angle = block.words['m' - 'a'];
  const bool polar = !absolute && plane == Plane::xy && (polar_radius || polar_angle);
  double at_1 = pos[first], at_2 = pos[second];
  for (long repeat = 0; repeat < repeats; ++repeat) {
    count_program_iteration(column);
    if (absolute) {
      at_1 = end[first];
      at_2 = end[second];
    } else if (polar) {
      const double radius = std::hypot(at_1, at_2) + (polar_radius ? polar_radius->value : 0.0);
      const double angle = std::atan2(at_2, at_1) +
                           (polar_angle ? polar_angle->value * std::numbers::pi / 180.0 : 0.0);
      at_1 = radius * std::cos(angle);
      at_2 = radius * std::sin(angle);
    } else {
      at_1 += step_1;
      at_2 += step_2;
    }
    // Across to the hole at the current height, or at R where that is higher.
    move(CanonKind::traverse, at_1, at_2, std::max(pos[normal], r));
    if (pos[normal] != r) move(CanonKind::traverse, at_1, at_2, r);
    switch (code) {
      case 810:
        move(CanonKind::feed, at_1, at_2, bottom);
        break;
      case 820:
        move(CanonKind::feed, at_1, at_2, bottom);
        dwell(block, cycle_p);
        break;
      case 830:
      case 730: {
        if ((r - bottom) / cycle_q > static_cast<double>(options.max_loop_iterations)) {
          fail(column, "Q" + written_number(cycle_q) + " makes more than " +
                           std::to_string(options.max_loop_iterations) +
                           " pecks (the bound on one loop)");
        }
        double depth = r;
        while (true) {
          count_program_iteration(column);
          depth = std::max(depth - cycle_q, bottom);
          move(CanonKind::feed, at_1, at_2, depth);
          if (depth <= bottom) break;
          if (code == 830) {
            move(CanonKind::traverse, at_1, at_2, r);
            move(CanonKind::traverse, at_1, at_2, depth + delta);
          } else {
            move(CanonKind::traverse, at_1, at_2, depth + delta);
          }
        }
        break;
      }
      case 850:
        move(CanonKind::feed, at_1, at_2, bottom);
        move(CanonKind::feed, at_1, at_2, r);
        break;
      case 890: {
        // G89 feeds all the way out to the clearance height (G85 feeds to R, then traverses).
        move(CanonKind::feed, at_1, at_2, bottom);
        dwell(block, cycle_p);
        move(CanonKind::feed, at_1, at_2, clear);
        continue;
      }
      default:
        fail(column, code_name('G', code) + " is not supported (spindle-synchronised cycle)");
    }
    move(CanonKind::traverse, at_1, at_2, clear);
  }
}

void Interpreter::State::start_compensation(const Block& block, const Code& code) {
  const std::string name = code_name('G', code.tenths);
  if (plane == Plane::yz) {
    fail(code.column, "cutter radius compensation works in the XY (G17) or XZ (G18) plane only");
  }
  if (compensation.on()) fail(code.column, "cutter radius compensation is already on (G40 first)");
  const auto& d = block.word('d');
  double radius = 0.0;  // program units
  if (code.tenths == 411 || code.tenths == 421) {
    // G41.1/G42.1: the D word is the tool's diameter.
    if (!d) fail(code.column, name + " needs a D word: the tool diameter");
    radius = d->value / 2.0;
    if (const auto& l = block.word('l')) {
      if (plane != Plane::xz) {
        fail(l->column, name + " with an L word (lathe tool orientation) needs the XZ plane (G18)");
      }
      if (l->value != 0.0 && l->value != 9.0) {
        fail(l->column, "lathe tool orientations are not supported: L0 or L9 (a round tool) only");
      }
    }
  } else {
    // G41/G42: the D word names a tool in the table; without one, the tool in the spindle.
    int tool = tool_in_spindle;
    const int column = d ? d->column : code.column;
    if (d) {
      require_word_in_range(block, 'd', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
      const double number = std::round(d->value);
      if (std::abs(d->value - number) >= 1e-4) {
        fail(d->column, name + " needs D to be a whole number: a tool in the tool table");
      }
      if (number < 0.0) fail(d->column, "negative D word (tool number)");
      tool = static_cast<int>(number);
    }
    if (tool != 0) {
      if (!options.tool_table) {
        fail(column, name + " needs a tool table (--tool-table) for the diameter of tool " +
                         std::to_string(tool));
      }
      const auto entry = options.tool_table->find(tool);
      if (entry == options.tool_table->end()) {
        fail(column, "tool " + std::to_string(tool) + " for " + name + " is not in the tool table");
      }
      radius = from_mm(entry->second.diameter) / 2.0;
    }
    if (radius == 0.0) {
      warn(name + " with tool " + std::to_string(tool) +
           " of zero diameter: the moves are not offset");
    }
  }
  compensation.turn_on(
      code.tenths == 410 || code.tenths == 411 ? CompensationSide::left : CompensationSide::right,
      radius, plane);
}

void Interpreter::State::go_home(const Block& block, int code) {
  // G28/G30: through the programmed axes' intermediate point, then to the stored position
  // (#5161.. / #5181.., machine coordinates) of those axes, or of all axes when none is given.
  const int base = code == 280 ? 5161 : 5181;
  const bool any = (block.letters & kAxisSlots) != 0;
  // The intermediate move is made even when it goes nowhere, as LinuxCNC makes it.
  straight(CanonKind::traverse, block, target(block, false));
  const Position offsets = total_offset_mm();
  Position home = pos;
  for (int axis = 0; axis < kAxes; ++axis) {
    if (any && !block.has(kAxisLetters[axis])) continue;
    home[axis] = axis_from_mm(axis, parameters.numbered(base + axis) - offsets[axis]);
  }
  straight(CanonKind::traverse, block, home);
}

void Interpreter::State::set_coordinates(const Block& block) {
  // G10 L1/L2/L10/L20.
  const int column = block.g_codes.front().column;
  if (!block.has('l')) fail(column, "G10 needs an L word");
  const long l = std::lround(block.value('l'));
  if (!block.has('p')) fail(column, "G10 needs a P word");
  require_word_in_range(block, 'p', -kMaxToolNumber, kMaxToolNumber,
                        "G10 P (a coordinate system or tool) goes from");
  const long p = std::lround(block.value('p'));
  if (l == 2 || l == 20) {
    const int system = p == 0 ? coord_system : static_cast<int>(p);
    if (system < 1 || system > 9) fail(block.word('p')->column, "G10 P must be 0..9");
    if (system == coord_system) {
      refuse_with_compensation(block.g_codes.front(), "change the active coordinate system");
    }
    const Position old_total = total_offset_mm();
    for (int axis = 0; axis < kAxes; ++axis) {
      if (!block.has(kAxisLetters[axis])) continue;
      const int number = 5201 + 20 * system + axis;
      double value = axis_to_mm(axis, block.value(kAxisLetters[axis]));
      if (l == 20) {
        // The current point gets the given coordinate in that system.
        const Position g5x = g5x_mm(coord_system);
        const double machine =
            axis_to_mm(axis, pos[axis]) + g5x[axis] + g92_mm[axis] + tool_offset_mm[axis];
        value = machine - value - g92_mm[axis] - tool_offset_mm[axis];
      }
      parameters.set_numbered(number, value);
    }
    if (system == coord_system) {
      reexpress(old_total);
      emit_offsets(block);
    }
  } else if (l == 1 || l == 10) {
    if (!options.tool_table) fail(column, "G10 L1/L10 needs a tool table");
    auto& table = const_cast<ToolTable&>(*options.tool_table);
    ToolEntry& entry = table[static_cast<int>(p)];
    entry.number = static_cast<int>(p);
    for (int axis = 0; axis < kAxes; ++axis) {
      if (block.has(kAxisLetters[axis]))
        entry.offset[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
    }
    if (block.has('r')) entry.diameter = 2.0 * to_mm(block.value('r'));
    require_finite_tool(entry, column);
  } else {
    fail(block.word('l')->column, "G10 L" + std::to_string(l) + " is not supported");
  }
}

void Interpreter::State::execute_block(const Block& block) {
  // Most lines of a CAM program are bare axis words continuing a G0 or G1: nothing but the move
  // to make. (The general path below makes the same move; this one skips its checks.)
  if (block.plain && (motion == 0 || motion == 10) && block.letters != 0 &&
      (block.letters & ~kAxisSlots) == 0) {
    motion_changed = false;
    move_column = 1;
    if (motion == 10) require_feed(block, 1);
    target(block, false, move_.end);  // built in place: straight() finds it there
    straight(motion == 0 ? CanonKind::traverse : CanonKind::feed, block, move_.end);
    return;
  }
  apply_assignments(block);
  for (const Comment& comment : block.comments) {
    std::string text = comment.text;
    std::string lower = text;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    const auto first = lower.find_first_not_of(" \t");
    if (first != std::string::npos && lower.compare(first, 4, "msg,") == 0) {
      Canon message = make(CanonKind::message, block);
      message.text = text.substr(first + 4);
      emit(message);
    } else {
      Canon c = make(CanonKind::comment, block);
      c.text = text;
      emit(c);
    }
  }
  if (block.empty) return;

  // Modal groups: at most one code of each in a block.
  g_by_group.clear();
  m_by_group.clear();
  for (const Code& code : block.g_codes) {
    const int group = g_group(code.tenths);
    if (group < 0) fail(code.column, "unknown G code " + code_name('G', code.tenths));
    const Code* slot = g_by_group[group];
    if (!slot) {
      g_by_group.set(group, code);
      continue;
    }
    if (group == 1 && (slot->tenths == 800 || code.tenths == 800)) {
      // "G80 G0": the cycle ends and the other motion mode takes over, as LinuxCNC allows.
      if (slot->tenths == 800) g_by_group.set(group, code);
      cycle_series = false;
      continue;
    }
    if (group == 0) fail(code.column, "two non-modal G codes on one line");
    fail(code.column, "two G codes of one modal group: " + code_name('G', slot->tenths) + " and " +
                          code_name('G', code.tenths));
  }
  for (const Code& code : block.m_codes) {
    int group = m_group(code.tenths);
    if (group < 0) {
      // Codes with no meaning off a real machine (M280 pen servo, M200+) are passed on.
      Canon event = make(CanonKind::event, block);
      event.text = code_name('M', code.tenths) + " passed on";
      warn(code_name('M', code.tenths) + " has no meaning here; passed on as an event");
      emit(event);
      continue;
    }
    if (group == 8 && m_by_group[8] && (code.tenths == 70 || code.tenths == 80) &&
        (m_by_group[8]->tenths == 70 || m_by_group[8]->tenths == 80)) {
      group = 11;  // M7 and M8 may share a line
    }
    if (const Code* slot = m_by_group[group]) {
      fail(code.column, "two M codes of one modal group: " + code_name('M', slot->tenths) +
                            " and " + code_name('M', code.tenths));
    }
    m_by_group.set(group, code);
  }
  refuse_unused_words(block);
  const auto g_in = [&](int group) { return g_by_group[group]; };
  const Code* const non_modal = g_in(0);
  const Code* const motion_code = g_in(1);
  bool has_axis = (block.letters & (kAxisSlots | kPolarSlots)) != 0;

  // 1. feed mode, feed, speed, tool.
  if (const auto code = g_in(5)) {
    if (code->tenths == 950) fail(code->column, "G95 (feed per revolution) is not supported");
    feed_mode = code->tenths == 930 ? FeedMode::inverse_time : FeedMode::units_per_minute;
    Canon c = make(CanonKind::set_feed_mode, block);
    c.feed_mode = feed_mode;
    emit(c);
  }
  if (block.has('f')) {
    const double f = block.value('f');
    if (f < 0.0) fail(block.word('f')->column, "negative F word");
    feed = f;
    if (feed_mode == FeedMode::units_per_minute) {
      Canon c = make(CanonKind::set_feed_rate, block);
      c.value = f;
      emit(c);
    }
  }
  if (block.has('s')) {
    if (block.value('s') < 0.0) fail(block.word('s')->column, "negative spindle speed");
    speed = block.value('s');
    Canon c = make(CanonKind::spindle_speed, block);
    c.value = speed;
    emit(c);
  }
  if (block.has('t')) {
    require_word_in_range(block, 't', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
    const long t = std::lround(block.value('t'));
    if (t < 0) fail(block.word('t')->column, "negative tool number");
    if (options.tool_table && t != 0 && !options.tool_table->count(static_cast<int>(t))) {
      fail(block.word('t')->column,
           "requested tool " + std::to_string(t) + " not found in the tool table");
    }
    if (!options.tool_table && t != 0)
      warn("T" + std::to_string(t) + " without a tool table: no offsets known");
    selected_tool = static_cast<int>(t);
    Canon c = make(CanonKind::select_tool, block);
    c.integer = selected_tool;
    emit(c);
  }
  // 2. tool change, spindle, coolant, overrides (most blocks have no M code).
  if (m_by_group.any()) {
    if (m_by_group[6]) {
      const Code code = *m_by_group[6];
      refuse_with_compensation(code, "change tools");
      if (code.tenths == 60) {
        Canon c = make(CanonKind::change_tool, block);
        c.integer = selected_tool;
        emit(c);
      }
      if (tool_off_path) pos = *tool_off_path;
      tool_off_path.reset();
      require_word_in_range(block, 'q', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
      tool_in_spindle = code.tenths == 610 ? static_cast<int>(block.has('q') ? block.value('q') : 0)
                                           : selected_tool;
    }
    if (m_by_group[7]) {
      const int code = m_by_group[7]->tenths;
      if (code == 30) emit(CanonKind::spindle_clockwise, block);
      if (code == 40) emit(CanonKind::spindle_counterclockwise, block);
      if (code == 50) emit(CanonKind::spindle_stop, block);
    }
    for (const int group : {8, 11}) {
      if (!m_by_group[group]) continue;
      const int code = m_by_group[group]->tenths;
      if (code == 70) emit(CanonKind::mist_on, block);
      if (code == 80) emit(CanonKind::flood_on, block);
      if (code == 90) {
        emit(CanonKind::mist_off, block);
        emit(CanonKind::flood_off, block);
      }
    }
    for (const int group : {9, 5, 10}) {
      if (!m_by_group[group]) continue;
      const int code = m_by_group[group]->tenths;
      Canon event = make(CanonKind::event, block);
      event.text = code_name('M', code);
      if (group == 10) warn(code_name('M', code) + " (user M-code) passed on as an event");
      emit(event);
    }
  }
  // 3. dwell.
  if (non_modal && non_modal->tenths == 40) {
    if (!block.has('p')) fail(non_modal->column, "G4 needs a P word (seconds)");
    if (block.value('p') < 0.0) fail(block.word('p')->column, "negative dwell");
    dwell(block, block.value('p'));
  }
  if (!g_in(7) && block.word('d')) {
    fail(block.word('d')->column, "D word with no G41, G42, G41.1 or G42.1 to use it");
  }
  // 4. plane, units, cutter compensation, tool length; 5. coordinate system, path control,
  // distance modes, retract mode (most blocks have no G code).
  if (g_by_group.any()) {
    if (const auto code = g_in(2)) {
      const Plane wanted = code->tenths == 170   ? Plane::xy
                           : code->tenths == 180 ? Plane::xz
                                                 : Plane::yz;
      if (wanted != plane) refuse_with_compensation(*code, "change planes");
      plane = wanted;
      emit(CanonKind::select_plane, block);
    }
    if (const auto code = g_in(6)) {
      const LengthUnits wanted = code->tenths == 200 ? LengthUnits::inch : LengthUnits::mm;
      if (wanted != units) {
        const double factor = wanted == LengthUnits::inch ? 1.0 / kMmPerInch : kMmPerInch;
        for (int axis = 0; axis < kAxes; ++axis) {
          if (is_linear(axis)) pos[axis] *= factor;
        }
        feed *= factor;
        units = wanted;
        compensation.rescale(factor, units);
      }
      emit(CanonKind::use_length_units, block);
    }
    if (const auto code = g_in(7)) {
      if (code->tenths == 400) {
        const Position tool = compensation.tool_position(pos);
        compensating(code->column, [&] { straight_exit = compensation.turn_off(); });
        if (straight_exit) tool_off_path = tool;
      } else {
        start_compensation(block, *code);
      }
    }
    if (const auto code = g_in(8)) {
      refuse_with_compensation(*code, "change the tool length offset");
      Position offset{};
      if (code->tenths == 430) {
        require_word_in_range(block, 'h', -kMaxToolNumber, kMaxToolNumber, "tool numbers go from");
        const int tool =
            block.has('h') ? static_cast<int>(std::lround(block.value('h'))) : tool_in_spindle;
        if (tool != 0) {
          if (options.tool_table && !options.tool_table->count(tool)) {
            fail(code->column, "tool " + std::to_string(tool) + " for G43 not in the tool table");
          }
          if (options.tool_table) offset = options.tool_table->at(tool).offset;
        }
      } else if (code->tenths == 431) {
        for (int axis = 0; axis < kAxes; ++axis) {
          if (block.has(kAxisLetters[axis]))
            offset[axis] = axis_to_mm(axis, block.value(kAxisLetters[axis]));
        }
        has_axis = false;  // the axis words were the offset
      } else if (code->tenths == 432) {
        fail(code->column, "G43.2 is not supported");
      }
      // The program position stays: the machine makes up the new length on the next move.
      tool_offset_mm = offset;
      Canon c = make(CanonKind::tool_length_offset, block);
      for (int axis = 0; axis < kAxes; ++axis) c.end[axis] = axis_from_mm(axis, offset[axis]);
      emit(c);
    }
    if (const auto code = g_in(12)) {
      static constexpr int kCodes[] = {540, 550, 560, 570, 580, 590, 591, 592, 593};
      const int system =
          static_cast<int>(std::find(std::begin(kCodes), std::end(kCodes), code->tenths) -
                           std::begin(kCodes)) +
          1;
      refuse_with_compensation(*code, "change coordinate systems");
      const Position old_total = total_offset_mm();
      coord_system = system;
      parameters.set_numbered(5220, system);
      reexpress(old_total);
      emit_offsets(block);
    }
    if (const auto code = g_in(13)) {
      refuse_with_compensation(*code, "change the path control mode");
      path_mode = code->tenths == 640 ? 64 : code->tenths == 610 ? 61 : 611;
      path_tolerance = code->tenths == 640 && block.has('p') ? block.value('p') : 0.0;
      Canon c = make(CanonKind::path_control, block);
      c.integer = path_mode;
      c.value = path_tolerance;
      c.value2 = block.has('q') ? block.value('q') : 0.0;
      emit(c);
    }
    if (const auto code = g_in(3)) absolute = code->tenths == 900;
    if (const auto code = g_in(4)) arc_absolute = code->tenths == 901;
    if (const auto code = g_in(10)) retract_to_old = code->tenths == 980;
    if (const auto code = g_in(14)) {
      if (code->tenths == 960) fail(code->column, "G96 (constant surface speed) is not supported");
    }
    if (const auto code = g_in(15)) {
      (void)code;  // lathe radius/diameter mode: no effect on these machines
    }
  }
  // 6. home, coordinate data, axis offsets.
  bool axes_used = false;
  if (non_modal) {
    const int code = non_modal->tenths;
    if (code == 280 || code == 300) refuse_with_compensation(*non_modal, "use G28 or G30");
    if (code >= 920 && code <= 923) refuse_with_compensation(*non_modal, "change axis offsets");
    if (code == 530 && compensation.offsetting()) {
      fail(non_modal->column, "cannot use G53 with cutter radius compensation on (G40 first)");
    }
    if (code == 100) {
      set_coordinates(block);
      axes_used = true;
    } else if (code == 280 || code == 300) {
      go_home(block, code);
      axes_used = true;
    } else if (code == 281 || code == 301) {
      // Store the current machine position as the G28/G30 home.
      const Position offsets = total_offset_mm();
      for (int axis = 0; axis < kAxes; ++axis) {
        parameters.set_numbered((code == 281 ? 5161 : 5181) + axis,
                                axis_to_mm(axis, pos[axis]) + offsets[axis]);
      }
    } else if (code == 920) {
      const Position old_total = total_offset_mm();
      for (int axis = 0; axis < kAxes; ++axis) {
        if (!block.has(kAxisLetters[axis])) continue;
        g92_mm[axis] += axis_to_mm(axis, pos[axis] - block.value(kAxisLetters[axis]));
        parameters.set_numbered(5211 + axis, g92_mm[axis]);
      }
      parameters.set_numbered(5210, 1.0);
      reexpress(old_total);
      emit_offsets(block);
      axes_used = true;
    } else if (code == 921 || code == 922) {
      const Position old_total = total_offset_mm();
      g92_mm = {};
      if (code == 921) {
        for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5211 + axis, 0.0);
        parameters.set_numbered(5210, 0.0);
      }
      reexpress(old_total);
      emit_offsets(block);
    } else if (code == 923) {
      const Position old_total = total_offset_mm();
      for (int axis = 0; axis < kAxes; ++axis) g92_mm[axis] = parameters.numbered(5211 + axis);
      reexpress(old_total);
      emit_offsets(block);
    }
  }
  // 7. motion.
  const bool machine_coordinates = non_modal && non_modal->tenths == 530;
  const bool previous_cycle = motion >= 730 && motion != 800;
  motion_changed = false;
  if (motion_code) {
    const int code = motion_code->tenths;
    motion_changed = code != motion;
    if (code == 800) {
      cycle_series = false;
    }
    motion = code;
  }
  // An explicit G0..G3 moves even without axis words (to where it is, as LinuxCNC does).
  const bool explicit_move = motion_code && motion_code->tenths <= 30;
  if (!axes_used && (has_axis || explicit_move)) {
    if (motion < 0 || motion == 800) {
      fail(1, "axis words with no motion mode active (after G80, give G0 or G1)");
    }
    const Position end = target(block, machine_coordinates);
    const int column = motion_code ? motion_code->column : 1;
    move_column = column;
    if (compensation.on() && motion >= 380 && motion != 800) {
      fail(column, "cannot use " + code_name('G', motion) +
                       (motion < 390 ? " (probing)" : " (canned cycle)") +
                       " with cutter radius compensation on (G40 first)");
    }
    switch (motion) {
      case 0:
        straight(CanonKind::traverse, block, end);
        break;
      case 10:
        require_feed(block, column);
        straight(CanonKind::feed, block, end);
        break;
      case 20:
      case 30:
        require_feed(block, column);
        arc(block, motion, end);
        break;
      case 330:
      case 331:
      case 760: {
        Canon event = make(CanonKind::event, block);
        event.text = code_name('G', motion) + " (spindle-synchronised motion) passed on";
        warn(event.text);
        emit(event);
        if (motion == 330) pos = end;
        break;
      }
      case 382:
      case 383:
      case 384:
      case 385: {
        // Probing as LinuxCNC's stand-alone interpreter simulates it: the probe trips at the
        // target (#5061.. hold it), and the tool backs off 0.01 inch towards the start.
        require_feed(block, column);
        double length = 0.0;
        for (int axis = 0; axis < 3; ++axis)
          length += (end[axis] - pos[axis]) * (end[axis] - pos[axis]);
        length = std::sqrt(length);
        if (length == 0.0) fail(column, "probe start and end points must differ");
        Canon probe = make(CanonKind::probe, block);
        probe.end = end;
        emit(probe);
        const double back_off = units == LengthUnits::inch ? 0.01 : 0.254;
        for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5061 + axis, end[axis]);
        parameters.set_numbered(5070, 0.0);
        Position after_probe = end;
        for (int axis = 0; axis < 3; ++axis) {
          after_probe[axis] = end[axis] - back_off * (end[axis] - pos[axis]) / length;
        }
        pos = after_probe;
        break;
      }
      default:
        if (motion >= 730) {
          cycle(block, motion, end);
        } else {
          fail(column, "motion mode " + code_name('G', motion) + " is not supported");
        }
    }
  }
  if (!motion_code || motion_code->tenths < 730) {
    if (previous_cycle && motion < 730) cycle_series = false;
  }
  // 8. stop and end.
  if (m_by_group[4]) {
    const int code = m_by_group[4]->tenths;
    release_compensation(m_by_group[4]->column);
    if (code == 0) emit(CanonKind::program_stop, block);
    if (code == 10) emit(CanonKind::optional_stop, block);
    if (code == 600) emit(CanonKind::program_stop, block);
    if (code == 20 || code == 300) {
      // LinuxCNC resets the modal state at the program end.
      const Position old_total = total_offset_mm();
      coord_system = 1;
      g92_mm = {};
      reexpress(old_total);
      plane = Plane::xy;
      absolute = true;
      feed_mode = FeedMode::units_per_minute;
      motion = 10;
      cycle_series = false;
      compensation.turn_off();  // nothing is held any more: the stop released it
      straight_exit = false;
      emit_offsets(block);
      emit(CanonKind::select_plane, block);
      emit(CanonKind::spindle_stop, block);
      emit(CanonKind::program_end, block);
      saw_end = true;
      ended = true;
    }
  }
}

Interpreter::Interpreter(std::filesystem::path program, InterpreterOptions options)
    : program_(std::move(program)), options_(std::move(options)) {}

Interpreter::~Interpreter() = default;

void Interpreter::run(const CanonSink& sink) {
  warnings_.clear();
  state_ = std::make_unique<State>(program_, options_, warnings_);
  state_->run(sink);
}

void Interpreter::start(const CanonSink& sink) {
  warnings_.clear();
  state_ = std::make_unique<State>(program_, options_, warnings_);
  state_->start(sink);
}

bool Interpreter::step() {
  return state_ && state_->step();
}

}  // namespace pkm::gcode
