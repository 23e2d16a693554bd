#include "pkm/certify/move_proof.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "pkm/bounds/assembly_mode.hpp"
#include "pkm/bounds/cable_bound.hpp"
#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/bounds/mechanism_rate.hpp"
#include "pkm/certify/proof_wording.hpp"
#include "pkm/kinematics/assembly_mode_bounds.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/hanging_cables.hpp"

namespace pkm::certify {

std::string_view verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::proven:
      return "proven";
    case Verdict::violated:
      return "violated";
    case Verdict::undecided:
      return "undecided";
  }
  return "unknown";
}

namespace {

// What a piece spans: its middle pose, its chord (zero in the coordinates the model does not
// control), its half-length in the scaled norm and, for an arc, how far it bows off the chord.
struct PieceSpan {
  geometry::Vector6d centre;
  geometry::Vector6d chord;
  double radius = 0.0;
  double sagitta = 0.0;
  bool line = true;
};

// A quantity not proven within its limit over a piece: how far its bound reaches, and the limit.
struct Unproven {
  Quantity quantity = Quantity::none;
  int index = -1;
  double reach = 0.0, limit = 0.0;
  int other = -1;  // joint angle: the end; clearance: the second leg
};

// The first joint angle or leg clearance whose reach over the ball of `radius` about the piece's
// middle (bounds::mechanism_reach) may pass its limit.
std::optional<Unproven> unproven_leg_limit(const kinematics::Kinematics& model,
                                           const geometry::Vector6d& centre,
                                           const kinematics::JointVector& joints,
                                           const kinematics::LegMotion& motion, double radius) {
  if (!model.has_mechanism_limits()) return std::nullopt;
  std::vector<kinematics::MechanismLimit> values;
  model.mechanism_limits(geometry::Pose::from_vector(centre), values);
  const std::optional<kinematics::LegEnds> ends =
      bounds::legs_at(model, geometry::Pose::from_vector(centre), joints);
  for (const kinematics::MechanismLimit& value : values) {
    const bounds::Reach reach =
        bounds::mechanism_reach(value, motion, radius, ends ? &*ends : nullptr);
    const bool angle = value.code == kinematics::StatusCode::joint_angle;
    const double falls = angle ? reach.up : reach.down;  // how far the margin can fall
    if (!(value.margin() - falls >= 0.0)) {
      return Unproven{angle ? Quantity::joint_angle : Quantity::clearance, value.leg,
                      angle ? value.value + falls : value.value - falls, value.limit, value.other};
    }
  }
  return std::nullopt;
}

// The first joint whose range over the piece (its value at the middle, the first-order change
// along the chord, the second-order bend) is not proven within [min, max].
std::optional<Unproven> unproven_joint(const machine::Machine& machine, const PieceSpan& span,
                                       const kinematics::JointVector& joints,
                                       const kinematics::JointJacobian& jacobian,
                                       const kinematics::HessianBounds& hessians) {
  for (int i = 0; i < joints.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double slope = 0.5 * std::abs(jacobian.row(i).dot(span.chord));
    const double bend = span.line ? hessians.along[k] / 8.0
                                  : 2.0 * span.sagitta * jacobian.block<1, 3>(i, 0).norm() +
                                        0.5 * hessians.norm[k] * span.radius * span.radius;
    const machine::JointSpec& spec = machine.joints()[k];
    const double low = joints[i] - slope - bend, high = joints[i] + slope + bend;
    if (!(low >= spec.min)) return Unproven{Quantity::joint, i, low, spec.min};
    if (!(high <= spec.max)) return Unproven{Quantity::joint, i, high, spec.max};
  }
  return std::nullopt;
}

// How far a coordinate of the piece strays from the middle's: half the chord, and for a position
// on an arc twice its sagitta (the box centre +- spread holds the piece).
double spread(const PieceSpan& span, int axis) {
  return 0.5 * std::abs(span.chord[axis]) + (axis < 3 ? 2.0 * span.sagitta : 0.0);
}

// The assembly mode over the box the piece lies in, for models whose mode is bounded over a box
// (a hexapod's: the platform tilted less than 90 deg, index -1, and each platform joint on home's
// side of the base plane, index: the leg, reach in mm; the bounds workspace takes over a cell).
std::optional<Unproven> unproven_mode_over_box(const kinematics::AssemblyModeBounds& modes,
                                               int home_mode, const PieceSpan& span) {
  geometry::Vector6d half;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) half[axis] = spread(span, axis);
  const std::optional<kinematics::ModeShortfall> shortfall =
      modes.mode_over_box(home_mode, span.centre, half);
  if (!shortfall) return std::nullopt;
  return Unproven{Quantity::assembly_mode, shortfall->leg, shortfall->low, 0.0};
}

