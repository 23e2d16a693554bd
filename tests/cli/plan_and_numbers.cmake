# Bad input to plan, gcode and calibrate, and the numbers of every command: each refused with the
# message a user can act on. Inputs that a failed refusal could overwrite are copies in CLI_OUT.
set(SQUARE ${CLI_OUT}/square.ngc)
file(WRITE ${SQUARE} "G0 X0 Y0\nG1 F400 X5 Y20\nG1 X15\nG1 X15 Y0\nG1 X0\nM2\n")
set(PLOTTER ${MACHINES}/wall-plotter.toml)
set(SPHERE ${PROJECT_SOURCE_DIR}/examples/jobs/sphere.ngc)
configure_file(${MACHINES}/hektor.toml ${CLI_OUT}/hektor.toml COPYONLY)
configure_file(${MACHINES}/matrix-mill.toml ${CLI_OUT}/matrix-mill.toml COPYONLY)
configure_file(${CLI_DATA}/hektor-measurements.csv ${CLI_OUT}/hektor-measurements.csv COPYONLY)

# Every number is finite and in range where the command line is read (NaN passes CLI11's own
# range checks: `--origin nan nan` dropped the whole job with status 0).
foreach(value nan inf)
  pkm_cli_refuses(plan_origin_${value} "--origin: '${value}' is not a finite number"
                  plan -m ${PLOTTER} ${SQUARE} --origin 600 ${value})
  pkm_cli_refuses(plan_start_${value} "--start: '${value}' is not a finite number"
                  plan -m ${PLOTTER} ${SQUARE} --start ${value} -700)
  pkm_cli_refuses(plan_period_${value} "--period: '${value}' is not a finite number"
                  plan ${SPHERE} --period ${value})
  pkm_cli_refuses(plan_jerk_${value} "--jerk: '${value}' is not a finite number"
                  plan ${SPHERE} --jerk ${value})
  pkm_cli_refuses(plan_max_samples_${value} "--max-samples: '${value}' is not a finite number"
                  plan ${SPHERE} --max-samples ${value})
  pkm_cli_refuses(demo_period_${value} "--period: '${value}' is not a finite number"
                  demo --period ${value})
  pkm_cli_refuses(post_tolerance_${value} "--tolerance: '${value}' is not a finite number"
                  post ${SPHERE} -o ${CLI_OUT}/never.ngc --tolerance ${value})
  pkm_cli_refuses(post_origin_${value} "--origin: '${value}' is not a finite number"
                  post ${SPHERE} -o ${CLI_OUT}/never.ngc --origin ${value} 0)
  pkm_cli_refuses(verify_tolerance_${value} "--tolerance: '${value}' is not a finite number"
                  verify ${SPHERE} --against ${SPHERE} --tolerance ${value})
  pkm_cli_refuses(verify_origin_${value} "--origin: '${value}' is not a finite number"
                  verify ${SPHERE} --against ${SPHERE} --origin 0 ${value})
  pkm_cli_refuses(ik_pose_${value} "pose: '${value}' is not a finite number" ik 0 0 ${value})
  pkm_cli_refuses(fk_joints_${value} "joints: '${value}' is not a finite number"
                  fk 1000 1000 1000 1000 1000 ${value})
  pkm_cli_refuses(fk_seed_${value} "--seed: '${value}' is not a finite number"
                  fk -m ${MACHINES}/hektor.toml --seed ${value} -40 -- 60 80)
  pkm_cli_refuses(calibrate_matrix_${value} "--diagonals: '${value}' is not a finite number"
                  calibrate matrix --diagonals 141.5 ${value})
endforeach()
pkm_cli_refuses(plan_origin_beyond_any_machine "--origin: 1e300 is outside \\[-1000000, 1000000\\]"
                plan -m ${PLOTTER} ${SQUARE} --origin 1e300 -800)
pkm_cli_refuses(plan_period_tiny "--period: 1e-300 is outside \\[1e-06, 1\\]"
                plan ${SPHERE} --period 1e-300)
pkm_cli_refuses(plan_period_zero "--period: 0 is outside \\[1e-06, 1\\]" plan ${SPHERE} --period 0)
pkm_cli_refuses(plan_jerk_negative "--jerk: -1 is outside \\[0, 1000000000000\\]"
                plan ${SPHERE} --jerk -1)
pkm_cli_refuses(plan_max_samples_zero "--max-samples: 0 is outside \\[1, 1e\\+15\\]"
                plan ${SPHERE} --max-samples 0)
pkm_cli_refuses(post_tolerance_tiny "--tolerance: 1e-300 is outside \\[0.0001, 1000\\]"
                post ${SPHERE} -o ${CLI_OUT}/never.ngc --tolerance 1e-300)

