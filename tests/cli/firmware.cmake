# pkm export TARGET and pkm import TARGET on the command line (docs/firmware.md): per target, one
# example machine it holds exactly (the summary and a setting), the round trip, a refusal, a
# bad file; --approximate on the examples a firmware cannot hold; a calibrated machine carried to
# FluidNC and to Klipper. The equations themselves are proven in tests/test_firmware_*.cpp.
set(FW_OUT ${CMAKE_CURRENT_BINARY_DIR}/firmware-out)
file(MAKE_DIRECTORY ${FW_OUT})
set(FW_DATA ${CMAKE_CURRENT_SOURCE_DIR}/data/firmware)
set(EXPECT_REFUSAL ${CMAKE_CURRENT_SOURCE_DIR}/cli/expect-refusal)

# pkm_firmware_export(NAME OUTPUT REGEX ARGS...): `pkm ARGS... -o OUTPUT`, then the written file;
# REGEX is matched against both (the summary line first).
function(pkm_firmware_export name output regex)
  add_test(NAME cli.firmware_${name}
           COMMAND sh -c "out=$1; shift; rm -f \"$out\"; \"$0\" \"$@\" -o \"$out\" && cat \"$out\""
                   ${PKM} ${output} ${ARGN})
  set_tests_properties(cli.firmware_${name} PROPERTIES PASS_REGULAR_EXPRESSION "${regex}")
endfunction()

# Exported exactly: the summary says so, and the setting that carries the geometry is the machine
# file's (less home where the firmware counts from the pen's start).
pkm_firmware_export(fluidnc_exports_maslow ${FW_OUT}/maslow.yaml
  "maslow\\.yaml: fluidnc config\\.yaml for Maslow CNC \\(GroundControl defaults\\) \\(two-cable wall plotter, exact\\).*right_anchor_x: 1489\\.200000\n.*right_anchor_y: 1072\\.600000\n.*startup_line0: G10 L2 P1 X-1489\\.200000 Y1072\\.600000 Z-5\\.000000"
  export fluidnc -m ${MACHINES}/maslow.toml)
pkm_firmware_export(klipper_exports_linear_delta ${FW_OUT}/linear-delta.cfg
  "linear-delta\\.cfg: klipper printer\\.cfg for Linear delta \\(linear delta, exact\\).*kinematics: delta\n.*delta_radius: 160  .*\\[stepper_a\\][^[]*angle: 90  [^[]*arm_length: 300  [^[]*position_endstop: 446\\.228449191  .*\\[stepper_b\\][^[]*angle: 210  "
  export klipper -m ${MACHINES}/linear-delta.toml)
pkm_firmware_export(rrf_exports_linear_delta ${FW_OUT}/linear-delta.g
  "linear-delta\\.g: rrf config\\.g for Linear delta \\(linear delta, exact\\).*M669 K3 .*M665 L300:300:300 R160 H446\\.228449 B120 X0 Y0 Z0 .*M666 X0 Y0 Z0 A0 B0 "
  export rrf -m ${MACHINES}/linear-delta.toml)
pkm_firmware_export(marlin_exports_hektor ${FW_OUT}/hektor.h
  "hektor\\.h: marlin Configuration\\.h for Hektor \\(source document, d = 100\\) \\(two-cable wall plotter, exact\\).*#define POLARGRAPH\n.*#define X_MAX_POS 100  .*#define MANUAL_X_HOME_POS 50  .*#define MANUAL_Y_HOME_POS -50  "
  export marlin -m ${MACHINES}/hektor.toml)
pkm_firmware_export(grblhal_exports_rotary_delta ${FW_OUT}/rdelta.txt
  "rdelta\\.txt: grblhal \\$ settings for LinuxCNC rdelta \\(rotarydeltakins 10, 10, 18, 5 in\\) \\(rotary delta, exact\\).*DELTA_ROBOT.*\\$641=457\\.200 .*\\$642=254\\.000 .*\\$643=879\\.88181 "
  export grblhal --kinematics -m ${MACHINES}/linuxcnc-rdelta.toml)
