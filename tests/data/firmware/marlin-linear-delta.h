// Written by pkmkit 0.1.0 from examples/machines/linear-delta.toml (Linear delta)
// Kinematics: linear delta
// Paste into Marlin's Configuration.h: each define replaces the one of that name.
#define DELTA
#define CUSTOM_MACHINE_NAME "Linear delta"
#define DELTA_DIAGONAL_ROD 300  // mm, rod joint to rod joint
#define DELTA_DIAGONAL_ROD_TRIM_TOWER { 0, 0, 0 }  // mm added to the rod of tower A B C
#define DELTA_RADIUS 160  // mm, X0 Y0 to where a tower's rod hangs vertical over the tool
#define DELTA_RADIUS_TRIM_TOWER { 0, 0, 0 }  // mm added to DELTA_RADIUS for tower A B C (no G-code sets these)
#define DELTA_TOWER_ANGLE_TRIM { 0, 0, 0 }  // deg added to towers A B C at 210, 330, 90 deg
#define DELTA_HEIGHT 100  // mm, the tool's Z at X0 Y0 once G28 has homed
#define DELTA_ENDSTOP_ADJ { 0, 0, 0 }  // mm each carriage moves from its endstop after homing (<= 0)
#define PRINTABLE_RADIUS 120  // mm: the largest circle about X0 Y0 inside the machine's work area
#define DELTA_PRINTABLE_RADIUS 120  // older Marlin's name
#define DELTA_MAX_RADIUS 120  // mm
#define MANUAL_X_HOME_POS 0
#define MANUAL_Y_HOME_POS 0
#define MANUAL_Z_HOME_POS 100  // DELTA_HEIGHT
#define X_BED_SIZE 240  // mm
#define Y_BED_SIZE 240  // mm
#define X_MIN_POS -120  // mm
#define Y_MIN_POS -120  // mm
#define X_MAX_POS 120  // mm
#define Y_MAX_POS 120  // mm
#define Z_MIN_POS 0  // mm, the lowest tool Z
#define Z_MAX_POS 100  // mm: DELTA_HEIGHT
// pkmkit joints: X = joint 2 tower_b, Y = joint 3 tower_c, Z = joint 1 tower_a (steps per mm: Marlin's stock values, set yours)
#define DEFAULT_AXIS_STEPS_PER_UNIT { 80, 80, 80 }  // steps per mm of the X Y Z steppers
#define DEFAULT_MAX_FEEDRATE { 300, 300, 300 }  // mm/s of each stepper
#define DEFAULT_MAX_ACCELERATION { 3000, 3000, 3000 }  // mm/s^2 of each stepper (whole numbers: Marlin holds integers)
#define DEFAULT_ACCELERATION 2000  // mm/s^2 of the tool along a move
#define DEFAULT_TRAVEL_ACCELERATION 2000  // mm/s^2 of the tool along a travel move
#define EXTRUDERS 0  // the machine file has no extruder
// The same geometry on a running Marlin (send, then M500 to keep it):
//   M665 L300 R160 H100 X0 Y0 Z0 A0 B0 C0
//   M666 X0 Y0 Z0
