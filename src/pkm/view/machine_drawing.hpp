// The machine drawn to scale as line segments in machine coordinates (mm): what stays put (base,
// rails, pulleys, the work envelope) once, and what moves (legs, struts, cables, platform, tool)
// at a pose. Hexapods: base and platform hexagons and the six legs; glides: rails over their
// travel, carriages and struts; cable plotters: pulleys, cables and the effector; other models:
// the tool and the envelope only (docs/html-views.md).
#pragma once

#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::view {

// How a segment is drawn: the page gives each kind its colour and width.
enum class Part { frame = 0, link = 1, platform = 2, tool = 3, envelope = 4 };

struct Segment {
  Part part = Part::frame;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
};

// True when the machine is best seen from the front as a plane (x right, y up): cable plotters
// and machines that control neither z nor an angle.
bool drawn_planar(const Machine& machine);

// The parts that never move.
std::vector<Segment> fixed_parts(const Machine& machine);

// The parts that move, at `pose` (mm, rad) with its joints (mm, rad) as inverse kinematics gave
// them.
std::vector<Segment> moving_parts(const Machine& machine, const Pose& pose,
                                  const JointVector& joints);

}  // namespace pkm::view
