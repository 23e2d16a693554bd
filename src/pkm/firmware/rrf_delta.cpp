#include "pkm/firmware/rrf_delta.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "pkm/firmware/firmware_machine.hpp"
#include "pkm/geometry/pose.hpp"

namespace pkm::firmware {
namespace {

// "X1 Y2 Z3" for three values of the X Y Z drives.
std::string per_drive(const std::array<double, 3>& values) {
  std::string text;
  for (std::size_t k = 0; k < 3; ++k) {
    text += (k > 0 ? " " : "") + std::string(1, kRrfDriveLetters[k]) + rrf_number(values[k]);
  }
  return text;
}

// An angle (deg) in (-180, 180].
double wrapped_deg(double angle) {
  double wrapped = std::fmod(angle + 180.0, 360.0);
  if (wrapped <= 0.0) wrapped += 360.0;
  return wrapped - 180.0;
}

std::string steps_line(const RrfLinearDelta& delta) {
  std::string text;
  for (std::size_t k = 0; k < 3; ++k) {
    if (!delta.steps_per_mm[k]) continue;
    text += " " + std::string(1, kRrfDriveLetters[k]) + rrf_number(*delta.steps_per_mm[k]);
  }
  if (text.empty()) return "; M92: the machine file gives no steps per mm: set them here";
  return "M92" + text + " ; motor steps per mm of carriage travel";
}

}  // namespace

TowerAssignment assign_towers(const std::array<double, 3>& angles_deg,
                              const std::array<double, 3>& nominal_deg) {
  std::array<int, 3> order{0, 1, 2};
  TowerAssignment best;
  double best_worst = std::numeric_limits<double>::infinity();
  do {
    TowerAssignment candidate{order, {}};
    double worst = 0.0;
    for (std::size_t tower = 0; tower < 3; ++tower) {
      candidate.corrections_deg[tower] =
          wrapped_deg(angles_deg[static_cast<std::size_t>(order[tower])] - nominal_deg[tower]);
      worst = std::max(worst, std::abs(candidate.corrections_deg[tower]));
    }
    if (worst < best_worst - 1e-9) {
      best_worst = worst;
      best = candidate;
    }
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

RrfBounds rrf_bounds(const machine::Machine& machine) {
  const machine::CartesianLimits& limits = machine.cartesian();
  // The reach (a bisection per axis) only where the envelope leaves a bound open.
  const bool open =
      !limits.envelope_min.head<3>().allFinite() || !limits.envelope_max.head<3>().allFinite();
  const machine::PoseBox reach = open ? machine::reach_box(machine) : machine::PoseBox{};
  auto low = [&](int axis) {
    return std::isfinite(limits.envelope_min[axis]) ? limits.envelope_min[axis] : reach.min[axis];
  };
  auto high = [&](int axis) {
    return std::isfinite(limits.envelope_max[axis]) ? limits.envelope_max[axis] : reach.max[axis];
  };
  RrfBounds bounds;
  bounds.print_radius_mm = std::min({-low(0), high(0), -low(1), high(1)});
  bounds.z_min_mm = low(2);
  bounds.z_max_mm = high(2);
  if (!(bounds.print_radius_mm > 0.0)) {
    throw ExportRefused(machine.source() +
                        ": RRF's printable radius (B) is a circle about x 0 y 0, and the "
                        "machine's work envelope does not hold x 0 y 0 inside it");
  }
  return bounds;
}

bool lower_into_limits(const kinematics::Kinematics& model, const std::array<double, 3>& low,
                       const std::array<double, 3>& high, geometry::Pose& pose) {
  const double start_z = pose.position_mm.z();
  kinematics::JointVector joints(model.joint_count());
  for (double step = 1e-9; step < 2.0; step *= 2.0) {
    if (model.inverse(pose, joints).ok()) {
      bool within = true;
      for (std::size_t k = 0; k < 3; ++k) {
        const double value = joints[static_cast<Eigen::Index>(k)];
        within = within && value >= low[k] + 1e-12 && value <= high[k] - 1e-12;
      }
      if (within) return true;
    }
    pose.position_mm.z() = start_z - step;
  }
  return false;
}

Eigen::Vector2d rrf_tower_position(const RrfLinearDelta& delta, int tower) {
  const double angle =
      geometry::degrees_to_radians(kRrfNominalTowerAngles[static_cast<std::size_t>(tower)] +
                                   delta.angle_corrections_deg[static_cast<std::size_t>(tower)]);
  return delta.radius_mm * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

double rrf_homed_carriage_height(const RrfLinearDelta& delta, int tower) {
  const std::size_t k = static_cast<std::size_t>(tower);
  return delta.homed_height_mm +
         std::sqrt(delta.diagonals_mm[k] * delta.diagonals_mm[k] -
                   delta.radius_mm * delta.radius_mm) +
         delta.endstop_adjustments_mm[k];
}

std::string rrf_number(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6f", value);
  std::string number = text;
  while (!number.empty() && number.back() == '0') number.pop_back();
  if (!number.empty() && number.back() == '.') number.pop_back();
  return number == "-0" ? "0" : number;
}

std::vector<std::string> rrf_delta_lines(const RrfLinearDelta& delta) {
  std::string rods = "L" + rrf_number(delta.diagonals_mm[0]);
  for (std::size_t k = 1; k < 3; ++k) rods += ":" + rrf_number(delta.diagonals_mm[k]);
  return {
      "M669 K3 ; linear delta kinematics",
      "M665 " + rods + " R" + rrf_number(delta.radius_mm) + " H" +
          rrf_number(delta.homed_height_mm) + " B" + rrf_number(delta.print_radius_mm) + " " +
          per_drive(delta.angle_corrections_deg) +
          " ; diagonal rods A:B:C (mm), delta radius (mm), homed height (mm), printable radius "
          "(mm), tower angle corrections (deg)",
      "M666 " + per_drive(delta.endstop_adjustments_mm) + " A" + rrf_number(100.0 * delta.tilt[0]) +
          " B" + rrf_number(100.0 * delta.tilt[1]) +
          " ; endstop corrections (mm), bed tilt (%): none",
      steps_line(delta),
      "M203 " + per_drive(delta.max_speed_mm_per_min) + " ; maximum speeds (mm/min)",
      "M201 " + per_drive(delta.max_acceleration_mm_per_s2) + " ; maximum accelerations (mm/s^2)",
      "M208 S1 Z" + rrf_number(delta.z_min_mm) + " ; lowest Z (mm)",
  };
}

}  // namespace pkm::firmware