# A job whose samples would pass the bound is refused before anything is written, with its
# numbers: the sphere at a 1 us period is 250 million samples (its junctions, sized for the period,
# take a little longer than at 1 ms).
pkm_cli_refuses(plan_past_the_sample_bound
  "sphere.ngc would take 249.0[0-9]* s of machine time: 2490[0-9]{5} samples at 1e-06 s \\(NPY 27.9[0-9]* GB\\), more than --max-samples 50000000"
  NO_FILE ${CLI_OUT}/sphere-1us.npy
  plan ${SPHERE} -o ${CLI_OUT}/sphere-1us.npy --period 1e-6)
pkm_cli_refuses(plan_past_a_stated_bound "248906 samples at 0.001 s .*more than --max-samples 1000"
  NO_FILE ${CLI_OUT}/sphere-bounded.csv
  plan ${SPHERE} -o ${CLI_OUT}/sphere-bounded.csv --max-samples 1000)

# An output is never an input.
pkm_cli_refuses(plan_output_is_the_job "square.ngc: the output is the input file .*square.ngc \\(the job\\)"
                plan -m ${PLOTTER} ${SQUARE} --origin 600 -800 -o ${CLI_OUT}/./square.ngc)
pkm_cli_refuses(plan_report_is_the_job "square.ngc: the output is the input file .*square.ngc \\(the job\\)"
                plan -m ${PLOTTER} ${SQUARE} --origin 600 -800 --report ${SQUARE})
pkm_cli_refuses(plan_report_is_the_samples "-o .*square.csv and --report .*square.csv name the same file"
                plan -m ${PLOTTER} ${SQUARE} --origin 600 -800 -o ${CLI_OUT}/square.csv
                --report ${CLI_OUT}/square.csv)
pkm_cli_refuses(calibrate_fit_output_is_the_data "the output is the input file .*hektor-measurements.csv \\(the measurements\\)"
                calibrate fit -m ${CLI_OUT}/hektor.toml ${CLI_OUT}/hektor-measurements.csv
                -o ${CLI_OUT}/hektor-measurements.csv)
pkm_cli_refuses(calibrate_fit_output_is_the_machine "the output is the input file .*hektor.toml \\(the machine file\\)"
                calibrate fit -m ${CLI_OUT}/hektor.toml ${CLI_OUT}/hektor-measurements.csv
                -o ${CLI_OUT}/../cli-out/hektor.toml)
pkm_cli_refuses(calibrate_matrix_output_is_the_machine "the output is the input file .*matrix-mill.toml \\(the machine file of --add-to\\)"
                calibrate matrix --z-tilt-y 0.004 80 --add-to ${CLI_OUT}/matrix-mill.toml
                -o ${CLI_OUT}/matrix-mill.toml)

# Numbers in files: located, and nothing written.
pkm_cli_refuses(calibrate_fit_row_of_1e308
  "hektor-measurements-1e308.csv:5:1: '1e308' is beyond any machine"
  NO_FILE ${CLI_OUT}/fit-1e308.toml
  calibrate fit -m ${MACHINES}/hektor.toml ${CLI_DATA}/hektor-measurements-1e308.csv
  -o ${CLI_OUT}/fit-1e308.toml)
pkm_cli_refuses(gcode_tool_table_nan "tool-table-nan.tbl:3:7: tool table: Znan must be a finite number"
                gcode --tool-table ${CLI_DATA}/tool-table-nan.tbl ${SQUARE})
pkm_cli_refuses(gcode_tool_table_bad_orientation
                "tool-table-bad-orientation.tbl:3:18: tool table: Q \\(a lathe tool's orientation\\) must be a whole number from 0 to 9"
                gcode --tool-table ${CLI_DATA}/tool-table-bad-orientation.tbl ${SQUARE})
pkm_cli_refuses(plan_tool_table_nan "tool-table-nan.tbl:3:7: tool table: Znan must be a finite number"
                plan -m ${PLOTTER} ${SQUARE} --origin 600 -800 --tool-table ${CLI_DATA}/tool-table-nan.tbl)

# What plan and gcode say about a job before it runs (the square above on the wall plotter, its
# path 180.278 mm from home to the origin and 65.616 mm of feed), and help that names the pose.
add_test(NAME cli.plan_estimate_without_output
         COMMAND ${PKM} plan -m ${PLOTTER} ${SQUARE} --origin 600 -800)
set_tests_properties(cli.plan_estimate_without_output PROPERTIES PASS_REGULAR_EXPRESSION
  "square\\.ngc on Wall plotter 1500 \\(estimate, no samples made\\): 11\\.778 s, path 245\\.853 mm\n  11780 samples at the period: NPY 659\\.8 kB")
