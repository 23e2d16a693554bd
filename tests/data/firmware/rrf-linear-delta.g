; Written by pkmkit 0.1.0 from examples/machines/linear-delta.toml (Linear delta)
; Kinematics: linear delta
; RepRapFirmware 3 config.g lines: they replace the kinematics, M92, M203, M201 and M208 lines of config.g
; drive X = tower A = joint 2 "tower_b": column x -138.564065 y -80 mm, endstop at its reading 700 mm
; drive Y = tower B = joint 3 "tower_c": column x 138.564065 y -80 mm, endstop at its reading 700 mm
; drive Z = tower C = joint 1 "tower_a": column x 0 y 160 mm, endstop at its reading 700 mm
; Each motor counts up as its carriage rises (set M569 S so); the carriages home up to their endstops (homedelta.g)
M669 K3 ; linear delta kinematics
M665 L300:300:300 R160 H446.228449 B120 X0 Y0 Z0 ; diagonal rods A:B:C (mm), delta radius (mm), homed height (mm), printable radius (mm), tower angle corrections (deg)
M666 X0 Y0 Z0 A0 B0 ; endstop corrections (mm), bed tilt (%): none
; M92: the machine file gives no steps per mm: set them here
M203 X9000 Y9000 Z9000 ; maximum speeds (mm/min)
M201 X2000 Y2000 Z2000 ; maximum accelerations (mm/s^2)
M208 S1 Z0 ; lowest Z (mm)
; Not held by RRF: the carriages' own speed and acceleration limits and their lowest readings (the joints' max_velocity, max_acceleration, min): RRF limits the effector's speed and acceleration along X Y (M203 X, M201 X) and along Z apart, keeps it above M208 Z and each carriage below its endstop
; RRF keeps X Y within M665 B of x 0 y 0 and pulls a move beyond it back onto that circle: B is the largest such circle inside the machine's work envelope (its reach where it has none)
