// The interpreter's state while it runs a program, private to the interpreter's rooms: one
// struct, its members defined by concern in
//   interpreter.cpp         lines of the program, the run, assignments
//   execute_block.cpp       a block's steps in LinuxCNC's order of execution
//   word_checks.cpp         the block's codes by modal group, words no code uses, word ranges
//   coordinate_systems.cpp  offsets, G5x, G10, G28/G30, G92, where axis words lead
//   motion.cpp              straight moves, arcs, probing, G33 and G33.1
//   canned_cycles.cpp       G73, G74, G81-G89
//   threading.cpp           G76
//   tools.cpp               tool selection and change, tool length, cutter compensation
//   o_word_flow.cpp         subroutines, conditionals and loops
//   modal_context.cpp       M70-M73: the modal state saved and restored
// Members used on the path of every line are defined here, inline.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/gcode/block.hpp"
#include "pkm/gcode/canon.hpp"
#include "pkm/gcode/cutter_compensation.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/gcode/line_source.hpp"
#include "pkm/gcode/modal_groups.hpp"
#include "pkm/gcode/parameters.hpp"

namespace pkm::gcode {

inline constexpr double kMmPerInch = 25.4;
// Tool numbers (T, H, D, M61 Q, G10 P) in magnitude: as a tool table holds them (tool_table.cpp).
inline constexpr double kMaxToolNumber = 1e6;
// Spindle speeds (S, rpm): beyond any spindle, and far from overflowing a feed per revolution.
inline constexpr double kMaxSpindleRpm = 1e6;
inline constexpr int kX = 0, kY = 1, kZ = 2;

// The axis letters in Position order, the word slots (Block::words) they use, and the axis of
// each slot (-1: not an axis). The polar words @ and ^ use the slots of G and M.
inline constexpr char kAxisLetters[kAxes] = {'x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w'};
inline constexpr std::uint32_t kAxisSlots = [] {
  std::uint32_t mask = 0;
  for (const char letter : kAxisLetters) mask |= 1u << (letter - 'a');
  return mask;
}();
inline constexpr std::array<int, 26> kAxisOfSlot = [] {
  std::array<int, 26> axis_of{};
  axis_of.fill(-1);
  for (int axis = 0; axis < kAxes; ++axis) axis_of[kAxisLetters[axis] - 'a'] = axis;
  return axis_of;
}();
inline constexpr std::uint32_t kPolarSlots = (1u << ('g' - 'a')) | (1u << ('m' - 'a'));

inline bool is_linear(int axis) {
  return axis < 3 || axis >= 6;
}

struct CycleLevels;   // canned_cycles.cpp
struct ThreadPasses;  // threading.cpp

// G73, G74 and G81-G89 (G76, between them, is the threading cycle: no canned cycle series).
inline bool is_canned_cycle(int motion_tenths) {
  return motion_tenths >= 730 && motion_tenths != 760 && motion_tenths != 800;
}

struct Interpreter::State {
  struct Mark {
    std::int64_t position = 0;  // byte offset in the file
    int line = 0;
    std::size_t file = 0;  // index in `files`
  };