# Without --kinematics, `pkm export grblhal` still writes the joints' $ settings of a machine
# whose [controller] is grblHAL (docs/grbl.md): wall-plotter.toml's own is grbl, so a copy.
add_test(NAME cli.firmware_grblhal_without_kinematics_writes_joint_settings
         COMMAND sh -c "sed 's/^kind = \"grbl\"/kind = \"grblhal\"/' \"$1\" >\"$2/wall-plotter-grblhal.toml\" && grep -q '^kind = \"grblhal\"' \"$2/wall-plotter-grblhal.toml\" && \"$0\" export grblhal -m \"$2/wall-plotter-grblhal.toml\" -o \"$2/joints.txt\" && cat \"$2/joints.txt\""
                 ${PKM} ${MACHINES}/wall-plotter.toml ${FW_OUT})
set_tests_properties(cli.firmware_grblhal_without_kinematics_writes_joint_settings PROPERTIES
  PASS_REGULAR_EXPRESSION "joints\\.txt: [0-9]+ grblhal settings for Wall plotter 1500: send it line by line.*\\$100=")
add_test(NAME cli.firmware_grblhal_approximate_needs_kinematics
         COMMAND ${EXPECT_REFUSAL} --no-file ${FW_OUT}/never.txt "--approximate needs --kinematics"
                 ${PKM} export grblhal --approximate -m ${MACHINES}/wall-plotter.toml
                 -o ${FW_OUT}/never.txt)

# Import of the exported file, export of the imported machine: the same settings, and from the
# second generation on the same text (tests/firmware-round-trip.sh). RRF's and grblHAL's comments
# name the joints, which the imported machine names after the firmware's towers and arms (the
# last argument: an extended regex of those comment lines; CMake lists forbid a ';' in it).
function(pkm_firmware_round_trip name target machine)
  add_test(NAME cli.firmware_${name}_round_trip
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/firmware-round-trip.sh ${PKM} ${target}
                   ${MACHINES}/${machine} ${FW_OUT}/round-trip-${name} ${ARGN})
  set_tests_properties(cli.firmware_${name}_round_trip PROPERTIES PASS_REGULAR_EXPRESSION
                       "round trip: [0-9]+ lines, the same text")
endfunction()
pkm_firmware_round_trip(fluidnc_maslow fluidnc maslow.toml)
pkm_firmware_round_trip(fluidnc_hektor fluidnc hektor.toml)
pkm_firmware_round_trip(fluidnc_maslow4 fluidnc maslow4.toml)
pkm_firmware_round_trip(klipper_linear_delta klipper linear-delta.toml)
pkm_firmware_round_trip(rrf_linear_delta rrf linear-delta.toml "^. drive [XYZ] = ")
pkm_firmware_round_trip(rrf_rotary_delta rrf linuxcnc-rdelta.toml "^. drive [XYZ] = ")
pkm_firmware_round_trip(marlin_hektor marlin hektor.toml)
pkm_firmware_round_trip(marlin_linear_delta marlin linear-delta.toml)
pkm_firmware_round_trip(grblhal_rotary_delta grblhal linuxcnc-rdelta.toml "^\\(motor A = ")
# The cable robot: its header says what the firmware does not check (the mover's mass,
# the tension limits), which the imported machine has not.
pkm_firmware_round_trip(klipper_hangprinter klipper hangprinter-v4.toml
                        "^. Not checked by the firmware")
pkm_firmware_round_trip(rrf_hangprinter rrf hangprinter-v4.toml
                        "^. Not checked by the firmware")

# A machine of a form the target has not: refused, the forms named, no file left behind.
function(pkm_firmware_refuses name message)
  add_test(NAME cli.firmware_${name}
           COMMAND ${EXPECT_REFUSAL} --no-file ${FW_OUT}/${name}.out ${message}
                   ${PKM} ${ARGN} -o ${FW_OUT}/${name}.out)
endfunction()
pkm_firmware_refuses(fluidnc_refuses_a_linear_delta
  "fluidnc has kinematics for a two-cable wall plotter, a rotary delta or a cable robot on swivel arms \\(Maslow 4\\). this machine's model is glide \\(a linear delta\\)"
  export fluidnc -m ${MACHINES}/linear-delta.toml)
pkm_firmware_refuses(klipper_refuses_a_wall_plotter
  "klipper has kinematics for a linear delta, a rotary delta or a cable robot. this machine's model is cable_plotter \\(a two-cable wall plotter\\)"
  export klipper -m ${MACHINES}/hektor.toml)
