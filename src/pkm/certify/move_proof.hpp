// A proof that one programmed move keeps the machine within its limits at every pose along it,
// not only at samples: bounds on each constrained quantity (joints, work envelope, joint angles,
// leg clearances, the model's reach margins, assembly mode) over pieces of the move from its value
// and derivatives at the piece's middle, the pieces halved where a bound still reaches a limit
// (docs/certified-check.md).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/kinematics/hanging_cables.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/segment.hpp"

namespace pkm::certify {

class ProofWording;

enum class Verdict {
  proven,     // every pose of the move keeps every limit
  violated,   // a pose of the move that the machine refuses was found
  undecided,  // neither: the finest piece's bound still reaches a limit, or no bound exists here
};
std::string_view verdict_name(Verdict verdict);

// What a constrained quantity is: a joint, a coordinate of the work envelope, a joint end's angle,
// a pair of legs, the assembly mode.
// `pull`: a cable plotter's pen between its anchors' verticals and off the anchors' line, where
// both cables pull (as built, over pulleys or weighed: index 0, 1 that cable's tension's sign,
// 2 the angle between the cables, 3 the balance itself). `tension`: a cable's tension (N,
// index: the cable) within tension_limits. `reach`: one of the model's reach margins
// (DerivativeBounds::reach_margin, index: the margin; a cable robot's cable clear of its anchor,
// its tensions' room within tension_limits), limit 0.
enum class Quantity {
  joint,
  envelope,
  joint_angle,
  clearance,
  assembly_mode,
  pull,
  tension,
  reach,
  none
};

// Where a move fails or where its proof stops. Values in the machine's internal units (mm, rad).
struct Finding {
  double u0 = 0.0, u1 = 0.0;  // violated: u0 == u1, the pose found; undecided: the piece
  geometry::Vector6d pose =
      geometry::Vector6d::Zero();  // at u0 (violated) or at the piece's middle (undecided)
  Quantity quantity = Quantity::none;
  int index = -1;      // joint, axis, leg (joint_angle, clearance)
  int other = -1;      // joint_angle: the end (0 inner, 1 platform); clearance: the second leg
  double value = 0.0;  // violated: the value at the pose; undecided: how far the bound reaches
  double limit = 0.0;  // the limit it passes (or may pass)
  // Violated: the farthest beyond the limit the quantity goes, of the poses the search met and
  // 1001 samples after u0 (at u = worst_u); worst_value = value at u0 when none went farther.
  double worst_u = 0.0, worst_value = 0.0;
  std::string text;  // a sentence in the machine file's units
};

struct MoveProof {
  Verdict verdict = Verdict::proven;
  long pieces = 0;  // pieces evaluated
  std::optional<Finding> finding;
};

struct ProofOptions {
  // A piece halved this often (a 2^-depth share of the move) and still not proven is undecided.
  int max_depth = 44;
  long max_pieces_per_move = 200000;
};

class MoveProver {
 public:
  explicit MoveProver(const machine::Machine& machine, ProofOptions options = {});

  // Empty when moves can be proven on this machine; else why not (no derivative bound for the
  // model, cable tensions without one): every move is then undecided with this reason.
  const std::string& unavailable() const { return unavailable_; }

  // The verdict on the whole move (dwells are proven: they do not move).
  MoveProof prove(const motion::Segment& segment) const;

  // "joint 'leg1'", "x (the work envelope)", "the platform joint angle of 'leg5'", ...
  std::string quantity_name(Quantity quantity, int index, int other) const;

 private:
  struct Piece;
  struct Outcome;
  Outcome bound_piece(const motion::Segment& segment, double u0, double u1) const;
  Finding refusal_at(const motion::Segment& segment, double u,
                     const kinematics::Status& status) const;
  // What a cable plotter's refusal at `pose` for `cable` is: a cable that would push, or one
  // past a tension limit (its value and the limit).
  void cable_refusal(const geometry::Pose& pose, int cable, Finding& finding) const;
  // The words of this machine's findings (proof_wording.hpp).
  ProofWording wording() const;
  // How far beyond its limit a violated finding's value is (> 0), in its own unit.
  double excess(const Finding& finding, double value) const;
  // `found`, a violation earlier on the move than `later` (if any): where both concern the same
  // quantity, it keeps the farther excess of the two as the farthest past the limit.
  Finding earlier_violation(Finding found, const std::optional<Finding>& later) const;
  // The finding's quantity at a pose (joint values without the machine's limits), if defined.
  std::optional<double> quantity_at(const Finding& finding, const geometry::Pose& pose) const;
  // Moves worst_u and worst_value to the farthest past the limit of 1001 samples from u0 on.
  void farthest_past(const motion::Segment& segment, Finding& finding) const;

  const machine::Machine& machine_;
  const kinematics::HangingCables* cables_ = nullptr;  // a cable plotter as built, else nullptr
  ProofOptions options_;
  std::vector<int> axes_;  // the pose coordinates the model controls
  double angle_scale_mm_ = 100.0;
  std::string unavailable_;
};

}  // namespace pkm::certify