// The first of the model's reach margins (DerivativeBounds::reach_over_cell: a glide's struts
// reaching their rails, a cable robot's cables clear of their anchors and its tensions holding
// the effector) not proven positive over the ball about the piece's middle that holds it (every
// pose of the piece is within half its length, `radius`, along the move).
std::optional<Unproven> unproven_reach(const kinematics::Kinematics& model,
                                       const geometry::Vector6d& centre, double radius,
                                       double angle_scale_mm) {
  const kinematics::DerivativeBounds* own = model.derivative_bounds();
  const int count = own != nullptr ? own->reach_count() : 0;
  if (count == 0) return std::nullopt;
  std::array<std::array<double, 2>, kinematics::kMaxJoints + 1> margins;
  own->reach_over_cell(centre, radius, radius, angle_scale_mm,
                       std::span(margins.data(), static_cast<std::size_t>(count)));
  for (int i = 0; i < count; ++i) {
    const double low = margins[static_cast<std::size_t>(i)][0];
    if (!(low > 0.0)) return Unproven{Quantity::reach, i, low, 0.0};
  }
  return std::nullopt;
}

// The model's reach margin measured in N whose refusal is `code` (a cable robot's tensions' room
// within tension_limits), and its value at `pose` (its bound over a ball of radius 0); none
// where the model has no such margin.
std::optional<std::pair<int, double>> force_margin_at(const kinematics::Kinematics& model,
                                                      const geometry::Vector6d& pose,
                                                      kinematics::StatusCode code,
                                                      double angle_scale_mm) {
  const kinematics::DerivativeBounds* own = model.derivative_bounds();
  const int count = own != nullptr ? own->reach_count() : 0;
  for (int i = 0; i < count; ++i) {
    const kinematics::ReachMargin margin = own->reach_margin(i);
    if (!margin.newtons || margin.failure.code != code) continue;
    std::array<std::array<double, 2>, kinematics::kMaxJoints + 1> margins;
    own->reach_over_cell(pose, 0.0, 0.0, angle_scale_mm,
                         std::span(margins.data(), static_cast<std::size_t>(count)));
    return std::pair{i, margins[static_cast<std::size_t>(i)][0]};
  }
  return std::nullopt;
}

// The first controlled coordinate whose range over the piece is not proven within the envelope.
std::optional<Unproven> unproven_envelope(const machine::CartesianLimits& limits,
                                          const std::vector<int>& axes, const PieceSpan& span) {
  for (const int axis : axes) {
    const double low = span.centre[axis] - spread(span, axis),
                 high = span.centre[axis] + spread(span, axis);
    if (!(low >= limits.envelope_min[axis])) {
      return Unproven{Quantity::envelope, axis, low, limits.envelope_min[axis]};
    }
    if (!(high <= limits.envelope_max[axis])) {
      return Unproven{Quantity::envelope, axis, high, limits.envelope_max[axis]};
    }
  }
  return std::nullopt;
}