pkm_firmware_refuses(rrf_refuses_a_hexapod
  "rrf has kinematics for a linear delta, a rotary delta or a cable robot. this machine's model is hexapod"
  export rrf -m ${MACHINES}/hexapod-bit.toml)
pkm_firmware_refuses(marlin_refuses_a_rotary_delta
  "marlin has kinematics for a two-cable wall plotter or a linear delta. this machine's model is rotary_delta \\(a rotary delta\\)"
  export marlin -m ${MACHINES}/linuxcnc-rdelta.toml)
pkm_firmware_refuses(grblhal_refuses_a_linear_delta
  "grblhal has kinematics for a two-cable wall plotter or a rotary delta. this machine's model is glide \\(a linear delta\\)"
  export grblhal --kinematics -m ${MACHINES}/linear-delta.toml)
pkm_firmware_refuses(klipper_refuses_maslow4_swivel_arms
  "maslow4\\.toml: klipper's cable robot kinematics cannot hold this machine exactly:"
  export klipper --approximate -m ${MACHINES}/maslow4.toml)
set_tests_properties(cli.firmware_klipper_refuses_maslow4_swivel_arms PROPERTIES
  PASS_REGULAR_EXPRESSION "exactly:\n  - swivel_arm 153\\.400 mm: .*\n  - cables_follow_z: .*\npkmkit does not approximate a cable robot"
  FAIL_REGULAR_EXPRESSION "expect-refusal:")
# A machine of the form, with what the form cannot hold: refused, listed, --approximate offered.
pkm_firmware_refuses(fluidnc_refuses_pulleys_without_approximate
  "makelangelo\\.toml: fluidnc's two-cable wall plotter kinematics cannot hold this machine exactly:"
  export fluidnc -m ${MACHINES}/makelangelo.toml)
# (the whole message, over its lines; expect-refusal still judges the exit status and the file)
set_tests_properties(cli.firmware_fluidnc_refuses_pulleys_without_approximate PROPERTIES
  PASS_REGULAR_EXPRESSION "cannot hold this machine exactly:\n  - pulley_radius 6\\.366 mm: the cords leave their pulleys tangentially.*\n--approximate writes the nearest two-cable wall plotter it can hold"
  FAIL_REGULAR_EXPRESSION "expect-refusal:")

# --approximate: the nearest machine the firmware holds, its worst tool error in the summary and
# in the file's header (the numbers docs/firmware.md's table gives).
foreach(target fluidnc marlin)
  pkm_firmware_export(${target}_approximates_makelangelo ${FW_OUT}/makelangelo-${target}.out
    "approximated: worst tool error 16\\.92[0-9]* mm at x -202\\.5 y -771\\.3 z 0\\.0 mm, rms 6\\.19[0-9]* mm.*Worst tool error 16\\.92[0-9]* mm"
    export ${target} --approximate -m ${MACHINES}/makelangelo.toml)
  pkm_firmware_export(${target}_approximates_maslow_frame ${FW_OUT}/maslow-frame-${target}.out
    "approximated: worst tool error 48\\.9[45][0-9]* mm at x 2649\\.4 y -2158\\.0 z 20\\.0 mm, rms 17\\.6[0-9]* mm.*Worst tool error 48\\.9[45][0-9]* mm"
    export ${target} --approximate -m ${MACHINES}/maslow-frame.toml)
endforeach()
# Klipper's delta has one delta_radius: a tower 0.5 mm out (a copy of linear-delta.toml) is
# refused with the cost, and --approximate writes the nearest delta Klipper holds with that cost
# (it once refused all the same: the command line did not pass --approximate to the target).
add_test(NAME cli.firmware_klipper_approximates_a_tower_off_the_circle
         COMMAND sh -c "sed 's/^origin = \\[0.0, 200.0, 0.0\\]/origin = [0.0, 200.5, 0.0]/' \"$1\" >\"$2/tower-out.toml\" && grep -q '200.5' \"$2/tower-out.toml\" && ! \"$0\" export klipper -m \"$2/tower-out.toml\" -o \"$2/tower-out.cfg\" 2>&1 && \"$0\" export klipper --approximate -m \"$2/tower-out.toml\" -o \"$2/tower-out.cfg\" 2>&1 && cat \"$2/tower-out.cfg\""
                 ${PKM} ${MACHINES}/linear-delta.toml ${FW_OUT})
