// The cable robot's spools and flex compensation settings, as RepRapFirmware's Hangprinter holds
// them (HangprinterKinematics: Recalc's steps per mm and buildup constants k0 k2,
// CartesianToMotorSteps' motor position; docs/kinematics.md, "Cable robot"): their machine-file
// keys, their validation, and the motor position a spool gives a joint. The joint stays the
// cable's length; the spool only turns it into motor steps.
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm::kinematics {

namespace {

// The spool's whole-number keys, in M666's order (U O L H J), and where each lives.
struct SpoolCount {
  const char* key;
  int CableSpool::*field;
};
constexpr SpoolCount kSpoolCounts[] = {
    {"mechanical_advantage", &CableSpool::mechanical_advantage},
    {"lines_per_spool", &CableSpool::lines_per_spool},
    {"motor_gear_teeth", &CableSpool::motor_gear_teeth},
    {"spool_gear_teeth", &CableSpool::spool_gear_teeth},
    {"full_steps_per_rev", &CableSpool::full_steps_per_rev},
};
constexpr const char* kSpoolKeys[] = {"spool_radius",     "mechanical_advantage",
                                      "lines_per_spool",  "motor_gear_teeth",
                                      "spool_gear_teeth", "full_steps_per_rev"};
// A count this large is no gear or strand count (and would overflow RRF's products).
constexpr int kLargestCount = 100000;

// The cable's own value, else the one for every cable in [kinematics].
const ModelConfig* holder(const ModelConfig& cable, const ModelConfig& kinematics,
                          const char* key) {
  if (cable.has(key)) return &cable;
  if (kinematics.has(key)) return &kinematics;
  return nullptr;
}

int whole_count(const ModelConfig& config, const char* key) {
  const double value = config.number(key);
  if (!(value >= 1.0 && value <= kLargestCount) || value != std::floor(value)) {
    config.fail(key, "must be a whole number from 1 to " + std::to_string(kLargestCount) +
                         ", got " + formatted_number("%g", value));
  }
  return static_cast<int>(value);
}

std::optional<CableSpool> read_spool(const ModelConfig& cable, const ModelConfig& kinematics,
                                     std::size_t index) {
  const ModelConfig* radius = holder(cable, kinematics, "spool_radius");
  if (radius == nullptr) {
    for (const char* key : kSpoolKeys) {
      if (cable.has(key)) cable.fail(key, "needs the cable's spool_radius (mm) too");
      if (kinematics.has(key)) {
        kinematics.fail(key, "is for every cable's spool, and cable " + std::to_string(index + 1) +
                                 " has no spool_radius (mm)");
      }
    }
    return std::nullopt;
  }
  CableSpool spool;
  spool.radius_mm = radius->length("spool_radius");
  if (!(spool.radius_mm > 0.0) || !std::isfinite(spool.radius_mm)) {
    radius->fail("spool_radius", "must be a length above 0 (mm)");
  }
  for (const SpoolCount& count : kSpoolCounts) {
    if (const ModelConfig* from = holder(cable, kinematics, count.key)) {
      spool.*count.field = whole_count(*from, count.key);
    }
  }
  return spool;
}

}  // namespace

void validate_cable_robot_drive(const CableRobotGeometry& g) {
  if (!(g.spool_buildup_mm >= 0.0) || !std::isfinite(g.spool_buildup_mm)) {
    throw std::invalid_argument("spool_buildup: must be 0 or more (mm)");
  }
  int spools = 0;
  for (const RobotCable& cable : g.cables) {
    if (!(cable.guy_wire_mm >= 0.0) || !std::isfinite(cable.guy_wire_mm)) {
      throw std::invalid_argument("guy_wire_length: must be 0 or more (mm)");
    }
    if (!cable.spool) continue;
    ++spools;
    const CableSpool& s = *cable.spool;
    if (!(s.radius_mm > 0.0) || !std::isfinite(s.radius_mm)) {
      throw std::invalid_argument("spool_radius: must be a length above 0 (mm)");
    }
    for (const SpoolCount& count : kSpoolCounts) {
      if (s.*count.field < 1 || s.*count.field > kLargestCount) {
        throw std::invalid_argument(std::string(count.key) + ": must be a whole number from 1 to " +
                                    std::to_string(kLargestCount));
      }
    }
  }
  if (g.spool_buildup_mm > 0.0 && spools == 0) {
    throw std::invalid_argument("spool_buildup: needs the cables' spool_radius");
  }
  if (!g.flex_compensation) return;
  if (g.planar) {
    throw std::invalid_argument(
        "flex_compensation: RRF's flex compensation holds a spatial robot (x y z) only");
  }
  if (!(g.line_stiffness_N > 0.0) || !std::isfinite(g.line_stiffness_N)) {
    throw std::invalid_argument("line_stiffness: must be above 0 (N)");
  }
  if (!g.tension_limited) {
    throw std::invalid_argument(
        "flex_compensation: needs tension_limits = [min, max] (N): RRF plans each line's force "
        "within them (M666 I X)");
  }
  if (!(g.line_stiffness_N > g.tension_max_N)) {
    throw std::invalid_argument(
        "line_stiffness: must exceed tension_limits' max (N), or a line at its max force would "
        "stretch without end");
  }
  const Eigen::Vector3d down = g.gravity_direction.normalized();
  if (g.gravity_given && !(down - Eigen::Vector3d(0.0, 0.0, -1.0)).isZero(1e-12)) {
    throw std::invalid_argument(
        "flex_compensation: RRF's mover hangs along -z; gravity must be [0, 0, -1]");
  }
}

std::optional<double> CableRobotKinematics::full_steps_per_mm(int cable) const {
  const std::optional<CableSpool>& spool = geometry_.cables[cable].spool;
  if (!spool) return std::nullopt;
  // Recalc: steps per mm times the radius is U J H / (2 pi L) (microstepping 1 here).
  const double steps_times_radius = double(spool->mechanical_advantage) *
                                    spool->full_steps_per_rev * spool->spool_gear_teeth /
                                    (2.0 * std::numbers::pi * spool->motor_gear_teeth);
  return steps_times_radius / spool->radius_mm;
}

std::optional<double> CableRobotKinematics::motor_full_steps(int cable, double joint_mm) const {
  const std::optional<double> per_mm = full_steps_per_mm(cable);
  if (!per_mm) return std::nullopt;
  const std::optional<double> at_origin = joint_at_line_origin_mm(cable);
  if (!at_origin) return std::nullopt;
  const RobotCable& c = geometry_.cables[cable];
  const CableSpool& spool = *c.spool;
  const double line_position = joint_mm - *at_origin;
  // Each strand pays out line_position, the spool U O times that; its radius r grows as
  // r^2 - U O Q line_position (the wound cross-section), the motor turning with it.
  const double wound = double(spool.mechanical_advantage) * spool.lines_per_spool;
  const double k2 = -wound * geometry_.spool_buildup_mm;
  if (k2 == 0.0) return line_position * *per_mm;
  const double square = spool.radius_mm * spool.radius_mm + line_position * k2;
  if (!(square > 0.0)) return std::nullopt;
  const double k0 = 2.0 * *per_mm * spool.radius_mm / k2;
  return k0 * (std::sqrt(square) - spool.radius_mm);
}

const LineSpools* CableRobotKinematics::line_spools() const {
  for (int cable = 0; cable < cable_count(); ++cable) {
    if (has_spool(cable)) return this;
  }
  return nullptr;
}

std::optional<double> CableRobotKinematics::joint_at_line_origin_mm(int cable) const {
  const RobotCable& c = geometry_.cables[cable];
  if (c.pulley_radius_mm == 0.0) return c.offset_mm + (c.anchor_mm - c.attach_mm).norm();
  PulleyPath path;
  if (!pulley_path(c, c.attach_mm, path).ok()) return std::nullopt;
  return c.offset_mm + path.length_mm;
}

std::optional<double> CableRobotKinematics::joint_from_motor_full_steps(int cable,
                                                                        double full_steps) const {
  const std::optional<double> per_mm = full_steps_per_mm(cable);
  if (!per_mm || !std::isfinite(full_steps)) return std::nullopt;
  const std::optional<double> origin = joint_at_line_origin_mm(cable);
  if (!origin) return std::nullopt;
  const double at_origin = *origin;
  const CableSpool& spool = *geometry_.cables[cable].spool;
  const double k2 =
      -double(spool.mechanical_advantage) * spool.lines_per_spool * geometry_.spool_buildup_mm;
  if (k2 == 0.0) return at_origin + full_steps / *per_mm;
  // steps = k0 (sqrt(r^2 + k2 p) - r) gives sqrt(r^2 + k2 p) = r + t with t = steps / k0, so
  // p = t (2 r + t) / k2, without the cancellation of (r + t)^2 - r^2. r + t below 0 is no root.
  const double k0 = 2.0 * *per_mm * spool.radius_mm / k2;
  const double t = full_steps / k0;
  if (!(spool.radius_mm + t > 0.0)) return std::nullopt;
  return at_origin + t * (2.0 * spool.radius_mm + t) / k2;
}

void read_cable_robot_drive(const ModelConfig& config, CableRobotGeometry& g) {
  const auto cables = config.table_list("cables");
  for (std::size_t i = 0; i < cables.size() && i < g.cables.size(); ++i) {
    g.cables[i].spool = read_spool(*cables[i], config, i);
    g.cables[i].guy_wire_mm = cables[i]->length_or("guy_wire_length", 0.0);
    if (!(g.cables[i].guy_wire_mm >= 0.0)) {
      cables[i]->fail("guy_wire_length", "must be 0 or more (mm)");
    }
  }
  g.spool_buildup_mm = config.length_or("spool_buildup", 0.0);
  g.flex_compensation = config.boolean_or("flex_compensation", false);
  g.line_stiffness_N = config.number_or("line_stiffness", g.line_stiffness_N);
  if (config.has("line_stiffness") && !g.flex_compensation) {
    config.fail("line_stiffness", "is for flex_compensation = true");
  }
}

void write_cable_robot_drive(const CableRobotGeometry& g, ModelConfigWriter& out) {
  if (g.spool_buildup_mm != 0.0) out.length("spool_buildup", g.spool_buildup_mm);
  if (!g.flex_compensation) return;
  out.boolean("flex_compensation", true);
  out.number("line_stiffness", g.line_stiffness_N);
}

void write_cable_drive(const CableRobotGeometry& /*g*/, const RobotCable& cable,
                       ModelConfigWriter& entry) {
  if (cable.spool) {
    entry.length("spool_radius", cable.spool->radius_mm);
    for (const SpoolCount& count : kSpoolCounts) {
      entry.whole_number(count.key, (*cable.spool).*count.field);
    }
  }
  if (cable.guy_wire_mm != 0.0) entry.length("guy_wire_length", cable.guy_wire_mm);
}

}  // namespace pkm::kinematics