Finding piece_finding(double u0, double u1, const geometry::Vector6d& pose, Quantity quantity,
                      int index, int other, double value, double limit) {
  Finding finding;
  finding.u0 = u0;
  finding.u1 = u1;
  finding.pose = pose;
  finding.quantity = quantity;
  finding.index = index;
  finding.other = other;
  finding.value = value;
  finding.limit = limit;
  return finding;
}

// An ideal cable plotter's pull region (cable_plotter.cpp, ideal_inverse): both cables pull while
// the pen stays on home's side of each anchor's vertical and the cables keep an angle between
// them. The sides are linear in x; the sine of the angle, det(u0, u1) with u the unit cables,
// moves by at most 1 / l0 + 1 / l1 per mm. The smallest margin (mm, or its sine) and its index.
struct PullMargin {
  double margin = INFINITY;
  int index = -1;  // 0, 1: anchor's vertical; 2: the angle between the cables
};

PullMargin pull_margin(const kinematics::CablePlotterGeometry& g, const geometry::Vector6d& home,
                       const geometry::Vector6d& centre, double x_spread, double radius) {
  PullMargin worst;
  std::array<Eigen::Vector2d, 2> unit;
  double rate = 0.0;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d& anchor = g.anchors_mm[static_cast<std::size_t>(i)];
    const double side = home[0] >= anchor.x() ? 1.0 : -1.0;
    const double margin = side * (centre[0] - anchor.x()) - x_spread;
    if (margin < worst.margin) worst = {margin, i};
    const Eigen::Vector2d from_anchor = centre.head<2>() - anchor;
    const double shortest = from_anchor.norm() - radius;
    rate += shortest > 0.0 ? 1.0 / shortest : INFINITY;
    unit[static_cast<std::size_t>(i)] = from_anchor.normalized();
  }
  const double sine = std::abs(unit[0].x() * unit[1].y() - unit[0].y() * unit[1].x());
  const double margin = sine - rate * radius - kinematics::kMinCableAngleSine;
  if (!(margin >= worst.margin)) worst = {margin, 2};
  return worst;
}

// A cable plotter as built (pulleys, a weighed or tilting effector, stretch), whose balance
// bounds::cable_box_bound bounds; nullptr for the ideal plotter and other models.
const kinematics::HangingCables* as_built_plotter(const kinematics::Kinematics& model) {
  const kinematics::HangingCables* cables = model.hanging_cables();
  return cables != nullptr && !cables->cable_geometry().ideal() ? cables : nullptr;
}

// The first of a cable plotter's quantities not proven over the box the piece lies in (its
// middle +- half its chord, plus twice its sagitta on an arc): with `joints_too` (no Hessian
// bound: the effector tilts or the cables stretch) each joint, the pass-through joints exactly;
// then both cables pulling (index 0, 1: that cable's tension; 2: the angle between them; 3:
// the balance unbounded) and the tension limits.
std::optional<Unproven> unproven_cable(const machine::Machine& machine,
                                       const kinematics::HangingCables& cables,
                                       const PieceSpan& span, bool joints_too) {
  Eigen::Vector2d half;
  for (int axis = 0; axis < 2; ++axis) half[axis] = spread(span, axis);
  // A line's piece is the segment itself: its tensions by the mean-value form along it.
  const Eigen::Vector2d half_chord = 0.5 * span.chord.head<2>();
  const bounds::CableBoxBound bound = bounds::cable_box_bound(
      cables.cable_geometry(), span.centre.head<2>(), half, span.line ? &half_chord : nullptr);
  if (!bound.known) return Unproven{Quantity::pull, 3, -INFINITY, 0.0};
  const kinematics::Kinematics& model = machine.kinematics();
  for (int joint = 0; joints_too && joint < model.joint_count(); ++joint) {
    const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
    bounds::Range range;
    if (const int axis = model.passthrough_axis(joint); axis >= 0) {
      range = {span.centre[axis] - spread(span, axis), span.centre[axis] + spread(span, axis)};
    } else {
      range = bound.joint_mm[static_cast<std::size_t>(joint)];
    }
    if (!(range.lo >= spec.min)) return Unproven{Quantity::joint, joint, range.lo, spec.min};
    if (!(range.hi <= spec.max)) return Unproven{Quantity::joint, joint, range.hi, spec.max};
  }
  for (int cable = 0; cable < 2; ++cable) {
    const bounds::Range& t = bound.tension_N[static_cast<std::size_t>(cable)];
    if (!(t.lo > 0.0)) return Unproven{Quantity::pull, cable, t.lo, 0.0};
  }
  if (!(bound.apart.lo > 0.0)) return Unproven{Quantity::pull, 2, bound.apart.lo, 0.0};
  const kinematics::CablePlotterGeometry& g = cables.cable_geometry();
  for (int cable = 0; cable < 2 && g.tension_limited; ++cable) {
    const bounds::Range& t = bound.tension_N[static_cast<std::size_t>(cable)];
    if (!(t.lo >= g.tension_min_N))
      return Unproven{Quantity::tension, cable, t.lo, g.tension_min_N};
    if (!(t.hi <= g.tension_max_N))
      return Unproven{Quantity::tension, cable, t.hi, g.tension_max_N};
  }
  return std::nullopt;
}

}  // namespace