set_tests_properties(cli.firmware_klipper_approximates_a_tower_off_the_circle PROPERTIES
  PASS_REGULAR_EXPRESSION "are 160\\.500000, 160\\.000000 and 160\\.000000 mm from it.*would cost a tool error of up to 0\\.106[0-9]* mm.*tower-out\\.cfg: klipper printer\\.cfg for Linear delta \\(linear delta, approximated: worst tool error 0\\.106[0-9] mm.*# Worst tool error 0\\.106[0-9] mm.*delta_radius: 160\\.")

# A firmware file without a setting the machine needs (tests/data/firmware: pkm's own exports with
# one line taken out): refused at the file's line, nothing written.
function(pkm_firmware_bad_import name target file message)
  add_test(NAME cli.firmware_${name}
           COMMAND ${EXPECT_REFUSAL} --no-file ${FW_OUT}/${name}.toml ${message}
                   ${PKM} import ${target} ${FW_DATA}/${file} -o ${FW_OUT}/${name}.toml)
endfunction()
pkm_firmware_bad_import(fluidnc_import_missing_anchor fluidnc fluidnc-no-left-anchor-x.yaml
  "fluidnc-no-left-anchor-x\\.yaml:6: left_anchor_x: missing in WallPlotter:")
pkm_firmware_bad_import(klipper_import_missing_arm_length klipper klipper-no-arm-length.cfg
  "klipper-no-arm-length\\.cfg:19: \\[stepper_a\\] arm_length: must be given")
pkm_firmware_bad_import(rrf_import_missing_m665 rrf rrf-no-m665.g
  "rrf-no-m665\\.g:15: M665 L: not set \\(the diagonal rods, mm\\)")
pkm_firmware_bad_import(marlin_import_missing_x_max_pos marlin marlin-no-x-max-pos.h
  "marlin-no-x-max-pos\\.h:4: X_MAX_POS: missing")
pkm_firmware_bad_import(grblhal_import_missing_641 grblhal grblhal-no-641.txt
  "grblhal-no-641\\.txt:17: \\$641: missing \\(forearm length re, mm\\)")

# A calibrated Klipper delta (its SAVE_CONFIG block: towers of different rods and endstops, so the
# carriages home the tool off x = y = 0) imports, its home lowered by rounding's worth where the
# inverse kinematics would read a carriage past its endstop (it once refused its own home:
# "joint 'stepper_a' = 699.812 mm passes its max 699.812 mm"), and exports its saved values.
add_test(NAME cli.firmware_klipper_imports_a_calibrated_delta
         COMMAND sh -c "rm -f \"$2/calibrated.toml\" \"$2/calibrated.cfg\"; \"$0\" import klipper \"$1\" -o \"$2/calibrated.toml\" && grep '^home = ' \"$2/calibrated.toml\" && \"$0\" export klipper -m \"$2/calibrated.toml\" -o \"$2/calibrated.cfg\" && cat \"$2/calibrated.cfg\""
                 ${PKM} ${FW_DATA}/klipper-delta-calibrated.cfg ${FW_OUT})
set_tests_properties(cli.firmware_klipper_imports_a_calibrated_delta PROPERTIES
  PASS_REGULAR_EXPRESSION "calibrated\\.toml: machine file of Klipper delta.*home = \\[0\\.0, 0\\.3036[0-9]*, 446\\.3412[0-9]*\\].*delta_radius: 160\\.214313  .*\\[stepper_a\\][^[]*angle: 90  [^[]*arm_length: 299\\.697938  [^[]*position_endstop: 446\\.533108  .*\\[stepper_b\\][^[]*angle: 209\\.998947  [^[]*arm_length: 300\\.252411  [^[]*position_endstop: 446\\.24531  ")

# Calibration to firmware (docs/firmware.md): pkm calibrate fit, then pkm export of the fitted
# machine carries the fitted geometry.
# Hektor measured (tests/data/hektor-measurements.csv: right anchor 0.6 mm out) to FluidNC: the
# anchors less home (x 50 y -50).
add_test(NAME cli.firmware_calibrated_hektor_to_fluidnc
         COMMAND sh -c "rm -f \"$3/hektor-fitted.toml\" \"$3/hektor-fitted.yaml\"; \"$0\" calibrate fit -m \"$1\" \"$2\" -o \"$3/hektor-fitted.toml\" && \"$0\" export fluidnc -m \"$3/hektor-fitted.toml\" -o \"$3/hektor-fitted.yaml\" && cat \"$3/hektor-fitted.yaml\""
                 ${PKM} ${MACHINES}/hektor.toml ${CMAKE_CURRENT_SOURCE_DIR}/data/hektor-measurements.csv
                 ${FW_OUT})
