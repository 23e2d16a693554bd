// The words of a move proof's findings (move_proof.hpp): what a constrained quantity is called,
// its values and how far a value is past its limit, in the machine file's units, and the sentence
// an undecided piece gets. Apart from the proof's arithmetic, so that the reports' wording is in
// one place.
#pragma once

#include <string>

#include "pkm/certify/move_proof.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"

namespace pkm::certify {

class ProofWording {
 public:
  // `cables`: the machine's cable plotter as built (pulleys, a weighed or tilting effector,
  // stretch), whose pull findings name the balance's margins; nullptr otherwise.
  ProofWording(const machine::Machine& machine, const kinematics::HangingCables* cables)
      : machine_(machine), cables_(cables) {}

  // "joint 'leg1'", "x (the work envelope)", "the platform joint angle of 'leg5'", ...
  std::string quantity_name(Quantity quantity, int index, int other) const;
  // A value of the quantity in the machine file's units ("12.500 mm", "31.000 deg", "4.200 N").
  std::string value_text(Quantity quantity, int index, double value) const;
  // How far `value` is past the finding's limit, `excess` in the quantity's own unit (mm, rad,
  // N), in the machine file's units ("0.25 mm").
  std::string excess_text(const Finding& finding, double value, double excess) const;
  // Why an undecided piece is undecided: the quantity, the piece, and where its bound reaches.
  std::string undecided_text(const Finding& finding) const;

 private:
  // The model's reach margin `index` (its name and unit).
  kinematics::ReachMargin reach_margin(int index) const;

  const machine::Machine& machine_;
  const kinematics::HangingCables* cables_;
};

}  // namespace pkm::certify
