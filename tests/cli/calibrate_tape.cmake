# Tape-measure calibration from the command line: the pattern written and planned, the fit of
# distances a tape gave on the wall plotter (tests/data: a hidden machine 7 mm wider, cable
# offsets 6 and -4 mm, read to the half millimetre), and bad input refused with its place.
set(TAPE_PATTERN ${CLI_DATA}/wall-plotter-pattern.json)
set(TAPE_DISTANCES ${CLI_DATA}/wall-plotter-distances.csv)

add_test(NAME cli.calibrate_pattern_writes_program_and_marks
         COMMAND ${PKM} calibrate pattern -m ${PLOTTER} -o ${CLI_OUT}/tape-pattern.ngc)
set_tests_properties(cli.calibrate_pattern_writes_program_and_marks PROPERTIES
  FIXTURES_SETUP tape_pattern
  PASS_REGULAR_EXPRESSION "12 marks \\(crosses of \\+-10\\.0 mm\\).*all 66 distances between them identify: .*cable_offset_left, cable_offset_right.*wrote .*tape-pattern\\.ngc and .*tape-pattern\\.json")
# The program is ordinary G-code the machine plans, and pattern.json is what `fit` reads back.
add_test(NAME cli.calibrate_pattern_plans
         COMMAND ${PKM} plan -m ${PLOTTER} ${CLI_OUT}/tape-pattern.ngc)
set_tests_properties(cli.calibrate_pattern_plans PROPERTIES FIXTURES_REQUIRED tape_pattern
  PASS_REGULAR_EXPRESSION "tape-pattern\\.ngc on Wall plotter 1500")
add_test(NAME cli.calibrate_pattern_is_the_checked_in_one
         COMMAND ${CMAKE_COMMAND} -E compare_files ${CLI_OUT}/tape-pattern.json ${TAPE_PATTERN})
set_tests_properties(cli.calibrate_pattern_is_the_checked_in_one PROPERTIES
  FIXTURES_REQUIRED tape_pattern)

add_test(NAME cli.calibrate_fit_distances_recovers_the_wall_plotter
         COMMAND ${PKM} calibrate fit -m ${PLOTTER} --distances ${TAPE_DISTANCES}
                 --pattern ${TAPE_PATTERN} -o ${CLI_OUT}/tape-fitted.toml)
set_tests_properties(cli.calibrate_fit_distances_recovers_the_wall_plotter PROPERTIES
  PASS_REGULAR_EXPRESSION "66 distances; residual \\(per distance, mm\\): RMS 3\\.8[0-9]+ max 9\\.0[0-9]+ before, RMS 0\\.1[0-9]+ max 0\\.2[0-9]+ after.*cable_offset_left +0\\.000000 +5\\.9[0-9]+.*wrote")

pkm_cli_refuses(calibrate_fit_unknown_mark
                "wall-plotter-distances-unknown-mark\\.csv:3:3: mark 99 is not in the pattern \\(its marks: 1 \\.\\. 12\\)"
                NO_FILE ${CLI_OUT}/tape-never.toml
                calibrate fit -m ${PLOTTER} --distances ${CLI_DATA}/wall-plotter-distances-unknown-mark.csv
                --pattern ${TAPE_PATTERN} -o ${CLI_OUT}/tape-never.toml)
pkm_cli_refuses(calibrate_fit_pattern_is_not_json "hektor-measurements\\.csv:1:1: not JSON: "
                calibrate fit -m ${PLOTTER} --distances ${TAPE_DISTANCES}
                --pattern ${CLI_DATA}/hektor-measurements.csv -o ${CLI_OUT}/tape-never.toml)
pkm_cli_refuses(calibrate_fit_distances_need_the_pattern "--distances and --pattern go together"
                calibrate fit -m ${PLOTTER} --distances ${TAPE_DISTANCES} -o ${CLI_OUT}/tape-never.toml)
pkm_cli_refuses(calibrate_fit_poses_or_distances "give either the measured poses"
                calibrate fit -m ${PLOTTER} ${CLI_DATA}/hektor-measurements.csv
                --distances ${TAPE_DISTANCES} --pattern ${TAPE_PATTERN} -o ${CLI_OUT}/tape-never.toml)
pkm_cli_refuses(calibrate_pattern_output_is_json "-o names the G-code program"
                calibrate pattern -m ${PLOTTER} -o ${CLI_OUT}/tape.json)
pkm_cli_refuses(calibrate_pattern_too_many_marks "the machine reaches room for only [0-9]+ of 999 marks"
                calibrate pattern -m ${PLOTTER} -o ${CLI_OUT}/tape-many.ngc --marks 999)