  // The program and the subroutine files its calls opened (o<name> call finds name.ngc beside
  // the program or on the subroutine path), each read a line at a time.
  struct SourceFile {
    explicit SourceFile(const std::filesystem::path& file)
        : lines(file), path(file), name(file.string()) {}
    LineSource lines;
    std::filesystem::path path;
    std::string name;
  };
  std::vector<std::unique_ptr<SourceFile>> files;  // files[0] is the program
  Mark next{0, 1, 0};
  Mark current;                   // the line being executed
  LineSource* reading = nullptr;  // the file of `next`: jump() keeps it
  const std::string& file_name() const { return files[current.file]->name; }

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
  int spindle_direction = 0;    // 1 clockwise (M3), -1 counterclockwise (M4), 0 stopped
  int motion = 0;               // G code times ten of the active motion mode, -1 after G80
  bool retract_to_old = false;  // G99 (retract to R) until G98, as LinuxCNC starts
  Position pos{};               // program coordinates
  int coord_system = 1;
  Position g92_mm{};  // G92 and G52 offsets (one offset in LinuxCNC)
  // The active coordinate system's XY rotation (G10 L2 R), deg, about its origin: a machine
  // position's XY is R(rotation) (program + G92) + G5x + tool, as LinuxCNC composes them.
  double rotation_deg = 0.0;
  double rotation_sent_deg = 0.0;  // the rotation last handed on (xy_rotation)
  Position tool_offset_mm{};
  int tool_in_spindle = 0;
  int selected_tool = 0;
  int path_mode = 64;
  double path_tolerance = 0.0;
  double naive_tolerance = 0.0;  // G64's Q
  bool tool_length_g43 = false;  // the last tool length code was G43 (its offset may be zero)
  bool mist = false, flood = false;
  // M48-M53: LinuxCNC starts with the overrides and feed hold enabled, adaptive feed disabled.
  bool feed_override_on = true, speed_override_on = true, adaptive_feed_on = false,
       feed_hold_on = true;
  // G41/G42: moves go through it, and every other command too (it holds them behind a move
  // whose end the next move settles). `pos` stays the programmed point.
  CutterCompensation compensation;
  bool straight_exit = false;  // offset moves ended at G40: the next move must be straight
  int move_column = 1;         // where the block's motion is, for errors found making it
  // After G40 the tool stays off the programmed point until the next move. A tool change
  // takes the machine's position as the program's (LinuxCNC re-reads it), so it matters then.
  std::optional<Position> tool_off_path;
  // Where rs274's canonical layer holds the tool, program coordinates: the last move's end,
  // moved with G5x and G92 offsets but not with tool length offsets or rotations. After a block
  // with a tool change LinuxCNC re-reads the position from there (`resync_position`), dropping
  // what a G43 on the same line did to the program position.
  Position canon_pos{};
  bool resync_position = false;

  // Canned cycles: sticky words and the level the current series started from.
  double cycle_r = 0.0, cycle_z = 0.0;  // mm
  double cycle_q = 0.0, cycle_p = 0.0;
  double cycle_old_cc = 0.0;
  bool cycle_series = false;
  bool motion_changed = false;  // this block changes the motion mode

