# pkm import linuxcnc: configurations it must refuse, each with the file:line (and [SECTION]KEY or
# pin) of the problem. The configurations are written here, a few lines each, into the build
# tree; lcnc_config(NAME INI [FILE TEXT]...) writes NAME/NAME.ini and its other files.
set(LCNC ${CLI_OUT}/linuxcnc)
# A working trivkins mill, the base of most cases.
set(LCNC_MILL "[KINS]\nKINEMATICS = trivkins\nJOINTS = 3\n[TRAJ]\nLINEAR_UNITS = mm\nMAX_LINEAR_VELOCITY = 50\n")
foreach(j 0 1 2)
  string(APPEND LCNC_MILL "[JOINT_${j}]\nMIN_LIMIT = -100\nMAX_LIMIT = 100\nMAX_VELOCITY = 50\nMAX_ACCELERATION = 500\n")
endforeach()
function(lcnc_config name ini)
  file(WRITE ${LCNC}/${name}/${name}.ini "${ini}")
  set(rest ${ARGN})
  while(rest)
    list(POP_FRONT rest file text)
    file(WRITE ${LCNC}/${name}/${file} "${text}")
  endwhile()
endfunction()
# The refusal must leave no machine file behind.
function(lcnc_refuses name message)
  pkm_cli_refuses(linuxcnc_${name} "${message}" NO_FILE ${LCNC}/${name}/out.toml
                  import linuxcnc ${LCNC}/${name}/${name}.ini -o ${LCNC}/${name}/out.toml ${ARGN})
endfunction()

lcnc_config(unknown_module "[KINS]\nKINEMATICS = scarakins coordinates=xyzc\nJOINTS = 4\n")
lcnc_refuses(unknown_module
  "unknown_module\\.ini:2:\\[KINS\\]KINEMATICS: kinematics module 'scarakins' cannot be imported. pkm import linuxcnc knows genhexkins, lineardeltakins, rotarydeltakins, matrixkins, trivkins$")

lcnc_config(no_kinematics "[EMC]\nMACHINE = x\n[KINS]\nJOINTS = 3\n")
lcnc_refuses(no_kinematics "no_kinematics\\.ini:3:\\[KINS\\]KINEMATICS: \\[KINS\\] has no KINEMATICS")

lcnc_config(missing_halfile "[HAL]\nHALFILE = nowhere.hal\n${LCNC_MILL}")
lcnc_refuses(missing_halfile
  "missing_halfile\\.ini:2:\\[HAL\\]HALFILE: HAL file .*nowhere\\.hal does not exist$")

lcnc_config(missing_lib_halfile "[HAL]\nHALFILE = LIB:nowhere.hal\n${LCNC_MILL}")
lcnc_refuses(missing_lib_halfile
  "missing_lib_halfile\\.ini:2:\\[HAL\\]HALFILE: HAL file /nowhere/lib/nowhere\\.hal does not exist \\(LIB: is LinuxCNC's /nowhere/lib\\)$"
  --hallib /nowhere/lib)

lcnc_config(bad_ini_number "[JOINT_1]\nMAX_VELOCITY = fast\n${LCNC_MILL}")
lcnc_refuses(bad_ini_number
  "bad_ini_number\\.ini:2:\\[JOINT_1\\]MAX_VELOCITY: 'fast' is not a number$")

lcnc_config(bad_hal_number
  "[HAL]\nHALFILE = cal.hal\n[KINS]\nKINEMATICS = matrixkins\nJOINTS = 3\n[TRAJ]\nLINEAR_UNITS = mm\n"
  cal.hal "# calibration\nsetp matrixkins.C_xx 1.0\nsetp matrixkins.C_xy 0.0003x\n")
lcnc_refuses(bad_hal_number
  "cal\\.hal:3:matrixkins\\.C_xy: setp matrixkins\\.C_xy: '0\\.0003x' is not a number$")

lcnc_config(missing_substitution "[HAL]\nHALFILE = cal.hal\n${LCNC_MILL}"
  cal.hal "loadrt [KINS]KINEMATICS\nsetp matrixkins.C_xy [CALIBRATION]C_XY\n")
lcnc_refuses(missing_substitution
  "cal\\.hal:2: \\[CALIBRATION\\]C_XY is not in .*missing_substitution\\.ini$")

