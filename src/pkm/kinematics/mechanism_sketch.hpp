// A kinematic model drawn to scale as line segments in machine coordinates (mm): what stays put
// (base, rails over their travel, pulleys) once, and what moves (legs, struts, arms, cables,
// platform, tool) at a pose. Kinematics::sketch() gives it; view/machine_drawing.hpp adds the work
// envelope and hands the lines to the HTML views.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::kinematics {

// What a line is part of: the page gives each its colour and width. The envelope is the work
// envelope's box, which the views add: never a model's.
enum class SketchPart { frame = 0, link = 1, platform = 2, tool = 3, envelope = 4 };

struct SketchLine {
  SketchPart part = SketchPart::frame;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
};

// A joint's travel (mm, or rad for a rotary joint), from the machine file's limits.
struct JointTravel {
  double min = 0.0, max = 0.0;
};

class MechanismSketch {
 public:
  virtual ~MechanismSketch() = default;

  // The parts that never move; `travel` holds every joint's, in joint order.
  virtual void fixed_parts(std::span<const JointTravel> travel,
                           std::vector<SketchLine>& out) const = 0;
  // The parts that move, at `pose` (mm, rad) with its joints as inverse kinematics gave them.
  virtual void moving_parts(const geometry::Pose& pose, const JointVector& joints,
                            std::vector<SketchLine>& out) const = 0;
};

// The closed polygon through `corners`.
void sketch_loop(std::vector<SketchLine>& out, SketchPart part,
                 const std::vector<Eigen::Vector3d>& corners);
// A circle of `radius` about `centre` in the plane spanned by unit vectors u and v, as 24 chords.
void sketch_circle(std::vector<SketchLine>& out, SketchPart part, const Eigen::Vector3d& centre,
                   double radius, const Eigen::Vector3d& u, const Eigen::Vector3d& v);

}  // namespace pkm::kinematics
