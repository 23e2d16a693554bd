# Calibration from joint readings at poses nobody measured (`pkm calibrate readings`): readings
# of a hidden Hangprinter whose anchors are up to 35 mm off hangprinter-v4.toml, counted from home
# with 0.05 mm of noise (tests/data/hangprinter-readings.csv, made by
# tools/make-cable-readings.py --shift '0,-25,18 30,-22,15 -28,27,-20 0,0,35'), and bad input.
set(HANGPRINTER ${MACHINES}/hangprinter-v4.toml)
set(HP_READINGS ${CLI_DATA}/hangprinter-readings.csv)

# D's z is 35 mm low in the file: the fit finds it (2299.83 + 35 = 2334.83) to its deviation.
add_test(NAME cli.calibrate_readings_recovers_the_hangprinter
         COMMAND ${PKM} calibrate readings -m ${HANGPRINTER} ${HP_READINGS}
                 --params "cable*.anchor.*" -o ${CLI_OUT}/hangprinter-fitted.toml)
set_tests_properties(cli.calibrate_readings_recovers_the_hangprinter PROPERTIES
  FIXTURES_SETUP hangprinter_fitted
  PASS_REGULAR_EXPRESSION "30 samples of 4 readings \\(counted from home\\), 3 pose coordinates each solved for; residual \\(per reading, mm\\): RMS [0-9.]+ max [0-9.]+ before, RMS 0\\.0[0-9]+ max 0\\.[0-9]+ after.*noise of a reading by the residuals 0\\.0[3-7][0-9]* mm.*cable4\\.anchor\\.z +2299\\.830000 +233[0-9]\\.[0-9]+ .*the readings cannot see these .*held at the machine file's values: cable4\\.anchor\\.[xy], cable4\\.anchor\\.[xy], cable1\\.anchor\\.x.*line 31: .*wrote")
# The fitted file loads and fits its own readings with nothing left to move.
add_test(NAME cli.calibrate_readings_fitted_file_fits
         COMMAND ${PKM} calibrate readings -m ${CLI_OUT}/hangprinter-fitted.toml ${HP_READINGS}
                 --params "cable*.anchor.*" -o ${CLI_OUT}/hangprinter-refitted.toml)
set_tests_properties(cli.calibrate_readings_fitted_file_fits PROPERTIES
  FIXTURES_REQUIRED hangprinter_fitted
  PASS_REGULAR_EXPRESSION "RMS 0\\.0[0-9]+ max 0\\.[0-9]+ before")

pkm_cli_refuses(calibrate_readings_bad_number
                "hangprinter-readings-bad\\.csv:4:6: 'abc' is not a number"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-readings-bad.csv
                -o ${CLI_OUT}/readings-never.toml)
pkm_cli_refuses(calibrate_readings_too_few_samples
                "5 samples of 4 readings pin 1 each beyond their own 3 pose coordinates, 5 in all: too few for 9 parameters with the noise left to estimate.{2}take at least 10 samples"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-readings-few.csv
                --params "cable*.anchor.*" -o ${CLI_OUT}/readings-never.toml)
pkm_cli_refuses(calibrate_readings_pose_fixed_by_joints
                "a cable_plotter has 2 joints for 2 coordinates: its readings fix each pose"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${PLOTTER} ${CLI_DATA}/wall-plotter-readings.csv
                -o ${CLI_OUT}/readings-never.toml)
pkm_cli_refuses(calibrate_readings_output_is_the_data
                "the output is the input file .*hangprinter-readings\\.csv \\(the readings\\)"
                calibrate readings -m ${HANGPRINTER} ${HP_READINGS} -o ${HP_READINGS})

# The same hidden machine's lengths themselves (tools/make-cable-readings.py --absolute): the
# frame's place is unseen too, and the cables' offsets act and are fitted.
add_test(NAME cli.calibrate_readings_absolute
         COMMAND ${PKM} calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-readings-absolute.csv
                 --absolute -o ${CLI_OUT}/hangprinter-absolute-fitted.toml)
