// Written by pkmkit 0.1.0 from examples/machines/hektor.toml (Hektor (source document, d = 100))
// Kinematics: two-cable wall plotter
// Paste into Marlin's Configuration.h: each define replaces the one of that name.
#define POLARGRAPH
#define CUSTOM_MACHINE_NAME "Hektor (source document, d = 100)"
#define X_MIN_POS 0  // mm: the left motor's x (X stepper)
#define Y_MAX_POS 0  // mm: both motors' y
#define Y_MIN_POS -172.916164  // mm: the lowest pen y
#define X_BED_SIZE 100  // mm
#define Y_BED_SIZE 172.916164  // mm
#define POLARGRAPH_MAX_BELT_LEN 179  // mm: Marlin takes belts up to this + 1 mm, the joints' max
#define MANUAL_X_HOME_POS 50  // mm: the pen after G28
#define MANUAL_Y_HOME_POS -50  // mm
// pkmkit joints: X = joint 1 left, Y = joint 2 right, Z = none (steps per mm: Marlin's stock values, set yours)
#define DEFAULT_AXIS_STEPS_PER_UNIT { 80, 80, 400 }  // steps per mm of the X Y Z steppers
#define DEFAULT_MAX_FEEDRATE { 60, 60, 5 }  // mm/s of each stepper
#define DEFAULT_MAX_ACCELERATION { 600, 600, 100 }  // mm/s^2 of each stepper (whole numbers: Marlin holds integers)
#define DEFAULT_ACCELERATION 500  // mm/s^2 of the tool along a move
#define DEFAULT_TRAVEL_ACCELERATION 500  // mm/s^2 of the tool along a travel move
#define EXTRUDERS 0  // the machine file has no extruder