// The outcome of bounding one piece: proven, refused at its middle, or neither (the first
// quantity whose bound reaches a limit, for the undecided report).
struct MoveProver::Outcome {
  enum Kind { proven, refused, open } kind = proven;
  kinematics::Status refusal;
  Finding open_at;
};

MoveProver::MoveProver(const machine::Machine& machine, ProofOptions options)
    : machine_(machine), options_(options) {
  const kinematics::Kinematics& model = machine.kinematics();
  axes_ = model.dof().axes();
  angle_scale_mm_ = bounds::pose_angle_scale_mm(model);
  const geometry::Vector6d home = machine.home().as_vector();
  cables_ = as_built_plotter(model);
  if (cables_ != nullptr) {
    // Pulleys, a weighed or tilting effector, stretch: the balance's bounds (bounds/cable_bound).
    unavailable_ = bounds::cable_bound_unavailable(cables_->cable_geometry());
  } else if (!bounds::inverse_hessian_bounds(model, home, 0.0, angle_scale_mm_, {})) {
    unavailable_ = "no bound on the derivatives of this kinematics model (" +
                   std::string(model.type()) + ") here";
  } else if (!bounds::has_assembly_bound(model, model.assembly_mode(machine.home()))) {
    unavailable_ = "no bound on the assembly mode of this kinematics model (" +
                   std::string(model.type()) + ") here";
  }
}