set_tests_properties(cli.firmware_calibrated_hektor_to_fluidnc PROPERTIES PASS_REGULAR_EXPRESSION
  "anchor_right_x +100\\.000000 +100\\.(59999|60000)[0-9].*hektor-fitted\\.yaml: fluidnc config\\.yaml for Hektor \\(source document, d = 100\\) \\(two-cable wall plotter, exact\\).*left_anchor_x: -(49\\.99999|50\\.00000)[0-9]\n.*left_anchor_y: (49\\.99999|50\\.00000)[0-9]\n.*right_anchor_x: (50\\.59999|50\\.60000)[0-9]\n.*right_anchor_y: (49\\.99999|50\\.00000)[0-9]\n")
# A linear delta built with rail 2's strut 301.2 mm and rail 3's origin 0.8 mm up
# (tests/data/delta-measurements.csv, tools/make-delta-measurements.sh) to Klipper: stepper_b's
# arm_length 301.2, stepper_c's position_endstop 0.8 mm above stepper_a's. Fitting only what
# Klipper has per tower (struts, carriage offsets) keeps the towers on one circle.
add_test(NAME cli.firmware_calibrated_delta_to_klipper
         COMMAND sh -c "rm -f \"$3/delta-fitted.toml\" \"$3/delta-fitted.cfg\"; \"$0\" calibrate fit -m \"$1\" \"$2\" --params 'rail*.strut,rail*.origin.z' -o \"$3/delta-fitted.toml\" && \"$0\" export klipper -m \"$3/delta-fitted.toml\" -o \"$3/delta-fitted.cfg\" && cat \"$3/delta-fitted.cfg\""
                 ${PKM} ${MACHINES}/linear-delta.toml
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/delta-measurements.csv ${FW_OUT})
set_tests_properties(cli.firmware_calibrated_delta_to_klipper PROPERTIES PASS_REGULAR_EXPRESSION
  "rail2\\.strut +300\\.000000 +301\\.(199|200)[0-9]* .*rail3\\.origin\\.z +0\\.000000 +0\\.(799|800|801)[0-9]* .*delta-fitted\\.cfg: klipper printer\\.cfg for Linear delta \\(linear delta, exact\\).*delta_radius: 160  .*\\[stepper_a\\][^[]*arm_length: 300\\.000[0-9]*  [^[]*position_endstop: 446\\.22[78][0-9]*  .*\\[stepper_b\\][^[]*arm_length: 301\\.(199|200)[0-9]*  [^[]*position_endstop: 444\\.81[01][0-9]*  .*\\[stepper_c\\][^[]*arm_length: 300\\.000[0-9]*  [^[]*position_endstop: 447\\.02[89][0-9]*  ")
# The same fit to RepRapFirmware: RRF's tower A is tower_b (at 210 deg), so M665 L lists the rods
# B C A of the machine file; the endstops become H (their mean) and M666's corrections.
add_test(NAME cli.firmware_calibrated_delta_to_rrf
         COMMAND sh -c "rm -f \"$3/delta-fitted-rrf.toml\" \"$3/delta-fitted.g\"; \"$0\" calibrate fit -m \"$1\" \"$2\" --params 'rail*.strut,rail*.origin.z' -o \"$3/delta-fitted-rrf.toml\" >/dev/null && \"$0\" export rrf -m \"$3/delta-fitted-rrf.toml\" -o \"$3/delta-fitted.g\" && cat \"$3/delta-fitted.g\""
                 ${PKM} ${MACHINES}/linear-delta.toml
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/delta-measurements.csv ${FW_OUT})
set_tests_properties(cli.firmware_calibrated_delta_to_rrf PROPERTIES PASS_REGULAR_EXPRESSION
  "delta-fitted\\.g: rrf config\\.g for Linear delta \\(linear delta, exact\\).*M665 L301\\.(199|200)[0-9]*:300\\.000[0-9]*:300\\.000[0-9]* R160 H446\\.02[23][0-9]* .*M666 X-1\\.21[12][0-9]* Y1\\.00[56][0-9]* Z0\\.20[56][0-9]* ")
