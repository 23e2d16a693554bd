// Written by pkmkit 0.1.0 from examples/machines/wall-plotter.toml (Wall plotter 1500)
// Kinematics: two-cable wall plotter
// Paste into Marlin's Configuration.h: each define replaces the one of that name.
#define POLARGRAPH
#define CUSTOM_MACHINE_NAME "Wall plotter 1500"
#define X_MIN_POS 0  // mm: the left motor's x (X stepper)
#define X_MAX_POS 1500  // mm: the right motor's x (Y stepper)
#define Y_MAX_POS 0  // mm: both motors' y
#define Y_MIN_POS -1961.504524  // mm: the lowest pen y
#define X_BED_SIZE 1500  // mm
#define Y_BED_SIZE 1961.504524  // mm
#define POLARGRAPH_MAX_BELT_LEN 2099  // mm: Marlin takes belts up to this + 1 mm, the joints' max
#define MANUAL_X_HOME_POS 750  // mm: the pen after G28
#define MANUAL_Y_HOME_POS -700  // mm
// pkmkit joints: X = joint 1 left, Y = joint 2 right, Z = none
#define DEFAULT_AXIS_STEPS_PER_UNIT { 80, 80, 400 }  // steps per mm of the X Y Z steppers
#define DEFAULT_MAX_FEEDRATE { 150, 150, 5 }  // mm/s of each stepper
#define DEFAULT_MAX_ACCELERATION { 1000, 1000, 100 }  // mm/s^2 of each stepper (whole numbers: Marlin holds integers)
#define DEFAULT_ACCELERATION 800  // mm/s^2 of the tool along a move
#define DEFAULT_TRAVEL_ACCELERATION 800  // mm/s^2 of the tool along a travel move
#define EXTRUDERS 0  // the machine file has no extruder