MoveProver::Outcome MoveProver::bound_piece(const motion::Segment& segment, double u0,
                                            double u1) const {
  const kinematics::Kinematics& model = machine_.kinematics();
  const double um = 0.5 * (u0 + u1);
  const geometry::Vector6d centre = segment.at(um);
  kinematics::JointVector joints;
  Outcome outcome;
  outcome.refusal = machine_.inverse(geometry::Pose::from_vector(centre), joints);
  if (!outcome.refusal.ok()) {
    outcome.kind = Outcome::refused;
    return outcome;
  }
  kinematics::JointJacobian jacobian;
  model.inverse_and_jacobian(geometry::Pose::from_vector(centre), joints, jacobian);
  const bounds::PieceMotion piece = bounds::piece_motion(segment, u0, u1, axes_, angle_scale_mm_);
  const bool line = segment.kind == motion::SegmentKind::line;
  const double radius = 0.5 * piece.length;
  const double sagitta = line ? 0.0 : piece.acceleration / 8.0;  // off the chord, position only
  geometry::Vector6d chord = segment.at(u1) - segment.at(u0);
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!model.dof().controls(axis)) chord[axis] = 0.0;
  }
  const auto hessians =
      bounds::inverse_hessian_bounds(model, centre, radius, angle_scale_mm_, piece.chord);
  if (!hessians && cables_ == nullptr) {
    outcome.kind = Outcome::open;
    outcome.open_at = piece_finding(u0, u1, centre, Quantity::none, -1, -1, 0.0, 0.0);
    return outcome;
  }
  // The first quantity not proven, kept for the report.
  const auto open = [&](Quantity quantity, int index, int other, double reach, double limit) {
    outcome.kind = Outcome::open;
    outcome.open_at = piece_finding(u0, u1, centre, quantity, index, other, reach, limit);
    return outcome;
  };
  const PieceSpan span{centre, chord, radius, sagitta, line};
  if (hessians) {
    if (const auto joint = unproven_joint(machine_, span, joints, jacobian, *hessians)) {
      return open(joint->quantity, joint->index, -1, joint->reach, joint->limit);
    }
  }
  if (const auto axis = unproven_envelope(machine_.cartesian(), axes_, span)) {
    return open(axis->quantity, axis->index, -1, axis->reach, axis->limit);
  }
  if (const auto reach = unproven_reach(model, centre, radius, angle_scale_mm_)) {
    return open(reach->quantity, reach->index, -1, reach->reach, reach->limit);
  }
  if (cables_ != nullptr) {
    // Cables as built: their balance bounded over the box the piece lies in (no legs, no mode).
    if (const auto cable = unproven_cable(machine_, *cables_, span, !hessians)) {
      return open(cable->quantity, cable->index, -1, cable->reach, cable->limit);
    }
    return outcome;
  }
  const kinematics::LegMotion motion =
      bounds::leg_motion(model, joints, jacobian, *hessians, radius, angle_scale_mm_);
  if (const auto leg = unproven_leg_limit(model, centre, joints, motion, radius)) {
    return open(leg->quantity, leg->index, leg->other, leg->reach, leg->limit);
  }
  if (const kinematics::HangingCables* hanging = model.hanging_cables()) {
    // An ideal plotter (one as built is bounded above): both cables pull.
    const double x_spread = spread(span, 0);
    const PullMargin pull = pull_margin(hanging->cable_geometry(), machine_.home().as_vector(),
                                        centre, x_spread, radius);
    if (!(pull.margin > 0.0)) return open(Quantity::pull, pull.index, -1, pull.margin, 0.0);
  }
  const int home_mode = model.assembly_mode(machine_.home());
  if (const kinematics::AssemblyModeBounds* modes = model.assembly_mode_bounds();
      modes != nullptr && modes->has_mode_over_box()) {
    if (const auto mode = unproven_mode_over_box(*modes, home_mode, span)) {
      return open(mode->quantity, mode->index, -1, mode->reach, mode->limit);
    }
    return outcome;
  }
  const auto mode =
      bounds::assembly_mode_over_ball(model, home_mode, centre, joints, motion.inner_speed);
  if (!mode || !(mode->value - mode->rate * radius > 0.0)) {
    return open(Quantity::assembly_mode, -1, -1, mode ? mode->value - mode->rate * radius : 0.0,
                0.0);
  }
  return outcome;
}

ProofWording MoveProver::wording() const {
  return ProofWording(machine_, cables_);
}

std::string MoveProver::quantity_name(Quantity quantity, int index, int other) const {
  return wording().quantity_name(quantity, index, other);
}

Finding MoveProver::earlier_violation(Finding found, const std::optional<Finding>& later) const {
  if (later && later->quantity == found.quantity && later->index == found.index &&
      later->other == found.other) {
    // Earlier, but perhaps not as far beyond: keep the farthest seen.
    if (!(excess(found, found.value) > excess(*later, later->worst_value))) {
      found.worst_u = later->worst_u;
      found.worst_value = later->worst_value;
    }
  }
  return found;
}