pkm_cli_refuses(calibrate_pattern_marks_run_together
                "300 marks of 15\\.000 mm would stand 60\\.000 mm apart and run together \\(at least 75\\.000 mm\\)"
                calibrate pattern -m ${PLOTTER} -o ${CLI_OUT}/tape-many.ngc --marks 300 --cross-size 15)
# A mill's Z stops at 0: the default pen-up height of 5 mm is refused with the joint at fault,
# and the heights given with --down-z and --up-z are taken.
pkm_cli_refuses(calibrate_pattern_pen_heights
                "joint 'z' = 5\\.004 mm passes its max 0\\.000 mm. give the pen.s heights with --down-z and --up-z"
                NO_FILE ${CLI_OUT}/tape-mill.ngc
                calibrate pattern -m ${MACHINES}/matrix-mill.toml -o ${CLI_OUT}/tape-mill.ngc)
add_test(NAME cli.calibrate_pattern_pen_heights_given
         COMMAND ${PKM} calibrate pattern -m ${MACHINES}/matrix-mill.toml
                 -o ${CLI_OUT}/tape-mill-given.ngc --down-z -2 --up-z -1)
set_tests_properties(cli.calibrate_pattern_pen_heights_given PROPERTIES
  PASS_REGULAR_EXPRESSION "12 marks.*wrote")

# The wall plotter on GT2 pulleys (tests/data/wall-plotter-gt2*): the tape cannot pin the pulley
# radius, which trades with the anchors' distance and the offsets. The pattern says so before
# anything is drawn, and the fit holds it at the pulley's 6.366 mm with its numbers (it once
# drove it to 0 mm with a standard deviation of 0, silently).
add_test(NAME cli.calibrate_pattern_names_the_pulley_it_cannot_pin
         COMMAND ${PKM} calibrate pattern -m ${CLI_DATA}/wall-plotter-gt2.toml
                 -o ${CLI_OUT}/tape-gt2-pattern.ngc)
set_tests_properties(cli.calibrate_pattern_names_the_pulley_it_cannot_pin PROPERTIES
  PASS_REGULAR_EXPRESSION "identify: anchor_right_x, cable_offset_left, cable_offset_right\n.*held pulley_radius at its nominal 6\\.366 mm: measured to \\+-0\\.5 mm, the distances would pin it only to \\+-5\\.0[0-9]+ mm, worse than the \\+-1\\.273 mm \\(20 % of its nominal value\\) a pulley's radius plausibly is off its machine file; it trades with anchor_right_x \\(correlation 1\\.00\\)")
add_test(NAME cli.calibrate_fit_distances_holds_the_gt2_pulley
         COMMAND ${PKM} calibrate fit -m ${CLI_DATA}/wall-plotter-gt2.toml
                 --distances ${CLI_DATA}/wall-plotter-gt2-distances.csv
                 --pattern ${CLI_DATA}/wall-plotter-gt2-pattern.json -o ${CLI_OUT}/tape-gt2-fitted.toml)
set_tests_properties(cli.calibrate_fit_distances_holds_the_gt2_pulley PROPERTIES
  PASS_REGULAR_EXPRESSION "pulley_radius +6\\.366000 +\\(held\\).*cable_offset_left +0\\.000000 +6\\.5[0-9]+.*warning: held pulley_radius at its nominal 6\\.366 mm: the data pin it only to \\+-5\\.2[0-9]+ mm \\(the fit put it at [0-9.e+-]+ mm\\).*trades with anchor_right_x \\(correlation 1\\.00\\), cable_offset_right \\(correlation -0\\.98\\), cable_offset_left \\(correlation -0\\.98\\).*wrote")
# Distances 10 % long (another tape than the pattern's): the offsets the data pin firmly come out
# 140 mm off, beyond three times what a cable's zero plausibly is off: refused, nothing written.
pkm_cli_refuses(calibrate_fit_nonsense_offsets
                "the fit is nonsense, nothing written: cable_offset_left = 137\\.9 mm \\(standard deviation 17\\.8 mm\\) is nonsense for a cable's zero of this machine: 137\\.9 mm from the machine file's 0 mm, more than 3 x 43\\.01 mm \\(2 mm \\+ 2 % of the machine's size of 2051 mm\\).{2}it trades with cable_offset_right \\(correlation 1\\.00\\)"
                NO_FILE ${CLI_OUT}/tape-never.toml
                calibrate fit -m ${PLOTTER} --distances ${CLI_DATA}/wall-plotter-distances-long.csv
                --pattern ${TAPE_PATTERN} -o ${CLI_OUT}/tape-never.toml)
