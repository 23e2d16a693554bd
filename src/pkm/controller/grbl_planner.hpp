// A model of grbl 1.1's motion planner and serial line (docs/grbl.md, "The planner model"): how
// long a joint program takes on a grbl-class controller, read line by line as a character-counting
// sender streams it. It follows grbl's rules as read in its planner.c and stepper.c, not its code:
// targets rounded to whole steps, per-axis rate and acceleration limits along each block's
// direction, junction deviation at corners, a look-ahead of planner_blocks - 1 blocks of which the
// newest always ends at rest, the executing block re-profiled from its current speed whenever a
// block arrives, M3/M4/M5, G4 and program ends waiting for the motion to finish, and lines that
// reach the controller no faster than the serial line and the receive buffer let them.
#pragma once

#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/machine/controller.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::controller {

// One grbl axis, in the units of the joint program (mm or deg) and seconds.
struct GrblAxis {
  char letter = 'X';
  double steps_per_unit = 0.0;    // $100..
  double max_rate = 0.0;          // $110.. / 60: units/s
  double max_acceleration = 0.0;  // $120..: units/s^2
};

struct GrblSetup {
  std::vector<GrblAxis> axes;
  machine::ControllerSettings settings;
  // Where grbl's axes stand when the program starts (units); empty: at zero.
  std::vector<double> start;
};

// The axes `pkm export grbl` gives the machine's joints, and its [controller] table, starting at
// home (the joints' values there, as the controller is zeroed). Throws std::invalid_argument
// where the machine has no [controller] table, a joint has no steps or home has no joints.
GrblSetup grbl_setup_of(const machine::Machine& machine);

struct GrblPrediction {
  double time_s = 0.0;          // from the program's first byte sent to the end of its motion
  double motion_start_s = 0.0;  // when the first block starts
  long blocks = 0;              // motion blocks planned (lines moving no axis by a step: none)
  long lines = 0;
  // The same program with unbounded look-ahead and an instant serial line: what grbl's per-axis
  // limits, junctions, feeds and stops alone allow; time_s - unlimited_time_s is what the
  // look-ahead and the line cost.
  double unlimited_time_s = 0.0;
  double path_length = 0.0;        // of the planned blocks, units (mm, deg)
  double mean_acceleration = 0.0;  // over the blocks, weighted by length: units/s^2
  // The stretch between two stops (a pen or spindle command, a dwell, the end) that the
  // look-ahead and the line slow most: the tag of the line of its first block (post: the job's
  // line) and the seconds it takes beyond its unlimited time.
  int slowest_stretch_tag = 0;
  double slowest_stretch_lost_s = 0.0;
};

// Fed the lines of a joint program in order; O(planner_blocks) work per line, memory bounded by
// the look-ahead except for the unlimited comparison, which holds the blocks between two stops.
class GrblTimeModel {
 public:
  explicit GrblTimeModel(GrblSetup setup);
  // Throws std::invalid_argument for a word it cannot read (the line is quoted). `tag` is the
  // caller's number for the line (post: the job line it was written for), returned as
  // slowest_stretch_tag.
  void add_line(std::string_view line, int tag = 0);
  GrblPrediction finish();

  // A planner block, exposed for the tests: length (units), acceleration (units/s^2), nominal
  // speed (units/s), and the squared speeds the planner keeps.
  struct Block {
    double length = 0.0;
    double acceleration = 0.0;
    double nominal = 0.0;
    double max_entry_sqr = 0.0;
    double entry_sqr = 0.0;
  };

 private:
  struct Sent {
    double ack_s;
    std::size_t bytes;
  };
  double arrival_of(std::size_t bytes);
  void read_words(std::string_view line, bool& motion, bool& sync, double& dwell_s);
  void plan_move();
  void recalculate();
  // Moves the executing point until `until_s` or until the buffer holds fewer than `keep`
  // blocks, whichever comes first.
  void advance(double until_s, std::size_t keep);
  void wait_for_stop();
  void flush_unlimited();

  GrblSetup setup_;
  double byte_s_;
  std::size_t capacity_;
  // The sender and the line.
  std::deque<Sent> in_flight_;
  double line_free_s_ = 0.0;
  double processed_s_ = 0.0;
  // The parser's modal state.
  bool rapid_ = true, inverse_time_ = false, first_line_ = true;
  double feed_ = 0.0;
  std::vector<double> target_;
  // The planner.
  std::vector<long> position_steps_;
  std::vector<double> previous_unit_;
  double previous_nominal_ = 0.0;
  std::deque<Block> buffer_;
  double now_s_ = 0.0, speed_ = 0.0;
  std::vector<Block> unlimited_;
  GrblPrediction prediction_;
  // The stretch being planned since the last stop: its first block's tag and start.
  int line_tag_ = 0, stretch_tag_ = 0;
  double stretch_start_s_ = 0.0;
  double acceleration_length_ = 0.0;
  bool started_ = false;
};

// The time (s) of one block's trapezoid: from `entry` to at most `nominal` and down to `exit`
// (units/s) at `acceleration` over `length`.
double trapezoid_time_s(double length, double acceleration, double entry, double nominal,
                        double exit);

// Plans `blocks` with every block known (the reverse and forward passes of grbl over all of them,
// from rest to rest) and returns their time: the unlimited look-ahead.
double planned_time_s(std::vector<GrblTimeModel::Block> blocks);

}  // namespace pkm::controller