MoveProof MoveProver::prove(const motion::Segment& segment) const {
  MoveProof proof;
  if (segment.kind == motion::SegmentKind::dwell) return proof;
  if (!unavailable_.empty()) {
    proof.verdict = Verdict::undecided;
    Finding finding;
    finding.pose = segment.start;
    finding.u1 = 1.0;
    finding.text = unavailable_;
    proof.finding = finding;
    return proof;
  }
  kinematics::JointVector joints;
  if (const kinematics::Status at_start =
          machine_.inverse(geometry::Pose::from_vector(segment.at(0.0)), joints);
      !at_start.ok()) {
    proof.verdict = Verdict::violated;
    proof.finding = refusal_at(segment, 0.0, at_start);
    return proof;
  }
  struct Span {
    double u0, u1;
    int depth;
  };
  // Depth first, the earlier half first: everything still on the stack lies after the piece in
  // hand, so the first refusal found ends the search to its right, and the search goes on to
  // its left for an earlier one.
  std::vector<Span> stack{{0.0, 1.0, 0}};
  std::optional<Finding> violation, undecided;
  while (!stack.empty()) {
    if (proof.pieces >= options_.max_pieces_per_move) {
      if (!undecided) {
        const Span& next = stack.back();
        undecided = piece_finding(next.u0, next.u1, segment.at(0.5 * (next.u0 + next.u1)),
                                  Quantity::none, -1, -1, 0.0, 0.0);
        undecided->text = "the proof needs more than " +
                          std::to_string(options_.max_pieces_per_move) + " pieces of this move";
      }
      break;
    }
    const Span span = stack.back();
    stack.pop_back();
    const Outcome outcome = bound_piece(segment, span.u0, span.u1);
    ++proof.pieces;
    const double middle = 0.5 * (span.u0 + span.u1);
    if (outcome.kind == Outcome::refused) {
      violation = earlier_violation(refusal_at(segment, middle, outcome.refusal), violation);
      stack.clear();
      if (span.depth < options_.max_depth) stack.push_back({span.u0, middle, span.depth + 1});
      continue;
    }
    if (outcome.kind == Outcome::proven) continue;
    if (span.depth >= options_.max_depth) {
      if (!undecided) {
        undecided = outcome.open_at;
        undecided->text = wording().undecided_text(*undecided);
      }
      continue;
    }
    stack.push_back({middle, span.u1, span.depth + 1});
    stack.push_back({span.u0, middle, span.depth + 1});
  }
  if (violation) {
    proof.verdict = Verdict::violated;
    farthest_past(segment, *violation);
    if (violation->worst_u != violation->u0) {
      violation->text += "; the farthest past it: " +
                         wording().excess_text(*violation, violation->worst_value,
                                               excess(*violation, violation->worst_value)) +
                         " at " + kinematics::formatted_number("%.6f", 100.0 * violation->worst_u) +
                         " % of the move";
    }
    proof.finding = violation;
  } else if (undecided) {
    proof.verdict = Verdict::undecided;
    proof.finding = undecided;
  }
  return proof;
}