set_tests_properties(cli.calibrate_readings_absolute PROPERTIES
  PASS_REGULAR_EXPRESSION "30 samples of 4 readings \\(absolute\\).*noise of a reading by the residuals 0\\.0[3-7][0-9]* mm.*cable1\\.offset +0\\.000000 +-?[0-9]\\.[0-9]+ .*the readings cannot see these \\(the frame moved or turned as a whole, a point moved with its cable\\).*wrote")
# A gross outlier (line 4: the three low lines 900 mm shorter, D's 900 mm longer) puts the effector
# where the machine file's tension limits only just hold it: refused at its line, nothing written
# (it once held every parameter at nominal, wrote the file unchanged and exited 0).
pkm_cli_refuses(calibrate_readings_outlier_at_the_edge
                "hangprinter-readings-outlier\\.csv:4:1: the machine file's geometry only just holds the effector where these readings put it"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-readings-outlier.csv
                -o ${CLI_OUT}/readings-never.toml)
# A reading 12 mm off (line 11: line A slipped) inflates the noise estimate to 1.5 mm, so the
# warning measures it against the others' median, which one reading does not move.
add_test(NAME cli.calibrate_readings_names_a_slipped_reading
         COMMAND ${PKM} calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-readings-slip.csv
                 -o ${CLI_OUT}/hangprinter-slip-fitted.toml)
set_tests_properties(cli.calibrate_readings_names_a_slipped_reading PROPERTIES
  PASS_REGULAR_EXPRESSION "warning: a reading at line 11 is 4\\.[0-9]+ mm off the fit, [0-9]+ times the others' spread")

# Hangprinter's own auto-calibration data are motor positions in degrees from the origin (its
# encoders, M569.3): the same hidden machine read that way (tools/make-cable-readings.py
# --motor-degrees, same --shift), turned into line lengths through hangprinter-v4.toml's spools,
# fits the same anchors.
add_test(NAME cli.calibrate_readings_motor_degrees
         COMMAND ${PKM} calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-motor-degrees.csv
                 --motor-degrees --params "cable*.anchor.*"
                 -o ${CLI_OUT}/hangprinter-degrees-fitted.toml)
set_tests_properties(cli.calibrate_readings_motor_degrees PROPERTIES
  PASS_REGULAR_EXPRESSION "30 samples of 4 readings \\(motor degrees from the origin\\).*RMS 0\\.0[0-9]+ max 0\\.[0-9]+ after.*noise of a reading by the residuals 0\\.0[3-7][0-9]* mm.*cable4\\.anchor\\.z +2299\\.830000 +233[0-9]\\.[0-9]+ .*wrote")
pkm_cli_refuses(calibrate_readings_motor_degrees_without_spools
                "maslow4\\.toml: motor degrees need the spools that turn them into line lengths, and cable 1 \\(joint tl\\) has none: add spool_radius \\(mm, M666 R\\)"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${MACHINES}/maslow4.toml ${CLI_DATA}/hangprinter-motor-degrees.csv
                --motor-degrees -o ${CLI_OUT}/readings-never.toml)
pkm_cli_refuses(calibrate_readings_motor_degrees_bad_number
                "hangprinter-motor-degrees-bad\\.csv:4:11: '1860\\.05O4' is not a number"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-motor-degrees-bad.csv
                --motor-degrees -o ${CLI_OUT}/readings-never.toml)
pkm_cli_refuses(calibrate_readings_motor_degrees_not_absolute
                "motor-degrees: motor positions count from the origin. --absolute is for the joints' own values"
                NO_FILE ${CLI_OUT}/readings-never.toml
                calibrate readings -m ${HANGPRINTER} ${CLI_DATA}/hangprinter-motor-degrees.csv
                --motor-degrees --absolute -o ${CLI_OUT}/readings-never.toml)
