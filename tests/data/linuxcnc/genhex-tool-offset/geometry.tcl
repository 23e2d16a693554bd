# Geometry of the hexapod (a Tcl HAL file: haltcl runs it; plain setp lines are HAL commands).
set base_z 0.0
# Base joints, world frame (three pairs on a 500 mm circle)
setp genhexkins.base.0.x -410.0
setp genhexkins.base.0.y  260.0
setp genhexkins.base.0.z    0.0
setp genhexkins.base.1.x  430.0
setp genhexkins.base.1.y  225.0
setp genhexkins.base.1.z    0.0
setp genhexkins.base.2.x  20.0
setp genhexkins.base.2.y -485.0
setp genhexkins.base.2.z    0.0
setp genhexkins.base.3.x  -20.0
setp genhexkins.base.3.y -485.0
setp genhexkins.base.3.z   10.0
setp genhexkins.base.4.x -430.0
setp genhexkins.base.4.y  225.0
setp genhexkins.base.4.z    0.0
setp genhexkins.base.5.x  410.0
setp genhexkins.base.5.y  260.0
setp genhexkins.base.5.z    0.0
# Platform joints, platform frame
setp genhexkins.platform.0.x  -40.0
setp genhexkins.platform.0.y  200.0
setp genhexkins.platform.0.z  -15.0
setp genhexkins.platform.1.x   40.0
setp genhexkins.platform.1.y  200.0
setp genhexkins.platform.1.z  -15.0
setp genhexkins.platform.2.x  195.0
setp genhexkins.platform.2.y -65.0
setp genhexkins.platform.2.z  -15.0
setp genhexkins.platform.3.x  155.0
setp genhexkins.platform.3.y -135.0
setp genhexkins.platform.3.z  -15.0
setp genhexkins.platform.4.x -155.0
setp genhexkins.platform.4.y -135.0
setp genhexkins.platform.4.z  -15.0
setp genhexkins.platform.5.x -195.0
setp genhexkins.platform.5.y -65.0
setp genhexkins.platform.5.z  -15.0
puts "hexapod geometry set in $base_z"