std::optional<double> MoveProver::quantity_at(const Finding& finding,
                                              const geometry::Pose& pose) const {
  switch (finding.quantity) {
    case Quantity::joint: {
      kinematics::JointVector joints;
      kinematics::JointJacobian jacobian;  // the leg limits do not apply to inverse_and_jacobian
      if (!machine_.kinematics().inverse_and_jacobian(pose, joints, jacobian).ok()) {
        return std::nullopt;
      }
      return joints[finding.index];
    }
    case Quantity::envelope:
      return pose.as_vector()[finding.index];
    case Quantity::assembly_mode: {
      // A hexapod's platform past its base plane: how far (mm), as refusal_at measured it (a
      // finding with a leg comes from base_plane_margin; the other modes have none).
      if (finding.index < 0) return std::nullopt;
      return machine_.kinematics().base_plane_margin(pose).margin_mm;
    }
    case Quantity::tension: {
      kinematics::CableStatics statics;
      if (cables_ == nullptr || !cables_->statics(pose, Eigen::Vector2d::Zero(), statics).ok()) {
        return std::nullopt;
      }
      const auto cable = static_cast<std::size_t>(finding.index);
      const bool min = finding.limit == cables_->tension_min_N();
      return min ? statics.lowest_N[cable] : statics.highest_N[cable];
    }
    case Quantity::reach: {
      // Only a force margin's refusal becomes a finding's quantity (refusal_at).
      const auto margin = force_margin_at(machine_.kinematics(), pose.as_vector(),
                                          kinematics::StatusCode::tension, angle_scale_mm_);
      if (!margin || margin->first != finding.index) return std::nullopt;
      return margin->second;
    }
    case Quantity::joint_angle:
    case Quantity::clearance: {
      std::vector<kinematics::MechanismLimit> values;
      machine_.kinematics().mechanism_limits(pose, values);
      for (const kinematics::MechanismLimit& value : values) {
        if (value.leg == finding.index && value.other == finding.other &&
            (value.code == kinematics::StatusCode::joint_angle) ==
                (finding.quantity == Quantity::joint_angle)) {
          return value.value;
        }
      }
      return std::nullopt;
    }
    default:
      return std::nullopt;
  }
}

void MoveProver::farthest_past(const motion::Segment& segment, Finding& finding) const {
  constexpr int kSamples = 1000;
  for (int k = 0; k <= kSamples; ++k) {
    const double u = finding.u0 + (1.0 - finding.u0) * k / kSamples;
    const std::optional<double> value =
        quantity_at(finding, geometry::Pose::from_vector(segment.at(u)));
    if (value && excess(finding, *value) > excess(finding, finding.worst_value)) {
      finding.worst_value = *value;
      finding.worst_u = u;
    }
  }
}

double MoveProver::excess(const Finding& finding, double value) const {
  switch (finding.quantity) {
    case Quantity::joint: {
      const bool min =
          finding.limit == machine_.joints()[static_cast<std::size_t>(finding.index)].min;
      return min ? finding.limit - value : value - finding.limit;
    }
    case Quantity::envelope: {
      const bool min = finding.limit == machine_.cartesian().envelope_min[finding.index];
      return min ? finding.limit - value : value - finding.limit;
    }
    case Quantity::joint_angle:
      return value - finding.limit;
    case Quantity::clearance:
    case Quantity::assembly_mode:  // a hexapod's side of its base plane (mm), limit 0
    case Quantity::reach:
      return finding.limit - value;
    case Quantity::tension:
      return cables_ != nullptr && finding.limit == cables_->tension_min_N()
                 ? finding.limit - value
                 : value - finding.limit;
    default:
      return 0.0;
  }
}