lcnc_config(screw_lead
  "[HAL]\nHALFILE = kins.hal\n[KINS]\nKINEMATICS = genhexkins\nJOINTS = 6\n"
  kins.hal "setp genhexkins.screw-lead 2.0\n")
lcnc_refuses(screw_lead
  "kins\\.hal:1:genhexkins\\.screw-lead: screw-lead 2\\.0: genhexkins' strut length correction for screw actuators has no counterpart in pkmkit's hexapod. set it to 0 to import$")

lcnc_config(geometry_at_run_time
  "[HAL]\nHALFILE = kins.hal\n[KINS]\nKINEMATICS = lineardeltakins\nJOINTS = 3\n"
  kins.hal "net radius lineardeltakins.R => my-dial.out\n")
lcnc_refuses(geometry_at_run_time
  "geometry_at_run_time\\.ini:4:\\[KINS\\]KINEMATICS: lineardeltakins\\.R is connected to my-dial\\.out \\(a value at run time\\). pkmkit needs the geometry as constants: setp or sets it$")

lcnc_config(tcl_geometry
  "[HAL]\nHALFILE = kins.tcl\n[KINS]\nKINEMATICS = lineardeltakins\nJOINTS = 3\n"
  kins.tcl "set r 130.25\nsetp lineardeltakins.R $r\n")
lcnc_refuses(tcl_geometry
  "kins\\.tcl:2: 'setp lineardeltakins\\.R \\$r' sets lineardeltakins through Tcl, which the import does not evaluate")

lcnc_config(gantry "[KINS]\nKINEMATICS = trivkins coordinates=XYYZ\nJOINTS = 4\n")
lcnc_refuses(gantry
  "gantry\\.ini:2:\\[KINS\\]KINEMATICS: trivkins coordinates=xyyz: the joints do not start x y z")

lcnc_config(lathe "[KINS]\nKINEMATICS = trivkins coordinates=xz\nJOINTS = 2\n")
lcnc_refuses(lathe "lathe\\.ini:2:\\[KINS\\]KINEMATICS: trivkins coordinates=xz: the joints do not start x y z")

lcnc_config(hexapod_joint_angular
  "[KINS]\nKINEMATICS = genhexkins\nJOINTS = 6\n[JOINT_0]\nTYPE = ANGULAR\n")
lcnc_refuses(hexapod_joint_angular
  "hexapod_joint_angular\\.ini:5:\\[JOINT_0\\]TYPE: this kinematics' joint 0 is LINEAR$")

lcnc_config(no_travel "[JOINT_2]\nMIN_LIMIT = 0\nMAX_LIMIT = 0\n${LCNC_MILL}")
lcnc_refuses(no_travel
  "no_travel\\.ini:3:\\[JOINT_2\\]MAX_LIMIT: must be greater than MIN_LIMIT \\(0\\.0\\): pkmkit needs the joint's travel$")

lcnc_config(units "[TRAJ]\nLINEAR_UNITS = furlong\n${LCNC_MILL}")
lcnc_refuses(units "units\\.ini:2:\\[TRAJ\\]LINEAR_UNITS: 'furlong' is not a unit pkmkit knows \\(mm or inch\\)$")

lcnc_config(missing_include "#INCLUDE joints.inc\n${LCNC_MILL}")
lcnc_refuses(missing_include
  "missing_include\\.ini:1: #INCLUDE joints\\.inc: .*joints\\.inc: cannot open \\(No such file or directory\\)$")

lcnc_config(include_loop "#INCLUDE again.inc\n${LCNC_MILL}" again.inc "#INCLUDE include_loop.ini\n")
lcnc_refuses(include_loop "again\\.inc:1: #INCLUDE include_loop\\.ini includes itself")

# The machine file would overwrite the configuration.
lcnc_config(over_input "${LCNC_MILL}")
pkm_cli_refuses(linuxcnc_over_input "the output is the input file"
                import linuxcnc ${LCNC}/over_input/over_input.ini -o ${LCNC}/over_input/over_input.ini)

# The command end to end: tests/data's matrixkins mill imported to a file, which `pkm ik` then
# reads: C_xy 0.0003, C_xz -0.0001, C_zx 0.0002 move the joints of (300, 200, -100) to
# (300.07, 200, -99.94).
set(LCNC_MILL_TOML ${LCNC}/imported-mill.toml)
add_test(NAME cli.import_linuxcnc_matrixkins_then_ik
         COMMAND sh -c "rm -f \"$3\" && \"$0\" import linuxcnc \"$1\" --hallib \"$2\" -o \"$3\" && \"$0\" ik -m \"$3\" 300 200 -100 0 0"
                 $<TARGET_FILE:pkm> ${CLI_DATA}/linuxcnc/matrixkins/mill.ini
                 ${CLI_DATA}/linuxcnc/hallib ${LCNC_MILL_TOML})
