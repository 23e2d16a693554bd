// The machine drawn to scale as line segments in machine coordinates (mm): what stays put (base,
// rails, pulleys, the work envelope) once, and what moves (legs, struts, cables, platform, tool)
// at a pose. The mechanism is the model's own sketch (Kinematics::sketch(): hexapods, glides,
// cable plotters, rotary deltas); models without one show the envelope only (docs/html-views.md).
#pragma once

#include <vector>

#include "pkm/kinematics/mechanism_sketch.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::view {

// A line of the drawing and what it is part of (the page gives each kind its colour and width):
// the model's own (mechanism_sketch.hpp) and the envelope's.
using Part = kinematics::SketchPart;
using Segment = kinematics::SketchLine;

// True when the machine is best seen from the front as a plane (x right, y up): cable plotters
// and machines that control neither z nor an angle.
bool drawn_planar(const machine::Machine& machine);

// The parts that never move.
std::vector<Segment> fixed_parts(const machine::Machine& machine);

// The parts that move, at `pose` (mm, rad) with its joints (mm, rad) as inverse kinematics gave
// them.
std::vector<Segment> moving_parts(const machine::Machine& machine, const geometry::Pose& pose,
                                  const kinematics::JointVector& joints);

}  // namespace pkm::view
