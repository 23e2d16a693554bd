; Written by pkmkit 0.1.0 from examples/machines/linuxcnc-rdelta.toml (LinuxCNC rdelta (rotarydeltakins 10, 10, 18, 5 in))
; Kinematics: rotary delta
; RepRapFirmware 3 config.g lines: they replace the kinematics, M92, M203, M201 and M208 lines of config.g; the firmware needs rotary delta support (SUPPORT_ROTARY_DELTA)
; drive X = arm A = joint 1 "joint0": towards -90 deg; RRF's arm angle is minus its reading, the endstop at its reading -45 deg
; drive Y = arm B = joint 2 "joint1": towards 30 deg; RRF's arm angle is minus its reading, the endstop at its reading -45 deg
; drive Z = arm C = joint 3 "joint2": towards 150 deg; RRF's arm angle is minus its reading, the endstop at its reading -45 deg
; Each motor counts up as its arm rises (set M569 S so); the arms home up to their endstops (homedelta.g)
M669 K10 U254:254:254 L457.2:457.2:457.2 H0:0:0 A-90:45 R127 B101.6 X60 Y60 Z60 ; rotary delta: arms and rods A:B:C (mm), pivot heights (mm), arm angles min:max (deg, up positive), pivot radius less the effector's (mm), printable radius (mm), arm angle corrections (deg)
M666 X0 Y0 Z0 ; endstop corrections (deg)
; M92: the machine file gives no steps per degree: set them here
M203 X15240 Y15240 Z15240 ; maximum speeds (mm/min)
M201 X2540 Y2540 Z2540 ; maximum accelerations (mm/s^2)
M208 Z-457.2:-254 ; Z range (mm)
; Not held by RRF: the arms' own speed and acceleration limits (the joints' max_velocity, max_acceleration): RRF limits the effector's speed and acceleration along X Y (M203 X, M201 X) and along Z apart; it homes each arm up to its endstop and keeps Z within M208
; RRF keeps X Y within M669 B of x 0 y 0 and pulls a move beyond it back onto that circle: B is the largest such circle inside the machine's work envelope (its reach where it has none)