set_tests_properties(cli.import_linuxcnc_matrixkins_then_ik PROPERTIES PASS_REGULAR_EXPRESSION
  "x = 300\\.070000 mm\ny = 200\\.000000 mm\nz = -99\\.940000 mm")

# A configuration pkm export linuxcnc wrote runs a machine file already: the import names it.
lcnc_config(pkmkins "[KINS]\nKINEMATICS = pkmkins machine=hexapod.toml\nJOINTS = 6\n")
lcnc_refuses(pkmkins
  "pkmkins\\.ini:2:\\[KINS\\]KINEMATICS: this configuration runs pkmkit's own module with hexapod\\.toml: use that machine file itself$")

# LinuxCNC's hexapod simulator: its -1000..1000 in joint and axis limits are placeholders, said on
# standard error with the numbers (the machine file is still written).
if(EXISTS ${PKM_LINUXCNC_SAMPLES}/sim/axis/vismach/hexapod-sim/hexapod.ini)
  add_test(NAME cli.linuxcnc_import_warns_of_placeholder_limits
           COMMAND pkm import linuxcnc
                   ${PKM_LINUXCNC_SAMPLES}/sim/axis/vismach/hexapod-sim/hexapod.ini
                   -o ${LCNC}/hexapod-sim-placeholders.toml)
  set_tests_properties(cli.linuxcnc_import_warns_of_placeholder_limits PROPERTIES
    PASS_REGULAR_EXPRESSION
    "hexapod\\.ini: warning: \\[JOINT_0\\] \\.\\. \\[JOINT_5\\] MIN_LIMIT/MAX_LIMIT are -1000 \\.\\. 1000 in on every joint: placeholders[^\n]*\n[^\n]*hexapod\\.ini: warning: \\[AXIS_X\\] \\[AXIS_Y\\] \\[AXIS_Z\\] MIN_LIMIT/MAX_LIMIT are -1000 \\.\\. 1000 in on every axis: placeholders, not a work envelope")
endif()

# pkm linuxcnc migrate refuses, saying where and why, and writes no directory: a module it does
# not switch from, JOINTS other than the machine file's (LinuxCNC's rdelta: 9 joints, the
# rotary delta 3), the configuration's own directory.
lcnc_config(migrate_trivkins "${LCNC_MILL}")
pkm_cli_refuses(linuxcnc_migrate_trivkins
  "migrate_trivkins\\.ini:2:\\[KINS\\]KINEMATICS: 'trivkins' is not a kinematics module pkm linuxcnc migrate switches from"
  NO_FILE ${LCNC}/migrate_trivkins-out
  linuxcnc migrate ${LCNC}/migrate_trivkins/migrate_trivkins.ini
  -m ${PROJECT_SOURCE_DIR}/examples/machines/matrix-mill.toml -o ${LCNC}/migrate_trivkins-out)
lcnc_config(migrate_joints "[KINS]\nKINEMATICS = genhexkins\nJOINTS = 3\n")
pkm_cli_refuses(linuxcnc_migrate_joints_not_the_machines
  "migrate_joints\\.ini:3:\\[KINS\\]JOINTS: \\[KINS\\] JOINTS = 3 but linuxcnc-hexapod-sim\\.toml has 6 joints"
  NO_FILE ${LCNC}/migrate_joints-out
  linuxcnc migrate ${LCNC}/migrate_joints/migrate_joints.ini
  -m ${PROJECT_SOURCE_DIR}/examples/machines/linuxcnc-hexapod-sim.toml -o ${LCNC}/migrate_joints-out)
lcnc_config(migrate_in_place "[KINS]\nKINEMATICS = genhexkins\nJOINTS = 6\n")
pkm_cli_refuses(linuxcnc_migrate_in_place
  "migrate_in_place is the configuration's own directory: give a new one"
  linuxcnc migrate ${LCNC}/migrate_in_place/migrate_in_place.ini
  -m ${PROJECT_SOURCE_DIR}/examples/machines/linuxcnc-hexapod-sim.toml -o ${LCNC}/migrate_in_place
  --force)