Finding MoveProver::refusal_at(const motion::Segment& segment, double u,
                               const kinematics::Status& status) const {
  Finding finding;
  finding.u0 = finding.u1 = u;
  finding.pose = segment.at(u);
  const geometry::Pose pose = geometry::Pose::from_vector(finding.pose);
  const std::string at =
      "at " + kinematics::formatted_number("%.6f", 100.0 * u) + " % of the move: ";
  kinematics::JointVector joints;
  if (status.code == kinematics::StatusCode::joint_limit &&
      machine_.kinematics().inverse(pose, joints).ok()) {
    const machine::JointSpec& spec = machine_.joints()[static_cast<std::size_t>(status.joint)];
    const double value = joints[status.joint];
    const bool below = value < spec.min;
    finding.quantity = Quantity::joint;
    finding.index = status.joint;
    finding.value = value;
    finding.limit = below ? spec.min : spec.max;
    finding.text = at + "pose " + machine_.format_pose(pose) + ": joint '" + spec.name +
                   "' = " + wording().value_text(Quantity::joint, status.joint, value) +
                   " passes its " + (below ? "min " : "max ") +
                   wording().value_text(Quantity::joint, status.joint, finding.limit) + " (by " +
                   wording().excess_text(finding, value, excess(finding, value)) + ")";
    finding.worst_u = u;
    finding.worst_value = finding.value;
    return finding;
  }
  if (status.code == kinematics::StatusCode::outside_envelope) {
    finding.quantity = Quantity::envelope;
    finding.index = status.axis;
    finding.value = finding.pose[status.axis];
    const bool below = finding.value < machine_.cartesian().envelope_min[status.axis];
    finding.limit = below ? machine_.cartesian().envelope_min[status.axis]
                          : machine_.cartesian().envelope_max[status.axis];
  } else if (status.code == kinematics::StatusCode::joint_angle ||
             status.code == kinematics::StatusCode::interference) {
    std::vector<kinematics::MechanismLimit> values;
    machine_.kinematics().mechanism_limits(pose, values);
    const kinematics::MechanismLimit* worst = nullptr;
    for (const kinematics::MechanismLimit& value : values) {
      if (value.code != status.code || value.leg != status.joint) continue;
      if (worst == nullptr || value.margin() < worst->margin()) worst = &value;
    }
    if (worst != nullptr) {
      finding.quantity = status.code == kinematics::StatusCode::joint_angle ? Quantity::joint_angle
                                                                            : Quantity::clearance;
      finding.index = worst->leg;
      finding.other = worst->other;
      finding.value = worst->value;
      finding.limit = worst->limit;
    }
  } else if (status.code == kinematics::StatusCode::other_assembly) {
    finding.quantity = Quantity::assembly_mode;
    // Past the base plane (a hexapod's platform): which leg, how far.
    const kinematics::BasePlaneMargin side = machine_.kinematics().base_plane_margin(pose);
    if (side.margin_mm <= 0.0) {
      finding.index = side.leg;
      finding.value = side.margin_mm;
    }
  } else if (cables_ != nullptr && status.joint >= 0 && status.joint < 2 &&
             (status.code == kinematics::StatusCode::tension ||
              status.code == kinematics::StatusCode::unreachable)) {
    cable_refusal(pose, status.joint, finding);
  } else if (status.code == kinematics::StatusCode::tension) {
    // A cable robot's tensions: its wrench-feasibility margin (N), how far past 0.
    if (const auto margin =
            force_margin_at(machine_.kinematics(), finding.pose, status.code, angle_scale_mm_)) {
      finding.quantity = Quantity::reach;
      finding.index = margin->first;
      finding.value = margin->second;
    }
  }
  finding.text = at + machine_.explain(pose, status);
  finding.worst_u = u;
  finding.worst_value = finding.value;
  return finding;
}

}  // namespace pkm::certify

namespace pkm::certify {

void MoveProver::cable_refusal(const geometry::Pose& pose, int cable, Finding& finding) const {
  kinematics::CableStatics statics;
  finding.index = cable;
  const kinematics::Status balance = cables_->statics(pose, Eigen::Vector2d::Zero(), statics);
  if (balance.code == kinematics::StatusCode::tension && balance.joint == cable) {
    finding.quantity = Quantity::pull;  // the cable would push
    return;
  }
  if (!balance.ok()) return;
  const auto k = static_cast<std::size_t>(cable);
  if (statics.lowest_N[k] < cables_->tension_min_N()) {
    finding.quantity = Quantity::tension;
    finding.value = statics.lowest_N[k];
    finding.limit = cables_->tension_min_N();
  } else if (statics.highest_N[k] > cables_->tension_max_N()) {
    finding.quantity = Quantity::tension;
    finding.value = statics.highest_N[k];
    finding.limit = cables_->tension_max_N();
  }
}

}  // namespace pkm::certify
