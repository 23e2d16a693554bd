// Cutter radius compensation (G41/G42, G41.1/G42.1) the way LinuxCNC's interpreter does it.
//
// The tool runs one radius to the left or right of the programmed path (in the XY or XZ plane).
// Where two moves meet at an inside (concave) corner, the first must end early, where the two
// offset paths cross; that point is known only once the second move has been read. So each
// compensated move is held until the next one settles its end, and every other command made
// meanwhile is held behind it, keeping the program's order. Outside (convex) corners get an arc
// about the programmed corner. The geometry, the 0.05 rad that tells a corner from a
// straight-through join, and the paths refused as gouging are LinuxCNC's, so `pkm gcode --canon`
// matches `rs274 -g` move for move (tests/test_gcode_conformance.cpp; docs/gcode.md).
//
// A lathe tool (orientation 1-8 in the XZ plane) is controlled by its tip, which lies off the
// centre of its nose radius: every compensated move goes out with X and Z moved by the radius
// as the orientation says, as LinuxCNC does (docs/gcode.md, "Lathe tool orientation").
#pragma once

#include <functional>
#include <stdexcept>
#include <vector>

#include "pkm/gcode/canon.hpp"

namespace pkm::gcode {

enum class CompensationSide { off, left, right };

// A point in the compensation plane: its first and second axis (X Y in G17, Z X in G18), the
// order of an arc's centre in Canon.
struct PlanePoint {
  double first = 0.0, second = 0.0;
};

// A path the tool cannot follow; the interpreter adds file:line:column.
class CompensationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CutterCompensation {
 public:
  using Sink = std::function<void(const Canon&)>;

  // Starts a program: nothing held, compensation off; commands go to `out`.
  void reset(const Sink& out);

  bool on() const { return side_ != CompensationSide::off; }
  CompensationSide side() const { return side_; }
  // On with a radius above zero: moves are offset (a zero radius leaves them as programmed).
  bool offsetting() const { return on() && radius_ > 0.0; }

  // G41/G42: `radius` in program units; a negative one swaps the side, as LinuxCNC does.
  // `plane` must be XY or XZ (the caller checks and reports it); `orientation` is a lathe
  // tool's (1-8, XZ only), 0 or 9 for a round tool.
  void turn_on(CompensationSide side, double radius, Plane plane, int orientation = 0);
  // G40. True when offset moves ended here: the next move must then be straight.
  bool turn_off();
  // Where the tool is: `programmed` with the plane's coordinates those of the last offset move.
  Position tool_position(Position programmed) const {
    set_in_plane(programmed, tool_);
    return from_tip(programmed);
  }
  // M0, M1, M60 and the program's end: the held commands go out, the last move ending where the
  // tool is. Compensation stays on (M2 and M30 then call turn_off()).
  void flush();

  // Moves are held (pass() would queue a command behind them).
  bool holding() const { return !held_.empty(); }
  // Any command other than a compensated move: out at once, or behind the held moves.
  void pass(const Canon& canon) {
    if (held_.empty()) {
      (*out_)(canon);
    } else {
      held_.push_back({canon, {}, 0.0, false});
    }
  }

  // A straight move (traverse or feed) programmed from `start` to `move.end`.
  void straight(Canon move, const Position& start);
  // An arc programmed from `start` to `move.end` about `move.center` (plane coordinates), turning
  // `move.turns` (+ counterclockwise).
  void arc(Canon move, const Position& start);

  // G20/G21 while on: the held moves and the tool position follow the program into `units`.
  void rescale(double factor, LengthUnits units);

 private:
  struct Held {
    Canon canon;
    PlanePoint direction;        // lines: the programmed direction (gouge check when the end moves)
    double sweep = 0.0;          // arcs: the swept angle as queued, rad (0: not checked)
    bool lathe_lead_in = false;  // the feed to the start of a lathe tool's entry arc
  };

  PlanePoint in_plane(const Position& position) const;
  void set_in_plane(Position& position, PlanePoint point) const;
  bool tool_inside(int turns) const;  // the tool runs inside an arc turning this way
  const Held* previous_move() const;

  bool lathe_tool() const { return orientation_ != 0 && orientation_ != 9; }
  // `position` with X and Z moved from the nose radius's centre to the lathe tool's tip.
  Position from_tip(Position position) const;
  void send(const Canon& canon) const;  // a move moved for a lathe tool, then out
  void hold(const Canon& move, PlanePoint direction, double sweep, bool lathe_lead_in = false) {
    held_.push_back({move, direction, sweep, lathe_lead_in});
  }
  void release();                    // the held commands go out as they are
  void end_held_at(PlanePoint end);  // the held moves end at `end`, then go out
  void set_start(PlanePoint start) {
    start_ = start;
    start_known_ = true;
  }

  // Goes round an outside corner of the programmed path at `corner`, from the tool's position
  // to `to`: an arc about the corner, or for a traverse (there is no rapid arc) straight there.
  void round_corner(const Canon& move, const Position& start, PlanePoint corner, PlanePoint to);
  void enter_straight(Canon move, const Position& start);
  void enter_arc(Canon move, const Position& start);

  const Sink* out_ = nullptr;
  CompensationSide side_ = CompensationSide::off;
  double radius_ = 0.0;  // program units
  Plane plane_ = Plane::xy;
  int orientation_ = 0;
  bool entering_ = true;  // the next offset move is the first after G41/G42
  PlanePoint tool_;       // where the tool is: the end of the last offset move
  PlanePoint start_;      // where the first held move starts, when known
  bool start_known_ = false;
  std::vector<Held> held_;
};

}  // namespace pkm::gcode