  // M70/M73's saved modal state, as LinuxCNC's save_settings keeps it (modal_context.cpp): G
  // codes in LinuxCNC's slots (its active_g_codes, times ten, -1 for none), M codes in its
  // slots (active_m_codes), and F, S and G64's P and Q.
  struct ModalContext {
    std::array<int, 17> g{};
    std::array<int, 9> m{};
    double feed = 0.0, speed = 0.0, path_tolerance = 0.0, naive_tolerance = 0.0;
  };
  // A call's (or the main program's) saved state: M70 and M73 make it valid, M71 invalidates
  // it, M73 also restores it when the call returns.
  struct SavedContext {
    ModalContext modes;
    bool valid = false;
    bool restore_on_return = false;
  };
  SavedContext main_context;  // the main program's, LinuxCNC's call level 0

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
    bool fanuc = false;   // M98's call of an O-number program, which M99 ends
    Mark start;           // the definition's line
    long repeats = 0;     // M98 L: runs still to make after this one
    long iterations = 0;  // runs made (bounded by max_loop_iterations)
    SavedContext context;
  };
  std::vector<Call> calls;
  // Subroutines by label: `o<name> sub` lines, or Fanuc O-number lines (`fanuc`), which only
  // M98 calls, as LinuxCNC keeps the two apart.
  struct Definition {
    Mark mark;
    bool fanuc = false;
  };
  std::map<std::string, Definition> subroutines;
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
        std::vector<Warning>& warns);

  // ---- the run (interpreter.cpp) ---------------------------------------------------------
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
  // Parameters set on a line take effect before it runs, with every value read before them.
  void apply_assignments(const Block& block);

  // ---- the source ------------------------------------------------------------------------
  // The next line into `line`, a view valid until the next read.
  // Inlined: it is on the path of every line (the compiler stopped inlining it on its own).
  [[gnu::always_inline]] bool read_line(std::string_view& line) {
    current = next;
    const auto read = reading->read(next.position);
    if (!read) {
      if (reading->failed()) cannot_read();
      return false;
    }
    line = read->first;
    next = {read->second, current.line + 1, current.file};
    return true;
  }
  [[noreturn, gnu::cold, gnu::noinline]] void cannot_read() const;
  void jump(const Mark& mark) {
    next = mark;
    reading = &files[mark.file]->lines;
  }
  // The line after the one at `mark`.
  Mark after(const Mark& mark);

  [[noreturn]] void fail(int column, const std::string& message) const {
    throw GcodeError(file_name(), current.line, column, message);
  }
  void warn(const std::string& message) { warnings.push_back({current.line, message}); }

  // ---- units -----------------------------------------------------------------------------
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

  // ---- output ----------------------------------------------------------------------------
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

  // ---- a block's steps (execute_block.cpp) -----------------------------------------------
  void execute_block(const Block& block);
  void emit_comments(const Block& block);
  void set_feed_speed_and_tool(const Block& block, const Code* feed_mode_code);
  void set_feed_mode(const Block& block, int code);  // G93, G94, G95
  void execute_m_codes(const Block& block);
  // M48-M53 (still passed on as events): which overrides are on, for M70's saved state.
  void set_override_state(const Block& block, int code);
  void dwell_if_asked(const Block& block, const Code* non_modal);
  // Plane, units, cutter compensation, tool length, coordinate system, path control, distance
  // and retract modes. Clears `has_axis` where the axis words were an offset (G43.1).
  void set_modes(const Block& block, bool& has_axis);
  void set_units(LengthUnits wanted);
  void set_path_control(const Block& block, const Code& code);
  // M98 with nothing else on its line but P and L.
  void call_fanuc_program_alone(const Block& block);
  void stop_or_end(const Block& block);
  void end_program(const Block& block);

  // ---- the block's words (word_checks.cpp) -----------------------------------------------
  // Sorts the block's codes into g_by_group and m_by_group, refusing two of one group; M codes
  // with no meaning here are passed on as events.
  void group_codes(const Block& block);
  // A word that must hold a number in [low, high] before it is converted to an integer.
  void require_word_in_range(const Block& block, char letter, double low, double high,
                             const std::string& what) const;
  // Words no code of the block uses are refused, as rs274 refuses them.
  void refuse_unused_words(const Block& block) const;
  // An M-code neither LinuxCNC's nor a user one (M100-M199): refused at its column.
  [[noreturn]] void refuse_unknown_m_code(const Code& code) const;
  void require_feed(const Block& block, int column) const {
    if (feed_mode == FeedMode::inverse_time ? !block.has('f') : !(feed > 0.0)) missing_feed(column);
    if (feed_mode == FeedMode::units_per_revolution && !(speed > 0.0)) missing_feed(column);
  }
  // A motion code other than G0-G3 and G80 with neither axis nor polar words: rs274's "All axes
  // missing with motion code".
  void refuse_motion_without_axes(const Block& block) const;
  // G33, G33.1 and G76 take their words (K, I J K P ...) and need axis words and a turning
  // spindle; these are refused before the block runs, as rs274 refuses them.
  void check_synchronised_words(const Block& block) const;
  // The motion the block makes: its group 1 code, or the modal one when it has axis words of
  // its own (not those of G10, G28, G30, G52, G92); -1 for none.
  int block_motion(const Block& block) const;
  [[noreturn]] void refuse_g_code(const Code& code) const;  // unknown, or a lathe cycle
  [[noreturn, gnu::cold, gnu::noinline]] void missing_feed(int column) const;

  // ---- coordinate systems and offsets (coordinate_systems.cpp) ---------------------------
  Position g5x_mm(int system) const;
  double rotation_of(int system) const { return parameters.numbered(5210 + 20 * system); }
  // Everything between program and machine coordinates but the rotation, mm.
  Position total_offset_mm() const;
  // What lies between program and machine coordinates, kept to re-express the position when
  // it changes.
  struct Offsets {
    Position total_mm, g5x_mm, g92_mm, tool_mm;
    double rotation_deg;
  };
  Offsets offsets() const {
    return {total_offset_mm(), g5x_mm(coord_system), g92_mm, tool_offset_mm, rotation_deg};
  }
  // The machine position (mm, deg) of program coordinates, and back, under the active offsets.
  Position machine_mm(const Position& program) const;
  Position program_from_machine(const Position& machine_mm) const;
  // Moves the program position so the machine position stays put when offsets change from
  // `old`. LinuxCNC's G10 L2/L20 on the active system turns the position without its G92
  // offset (`g92_turns` false), which moves the machine when both a G92 offset and a change of
  // rotation are in effect; so does pkm, to make the same moves.
  void reexpress(const Offsets& old, bool g92_turns = true);
  void emit_offsets(const Block& block);
  // Where the block's axis words lead, into `end` (the current point where a word is missing).
  void target(const Block& block, bool machine_coordinates, Position& end) const;
  Position target(const Block& block, bool machine_coordinates) const {
    Position end;
    target(block, machine_coordinates, end);
    return end;
  }
  // G53's X and Y under a rotation: machine coordinates turned into the program's.
  void machine_xy_under_rotation(const Block& block, Position& end) const;
  void select_coordinate_system(const Block& block, const Code& code);
  // G10, G28, G30, G28.1, G30.1, G52 and G92..G92.3; true when the axis words were theirs.
  bool execute_non_modal(const Block& block, const Code& code);
  void set_coordinates(const Block& block);
  void set_coordinate_system(const Block& block, long l, long p);
  // G10 L20's new origin of `system` (mm): the current point gets the block's coordinates there.
  Position origin_making_current(const Block& block, int system) const;
  // The current point in `system` (mm, deg) as LinuxCNC finds it for G10, with the
  // tool length offset taken off (`without_tool`) for G10 L10/L11.
  Position current_in_system_mm(int system, bool without_tool) const;
  void set_tool_entry(const Block& block, long l, long p, int column);
  void set_tool_offset_from_current(const Block& block, long l, ToolEntry& entry) const;
  void go_home(const Block& block, int code);
  void store_home(int code);
  void set_axis_offsets(const Block& block, int code);

  // ---- motion (motion.cpp) ---------------------------------------------------------------
  // The block's move in the active motion mode (axis words given, or G0-G3 alone).
  void make_motion(const Block& block, const Code* motion_code, bool machine_coordinates);
  void straight(CanonKind kind, const Block& block, const Position& end);
  void arc(const Block& block, int code, const Position& end);
  std::array<double, 2> arc_centre_from_radius(const Block& block, int code,
                                               const std::array<double, 2>& start,
                                               const std::array<double, 2>& end) const;
  // An I/J/K centre must be as far from the start as from the end, within LinuxCNC's tolerance.
  void check_arc_radii(int column, const std::array<double, 2>& centre,
                       const std::array<double, 2>& start, const std::array<double, 2>& end) const;
  void probe(const Block& block, int column, const Position& end);
  // The speed of the spindle a move fed per revolution follows: 0 when it is stopped.
  double turning_rpm() const { return spindle_direction != 0 ? speed : 0.0; }
  void require_turning_spindle(int code) const;
  // Spindle-synchronised motion: G33's straight move, G33.1's rigid tap (motion.cpp), and the
  // START_SPEED_FEED_SYNC that opens them and G76's passes.
  void start_synchronisation(const Block& block, double pitch);
  void synchronised_move(const Block& block, const Position& end);
  void rigid_tap(const Block& block, const Position& end);
  // A straight feed at `pitch` units per revolution of the spindle (G33, G76's passes).
  void synchronised_feed(const Block& block, const Position& end, double pitch);
  // G76 (threading.cpp): passes of synchronised feeds, deeper each time.
  void threading_cycle(const Block& block, const Position& end);
  void require_thread_words(const Block& block, const Position& end) const;
  ThreadPasses thread_passes(const Block& block, const Position& end) const;
  void threading_pass(const Block& block, const ThreadPasses& passes, double depth);
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
    canon_pos = move.end;
  }

  // ---- canned cycles (canned_cycles.cpp) -------------------------------------------------
  void cycle(const Block& block, int code, const Position& end);
  // The block's sticky words taken, its levels along the plane's normal worked out.
  CycleLevels cycle_levels(const Block& block, int code);
  void cycle_move(const Block& block, const CycleLevels& levels, CanonKind kind, double at_1,
                  double at_2, double height);
  void cycle_hole(const Block& block, int code, const CycleLevels& levels, double at_1,
                  double at_2);
  void peck(const Block& block, int code, const CycleLevels& levels, double at_1, double at_2);
  // G84 (right hand) and G74 (left hand): in with the spindle, out with it reversed.
  void tap(const Block& block, int code, const CycleLevels& levels, double at_1, double at_2);
  void emit_overrides(const Block& block, bool enabled);
  void orient_spindle(const Block& block);

  // ---- tools and cutter compensation (tools.cpp) -----------------------------------------
  void select_tool(const Block& block);
  void change_tool(const Block& block, const Code& code);
  void set_tool_length_offset(const Block& block, const Code& code, bool& has_axis);
  // The offsets (mm, deg) of the tool G43's or G43.2's H names, or of the tool in the spindle.
  Position table_tool_offset(const Block& block, const Code& code) const;
  void set_compensation(const Block& block, const Code& code);
  void start_compensation(const Block& block, const Code& code);
  // The radius (program units) and lathe orientation G41/G42 or G41.1/G42.1 compensate for.
  struct CompensationTool {
    double radius = 0.0;
    int orientation = 0;
  };
  CompensationTool compensation_tool(const Block& block, const Code& code);
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
  void require_finite_tool(const ToolEntry& entry, int column) const {
    bool finite = std::isfinite(entry.diameter);
    for (const double value : entry.offset) finite = finite && std::isfinite(value);
    if (!finite) fail(column, "calculation resulted in infinity or NaN (a tool offset too large)");
  }

  // ---- M70-M73 (modal_context.cpp) ------------------------------------------------------
  SavedContext& context_here() { return calls.empty() ? main_context : calls.back().context; }
  ModalContext active_modes() const;
  void save_or_restore_modes(const Code& code);  // M70, M71, M72, M73
  // Makes `saved` the modal state again, as LinuxCNC does: by executing the G and M codes that
  // differ (units first), and always F, S and G64's P and Q. `what` names the restoring code
  // for errors and warnings, at `column`.
  void restore_modes(const ModalContext& saved, int column, const std::string& what);
  void execute_restoring(const std::string& line, int column, const std::string& what);
  // A call's M73 state restored as the call returns (endsub, return, M99).
  void restore_on_return(const SavedContext& leaving, int column);

  // ---- O-word flow (o_word_flow.cpp) -----------------------------------------------------
  void execute_o_word(const Block& block);
  double o_value(const OWord& o) const;
  // The innermost open frame is `type` and belongs to `label`.
  bool innermost_is(Frame::Type type, const std::string& label) const {
    return !flow.empty() && flow.back().type == type && flow.back().label == label;
  }
  void call_subroutine(const OWord& o);
  void return_from_subroutine(const OWord& o);
  // Leaves the innermost call for the line after it; `column` is the returning code's.
  void leave_call(int column);
  // M98 P L (Fanuc-style subprogram call) and M99 (its return, or the main program's end).
  void call_fanuc_program(const Block& block, const Code& m98);
  void return_from_fanuc_program(const Block& block, const Code& m99);
  void o_if(const OWord& o);
  void o_else(const OWord& o);
  void o_while(const OWord& o);
  void o_endwhile(const OWord& o);
  void o_repeat(const OWord& o);
  void o_endrepeat(const OWord& o);
  void o_break_or_continue(const OWord& o);
  void skip_to(const std::string& label, std::initializer_list<std::string_view> keywords,
               std::string* found_keyword, int column, bool* with_value = nullptr);
  // Where subroutine `label` starts: known already, defined further on in this file, or in a
  // file of its name on the subroutine path. `fanuc`: called by M98 (an O-number program).
  Mark find_subroutine(const std::string& label, bool fanuc, int column);
  // Reads on to the end of the file `mark` is in, registering the definitions found, until
  // `label`'s; where it is, or nothing. Leaves the position as it was.
  std::optional<Mark> scan_for_definition(const Mark& mark, const std::string& label);
  // The file `label`'s subroutine lives in by itself (name.ngc), opened, or nothing.
  std::optional<Mark> open_subroutine_file(const std::string& label, int column);
  // Bounds (docs/gcode.md): one more round of `loop`, one more unit of the program's work.
  void count_loop_iteration(Frame& loop, int column);
  void count_program_iteration(int column);
  // `what` ("o<name> call", "M98 P100") may nest one more call.
  void require_call_depth(const std::string& what, int column) const;
  // Where subroutine files are looked for: beside the program, then the subroutine path.
  std::vector<std::filesystem::path> subroutine_directories() const;
};

}  // namespace pkm::gcode