add_test(NAME cli.gcode_summary COMMAND ${PKM} gcode ${SQUARE})
set_tests_properties(cli.gcode_summary PROPERTIES PASS_REGULAR_EXPRESSION
  "5 moves, written in mm \\(G21\\).*\n  box +x 0\\.000 \\.\\. 15\\.000, y 0\\.000 \\.\\. 20\\.000, z 0\\.000 \\.\\. 0\\.000 mm\n.*  path +rapid 0\\.000 mm, feed 65\\.616 mm, arc 0\\.000 mm")
# A job's boxes as printed where it has no move, and where it has no feed move.
add_test(NAME cli.gcode_summary_empty_boxes
         COMMAND sh -c "printf 'M2\\n' > \"$1\" && printf 'G0 X1 Y-2 Z3\\nM2\\n' > \"$2\" && \"$0\" gcode \"$1\" && \"$0\" gcode \"$2\""
                 ${PKM} ${CLI_OUT}/no-moves.ngc ${CLI_OUT}/one-rapid.ngc)
set_tests_properties(cli.gcode_summary_empty_boxes PROPERTIES PASS_REGULAR_EXPRESSION
  "no-moves\\.ngc: 0 moves, written in no units \\(no moves\\).*\n  box +none\n  feed box +none\n.*one-rapid\\.ngc: 1 moves.*\n  box +x 1\\.000 \\.\\. 1\\.000, y -2\\.000 \\.\\. -2\\.000, z 3\\.000 \\.\\. 3\\.000 mm\n  feed box +none\n")
# M19's orientation with LinuxCNC's ORIENT_OFFSET: the same ORIENT_SPINDLE as rs274 with the INI
# setting it (R45 + 42 = 87 deg).
add_test(NAME cli.gcode_orient_offset_as_rs274
         COMMAND sh -c "cd \"$2\" && printf '[RS274NGC]\\nORIENT_OFFSET = 42\\n' > orient.ini && rs274 -i orient.ini -g \"$1\" | grep -o 'ORIENT_SPINDLE.*' > orient-rs274.txt && \"$0\" gcode --canon --orient-offset 42 \"$1\" | grep -o 'ORIENT_SPINDLE.*' > orient-pkm.txt && diff orient-rs274.txt orient-pkm.txt && grep -q 'ORIENT_SPINDLE(0, 87.0000, 0)' orient-pkm.txt"
                 ${PKM} ${PROJECT_SOURCE_DIR}/tests/gcode/spindle-orientation.ngc ${CLI_OUT})
set_tests_properties(cli.gcode_orient_offset_as_rs274 PROPERTIES RESOURCE_LOCK rs274)
foreach(command plan post verify)
  add_test(NAME cli.${command}_help_names_the_origin COMMAND ${PKM} ${command} --help)
  set_tests_properties(cli.${command}_help_names_the_origin PROPERTIES PASS_REGULAR_EXPRESSION
    "--origin x y \\[z \\[a b c\\]\\] +Where the (program|job)'s X0 Y0 Z0 sits in machine coordinates, in the machine file.s units \\(mm or inch\\) and deg")
endforeach()

# A refused option reads like every other error, with a status a shell script can tell apart
# from a failed run (2, not CLI11's 105).
add_test(NAME cli.refused_option_status_and_prefix
         COMMAND sh -c "\"$0\" plan -m \"$1\" \"$2\" --origin nan 0; test $? -eq 2"
                 ${PKM} ${PLOTTER} ${SQUARE})
pkm_cli_refuses(refused_option_prefix "^pkm: error: --origin: 'nan' is not a finite number"
                plan -m ${PLOTTER} ${SQUARE} --origin nan 0)
# post's bound on blocks (--max-blocks, the counterpart of plan's --max-samples): a million-turn
# arc is refused at its line from its estimate (70 million blocks at 0.01 mm) before any block is
# covered, nothing written; a hundred turns (7,475 blocks) pass the estimate under a bound of
# 7,100 (about 7,025) and are refused at the block that passes it.
pkm_cli_refuses(post_past_the_block_bound
  "helix-million-turns.ngc:3: this arc \\(62831853.07 mm of path, 1000000 turns\\) needs about 70242[0-9]{3} blocks to keep within 0.01 mm. with the 0 written before it, the joint program would pass the bound of 10000000 blocks. .* or raise --max-blocks"
  NO_FILE ${CLI_OUT}/helix.ngc
  post -m ${MACHINES}/hektor.toml ${CLI_DATA}/helix-million-turns.ngc --origin 10 0
  -o ${CLI_OUT}/helix.ngc)
pkm_cli_refuses(post_max_blocks_zero "--max-blocks: 0 is outside \\[1, 1e\\+15\\]"
                post ${SPHERE} -o ${CLI_OUT}/never.ngc --max-blocks 0)
