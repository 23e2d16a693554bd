# A hanging effector's cable tensions from the command line: check's tension-feasible region,
# plan's tension-limited moves, and a move that leaves the tension limits at rest. (A ';' in a
# CMake argument splits it: the refusal's message matches it with '.'.)
set(TENSION_FRAME ${CLI_DATA}/maslow-tension.toml)
set(TENSION_JOB ${CLI_OUT}/tension-zigzag.ngc)
file(WRITE ${TENSION_JOB}
     "G21 G90\nG0 X-1150 Y580\nG1 F30000 X-1125 Y420\nX-1100 Y580\nX-1075 Y420\nM2\n")
set(TENSION_UP ${CLI_OUT}/tension-up.ngc)
file(WRITE ${TENSION_UP} "G1 X-100 Y800 F1000\nM2\n")

add_test(NAME cli.check_tension_region COMMAND ${PKM} check -m ${TENSION_FRAME})
set_tests_properties(cli.check_tension_region PROPERTIES PASS_REGULAR_EXPRESSION
  "tensions at rest \\(9 kg effector, tension_limits 5\\.\\.300 N\\), at the 1828 of 2400 grid points over x 0\\.0\\.\\.2978\\.4 y -3266\\.3\\.\\.0\\.0 mm the joints reach:\n    within the limits at 93\\.1 % [^\n]*\n[^\n]*\n    left +slack at +1\\.5 % \\(x 2903\\.9\\.\\.2953\\.6 [^\n]*\\), above 300 N at +3\\.9 %")
add_test(NAME cli.check_tension_region_json COMMAND ${PKM} check -m ${TENSION_FRAME} --json)
set_tests_properties(cli.check_tension_region_json PROPERTIES PASS_REGULAR_EXPRESSION
  "\"tensions\": \\{[^}]*\"cables\": \\[")
# A feed a cable's tension lowered says which way the cable fails (it said "by the right cable's
# tension"), and at a G64 corner what the tool's own acceleration allows there.
add_test(NAME cli.plan_says_how_a_tension_lowers_a_feed
         COMMAND ${PKM} plan -m ${TENSION_FRAME} ${TENSION_JOB} --origin 1489.2 -1072.6)
set_tests_properties(cli.plan_says_how_a_tension_lowers_a_feed PROPERTIES PASS_REGULAR_EXPRESSION
  "    line 5: F30000\\.0 lowered to F495\\.6 at the G64 corner blend after line 4 \\(turn 162\\.2 deg, radius 0\\.0118 mm\\): the right cable would go slack at a higher speed. the tool's own v\\^2/r allows F922\\.7 \\(within 20000\\.0 mm/s\\^2, 100\\.0 % of max_acceleration 20000\\.0\\)")
add_test(NAME cli.plan_names_tension_limited_moves
         COMMAND ${PKM} plan -m ${TENSION_FRAME} ${TENSION_JOB} --origin 1489.2 -1072.6)
set_tests_properties(cli.plan_names_tension_limited_moves PROPERTIES PASS_REGULAR_EXPRESSION
  "acceleration lowered by cable tensions on 6 moves \\(first at line 2, the left cable\\)\n.*    line 2: acceleration 20000\\.0 lowered to 8396\\.3 mm/s\\^2: the left cable would go slack")
pkm_cli_refuses(plan_leaves_the_tension_limits
  "tension-up\\.ngc:1: the move leaves the machine's reach at 92\\.0 % of it: pose x 1397\\.232 y -336\\.859 z 5\\.000 mm: tension: the left cable would be overloaded: 300\\.00 N, above tension_limits' max 300 N \\(move the pen lower, away from the top\\). the left cable's tension reaches 441 N, the right cable's tension reaches 440\\.4 N along the move"
  plan -m ${TENSION_FRAME} ${TENSION_UP} --origin 1489.2 -1072.6)