# Fitting the rails' origins in x and y as well moves the towers off one circle by the
# measurements' noise: Klipper's delta refuses that, --approximate states what it costs.
add_test(NAME cli.firmware_calibrated_delta_origins_to_klipper_approximate
         COMMAND sh -c "rm -f \"$3/delta-fitted-xyz.toml\" \"$3/delta-fitted-xyz.cfg\"; \"$0\" calibrate fit -m \"$1\" \"$2\" --params 'rail*.strut,rail*.origin.*' -o \"$3/delta-fitted-xyz.toml\" >/dev/null && ! \"$0\" export klipper -m \"$3/delta-fitted-xyz.toml\" -o \"$3/delta-fitted-xyz.cfg\" 2>&1 && test ! -e \"$3/delta-fitted-xyz.cfg\" && \"$0\" export klipper --approximate -m \"$3/delta-fitted-xyz.toml\" -o \"$3/delta-fitted-xyz.cfg\" 2>&1 && cat \"$3/delta-fitted-xyz.cfg\""
                 ${PKM} ${MACHINES}/linear-delta.toml
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/delta-measurements.csv ${FW_OUT})
set_tests_properties(cli.firmware_calibrated_delta_origins_to_klipper_approximate PROPERTIES
  PASS_REGULAR_EXPRESSION "klipper's delta puts every tower at one delta_radius from the origin.*delta-fitted-xyz\\.cfg: klipper printer\\.cfg for Linear delta \\(linear delta, approximated: worst tool error 0\\.00[0-9]+ mm.*\\[stepper_b\\][^[]*arm_length: 301\\.(19|20)[0-9]*  ")
# The measurements are what the script makes of linear-delta.toml today.
add_test(NAME cli.firmware_delta_measurements_reproducible
         COMMAND sh -c "\"$1\" \"$0\" \"$2\" \"$4/delta-measurements.csv\" && cmp \"$3\" \"$4/delta-measurements.csv\" && echo 'the same measurements'"
                 ${PKM} ${PROJECT_SOURCE_DIR}/tools/make-delta-measurements.sh
                 ${MACHINES}/linear-delta.toml
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/delta-measurements.csv ${FW_OUT})
set_tests_properties(cli.firmware_delta_measurements_reproducible PROPERTIES
                     PASS_REGULAR_EXPRESSION "the same measurements")

# Maslow 4's belts: MaslowKinematics' keys as its firmware reads them; a Hangprinter is refused.
pkm_firmware_export(fluidnc_exports_maslow4 ${FW_OUT}/maslow4.yaml
  "cable robot on swivel arms, exact.*MaslowKinematics:\n    tlX: -27\\.600000\n    tlY: 2064\\.900000\n    tlZ: 100\\.000000\n.*brZ: 78\\.000000\n    beltEndExtension: 30\\.000000\n    armLength: 123\\.400000"
  export fluidnc -m ${MACHINES}/maslow4.toml)
pkm_firmware_refuses(fluidnc_refuses_a_hangprinter
  "fluidnc has kinematics for .* cable robot on swivel arms \\(Maslow 4\\). this machine's model is cable_robot \\(a cable robot\\)"
  export fluidnc -m ${MACHINES}/hangprinter-v4.toml)
# A user's maslow.yaml (Maslow_4's FluidNC/data/maslow.yaml's keys and values): read, what is not
# kinematics named; a corner's key missing names its line.
add_test(NAME cli.firmware_fluidnc_imports_a_maslow_yaml
         COMMAND ${PKM} import fluidnc ${FW_DATA}/maslow-users.yaml -o ${FW_OUT}/maslow-users.toml)
set_tests_properties(cli.firmware_fluidnc_imports_a_maslow_yaml PROPERTIES PASS_REGULAR_EXPRESSION
  "machine file of Maslow S3 Board")
pkm_firmware_bad_import(fluidnc_import_maslow_missing_brz fluidnc maslow-no-brz.yaml
  "maslow-no-brz\\.yaml:9: brZ: missing in MaslowKinematics:")
