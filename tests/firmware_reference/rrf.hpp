// An independent RepRapFirmware linear and rotary delta, written from its source
// (Duet3D/RepRapFirmware, src/Movement/Kinematics/LinearDeltaKinematics.cpp: Configure for M665
// and M666, Recalc for the towers and the homed carriage heights, Transform for a motor's
// position; RotaryDeltaKinematics.cpp: Configure for M669 and M666, Recalc, Transform,
// OnHomingSwitchTriggered; HangprinterKinematics.cpp: Configure for M669 and M666, Recalc and
// CartesianToMotorSteps) to check what `pkm export rrf` writes: it reads the exported config.g
// lines with its own small parser, not pkmkit's reader.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace pkm::test::rrf_reference {

struct LinearDelta {
  std::array<double, 3> diagonals{215.0, 215.0, 215.0};  // RRF's defaults
  double radius = 105.6;
  double homed_height = 240.0;
  double print_radius = 80.0;
  std::array<double, 3> angle_corrections{};  // deg
  std::array<double, 3> endstop_adjustments{};
  double x_tilt = 0.0, y_tilt = 0.0;  // M666 A, B over 100
  // "M92 X" -> value, for every other parameter of the lines read.
  std::map<std::string, double> settings;
  // From the export's "; drive X = tower A = joint N" comments: pkmkit joint (from 0) per drive.
  std::array<int, 3> joint_of_drive{-1, -1, -1};
};

// The settings the config.g text sets, read as RRF would (later lines override earlier ones).
LinearDelta parse(const std::string& config_text);

// Tower `tower`'s x y as Recalc places it (0 = A, driven by X).
std::array<double, 2> tower_position(const LinearDelta& delta, int tower);
// The motor position (mm) Transform gives tower `tower` for the head at x y z (mm).
double motor_position(const LinearDelta& delta, int tower, double x, double y, double z);
// The motor position homing sets at the tower's endstop (Recalc's homed carriage height).
double homed_carriage_height(const LinearDelta& delta, int tower);

struct RotaryDelta {
  std::array<double, 3> arms{100.0, 100.0, 100.0};  // RRF's defaults
  std::array<double, 3> rods{200.0, 200.0, 200.0};
  std::array<double, 3> bearing_heights{250.0, 250.0, 250.0};
  double min_arm_angle = -45.0, max_arm_angle = 45.0;
  double radius = 50.0;
  std::array<double, 3> angle_corrections{};    // deg
  std::array<double, 3> endstop_adjustments{};  // deg
  std::map<std::string, double> settings;
  std::array<int, 3> joint_of_drive{-1, -1, -1};
};

RotaryDelta parse_rotary(const std::string& config_text);
// The arm angle (deg, up positive) Transform gives arm `arm` for the head at x y z (mm).
double arm_angle_deg(const RotaryDelta& delta, int arm, double x, double y, double z);
// The angle homing sets at the arm's endstop (OnHomingSwitchTriggered, the high end).
double homed_arm_angle_deg(const RotaryDelta& delta, int arm);

// RRF's Hangprinter (M669 K6) as its HangprinterKinematics with M666 F: the anchors M669 A B C D
// (N5: and I); M666 Q (spool buildup), R U O L H J (spools), F (flex: 0 off, 1 least squares),
// W S I X Y (mover weight, line stiffness, min and max planned force, guy wires); RRF's Init
// defaults for what is not set. Microstepping 1 (it scales every motor position alike).
struct Hangprinter {
  std::vector<std::array<double, 3>> anchors;
  double spool_buildup = 0.007;  // RRF's default
  int flex = 0;
  double mover_weight = 0.0;
  double spring_k_per_unit_length = 20000.0;
  std::map<char, std::vector<double>> per_anchor;  // 'R' 'U' 'O' 'L' 'H' 'J' 'I' 'X' 'Y'
};
Hangprinter parse_hangprinter(const std::string& config_text);
// StaticForcesQp's planned force per anchor (N) for the tool at x y z: the exact minimum of its
// least squares (every free/at-min/at-max assignment tried), and the forces as RRF's own iteration
// leaves them (solve_box_ridge_ls: it stops at a projected gradient of 1e-3 N, and a step that
// meets a limit at once stalls it).
std::vector<double> hangprinter_forces(const Hangprinter& hangprinter, double x, double y,
                                       double z);
std::vector<double> hangprinter_forces_iterated(const Hangprinter& hangprinter, double x, double y,
                                                double z);
// CartesianToMotorSteps' motor position of anchor `anchor` (full steps, unrounded) for the tool
// at x y z: the line position |anchor - tool| - |anchor| (less the stretch with F1) through the
// spool model (constant radius where U O Q is 0, else k0 (sqrt(R^2 + linePos k2) - R)); the
// stretch with RRF's iterated forces.
double hangprinter_motor_steps(const Hangprinter& hangprinter, int anchor, double x, double y,
                               double z);
// Recalc's steps per mm at the origin (full steps).
double hangprinter_steps_per_mm(const Hangprinter& hangprinter, int anchor);
// The motor position over the steps per mm at the origin (mm; the line position itself with Q 0
// and F 0).
double hangprinter_line_position(const Hangprinter& hangprinter, int anchor, double x, double y,
                                 double z);

}  // namespace pkm::test::rrf_reference
