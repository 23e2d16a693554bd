# The N-cable robot (type = "cable_robot") through every command (issue 31, item 3): the
# Hangprinter v4 (examples/machines/hangprinter-v4.toml: 1 kg, tension_limits [0, 70] N) and the
# Maslow 4 (maslow4.toml: planar, swivel arms, no mass). Numbers by hand where they can be:
#   a line's length at home is |anchor| (the tie point is the tool point at 0 0 0):
#     A sqrt(1610.98^2 + 131.53^2) = 1616.3405 mm, D sqrt(0.01^2 + 2299.83^2) = 2299.8300 mm;
#   Maslow's tl at home: its corner (-27.6, 2064.9) is 1811.98 mm from (1461.9, 1033.073) in plan,
#     less the arm's 153.4, with the 100 mm height: sqrt(1658.58^2 + 100^2) = 1661.593 mm;
#   the tensions at home: the distribution nearest 35 N each (docs/cable-machines.md, "N cables":
#     A 39.6545, B 37.5787, C 30.2545, D 17.8454 N, checked there by its balance).
# (A ';' in a CMake argument splits it: messages match it with '.'.)
set(CR_OUT ${CLI_OUT}/cable_robot)
file(MAKE_DIRECTORY ${CR_OUT})
set(HANGPRINTER ${MACHINES}/hangprinter-v4.toml)
set(MASLOW4 ${MACHINES}/maslow4.toml)
# A 400 mm square 100 mm above the Hangprinter's origin, from home: 300 mm of travel (200, 200,
# 100) and 1600 mm drawn.
set(CR_SQUARE ${CR_OUT}/hangprinter-square.ngc)
file(WRITE ${CR_SQUARE} "G21 G90\nG0 X-200 Y-200 Z100\nG1 F6000 X200\nY200\nX-200\nY-200\nM2\n")
# A real router job (ShapeOko 2's "Hello World", inch, grbl's test files; SOURCES.md) on the Maslow.
set(CR_HELLO ${PKM_REAL_CORPUS}/grbl/SO2_helloworld.nc)

# ik: the joints and each cable's tension with its limits; --json the same.
add_test(NAME cli.cable_robot_ik_hangprinter_home COMMAND ${PKM} ik -m ${HANGPRINTER} 0 0 0)
set_tests_properties(cli.cable_robot_ik_hangprinter_home PROPERTIES PASS_REGULAR_EXPRESSION
  "^A = 1616\\.340528 mm\nB = 1830\\.317488 mm\nC = 1587\\.401480 mm\nD = 2299\\.830000 mm\ntension A = 39\\.654 N \\(limits \\[0, 70\\] N\\)\ntension B = 37\\.579 N \\(limits \\[0, 70\\] N\\)\ntension C = 30\\.254 N \\(limits \\[0, 70\\] N\\)\ntension D = 17\\.845 N \\(limits \\[0, 70\\] N\\)\n$")
add_test(NAME cli.cable_robot_ik_hangprinter_json COMMAND ${PKM} ik -m ${HANGPRINTER} --json 0 0 0)
set_tests_properties(cli.cable_robot_ik_hangprinter_json PROPERTIES PASS_REGULAR_EXPRESSION
  "\"tensions\":\\{\"held\":true,\"mass_kg\":1\\.0,\"max_N\":\\[70\\.0,70\\.0,70\\.0,70\\.0\\],\"min_N\":\\[0\\.0,0\\.0,0\\.0,0\\.0\\],\"names\":\\[\"A\",\"B\",\"C\",\"D\"\\],\"tension_N\":\\[39\\.654[0-9]*,37\\.578[0-9]*,30\\.254[0-9]*,17\\.845[0-9]*\\]\\}")
# Near the ceiling anchor D, 600 mm off its axis, the others would have to push: the refusal says
# which cable would need what, and the tensions nearest to holding it by name.
pkm_cli_refuses(cable_robot_ik_tension
  "pose x 600\\.000 y 600\\.000 z 1900\\.000 mm: tension: no tensions within tension_limits \\[0\\.000, 70\\.000\\] N hold the 1\\.000 kg effector here: cable 1 would need -4\\.176 N \\(its min 0\\.000 N\\). cable 2 would need -4\\.176 N \\(its min 0\\.000 N\\). cable 3 would need -3\\.071 N \\(its min 0\\.000 N\\). the tensions nearest to holding it: A -4\\.176 N, B -4\\.176 N, C -3\\.071 N, D 2\\.590 N \\(limits \\[0, 70\\] N\\)"
  ik -m ${HANGPRINTER} 600 600 1900)
# A sled without a mass or tension limits has no tensions to list.
add_test(NAME cli.cable_robot_ik_maslow_home COMMAND ${PKM} ik -m ${MASLOW4} 1461.9 1033.073 0)
set_tests_properties(cli.cable_robot_ik_maslow_home PROPERTIES
  PASS_REGULAR_EXPRESSION "^tl = 1661\\.593459 mm\ntr = 1638\\.251432 mm\nbl = 1637\\.034520 mm\nbr = 1662\\.601422 mm\nz = 0\\.000000 mm\n$"
  FAIL_REGULAR_EXPRESSION "tension")

# fk: home's joints give home back (to the printed digits), with the tensions there.
add_test(NAME cli.cable_robot_fk_hangprinter_round_trip
         COMMAND ${PKM} fk -m ${HANGPRINTER} 1616.340528 1830.317488 1587.401480 2299.83)
set_tests_properties(cli.cable_robot_fk_hangprinter_round_trip PROPERTIES PASS_REGULAR_EXPRESSION
  "^x = 0\\.000000 mm\ny = 0\\.000000 mm\nz = 0\\.000000 mm\ntension A = 39\\.654 N")
# A misfit: B read 5 mm long. With one line more than coordinates any one line could explain it
# (each by how much it reads more than the others fit: B's 5.005, to first order its 5 mm).
pkm_cli_refuses(cable_robot_fk_hangprinter_misfit
  "no pose for these joints on Hangprinter v4 .*: unreachable \\(joint 'A'\\): the cables fit no pose: the nearest leaves cable 'A' 1\\.879 mm off \\(RMS 1\\.491 mm, misfit_tolerance 0\\.010 mm\\). any one cable could explain it \\(its reading more than the others fit\\): 'A' by \\+4\\.731 mm, 'B' by \\+5\\.005 mm, 'C' by \\+6\\.193 mm, 'D' by \\+23\\.271 mm. with one cable more than coordinates the joints cannot tell which"
  fk -m ${HANGPRINTER} 1616.340528 1835.317488 1587.401480 2299.83)
# On the Maslow (four belts, two coordinates) one belt alone explains it: br read 10 mm long.
pkm_cli_refuses(cable_robot_fk_maslow_slack_belt
  "unreachable \\(joint 'br'\\): the cables fit no pose: the nearest leaves cable 'tl' 5\\.001 mm off \\(RMS 3\\.534 mm, misfit_tolerance 0\\.010 mm\\). cable 'br' alone explains it: it reads 10\\.002 mm more than the others fit \\(slack or mismeasured\\?\\)"
  fk -m ${MASLOW4} 1661.593459 1638.251432 1637.034520 1672.601422 0)

# check: the tensions at home at rest, text and JSON.
add_test(NAME cli.cable_robot_check_hangprinter COMMAND ${PKM} check -m ${HANGPRINTER})
set_tests_properties(cli.cable_robot_check_hangprinter PROPERTIES PASS_REGULAR_EXPRESSION
  "  tensions at home at rest \\(1 kg effector, tension_limits \\[0, 70\\] N\\):\n    tension A = 39\\.654 N \\(limits \\[0, 70\\] N\\)\n    tension B = 37\\.579 N [^\n]*\n    tension C = 30\\.254 N [^\n]*\n    tension D = 17\\.845 N [^\n]*\n  ok: machine file is valid")
add_test(NAME cli.cable_robot_check_hangprinter_json
         COMMAND ${PKM} check -m ${HANGPRINTER} --json)
set_tests_properties(cli.cable_robot_check_hangprinter_json PROPERTIES PASS_REGULAR_EXPRESSION
  "\"home_tensions\": \\{\n    \"held\": true,")

# plan: the square's joints. A is shortest at (0, -200, 100), nearest its anchor:
# sqrt(1410.98^2 + 231.53^2) = 1429.850 mm; D longest at home (2299.830) and shortest mid-edge,
# sqrt(200^2 + 2199.83^2) = 2208.903 mm.
add_test(NAME cli.cable_robot_plan_hangprinter_square
         COMMAND ${PKM} plan -m ${HANGPRINTER} ${CR_SQUARE})
set_tests_properties(cli.cable_robot_plan_hangprinter_square PROPERTIES PASS_REGULAR_EXPRESSION
  "path 1899\\.9[0-9]* mm\n.*\n  A +1429\\.850 \\.\\. +[0-9.]+ mm[^\n]*\n.*\n  D +2208\\.90[23] \\.\\. +2299\\.830 mm")
# post: no derivative bound for this model here, so the deviation is sampled and says so; verify
# traces the whole job within the tolerance.
add_test(NAME cli.cable_robot_post_verify_hangprinter_square
         COMMAND sh -c "\"$0\" post -m \"$1\" \"$2\" -o \"$3\" --tolerance 0.01 && head -3 \"$3\" && \"$0\" verify -m \"$1\" \"$3\" --against \"$2\""
                 ${PKM} ${HANGPRINTER} ${CR_SQUARE} ${CR_OUT}/hangprinter-square-joints.ngc)
set_tests_properties(cli.cable_robot_post_verify_hangprinter_square PROPERTIES PASS_REGULAR_EXPRESSION
  "hangprinter-square-joints\\.ngc: [0-9]+ blocks for 5 moves, largest sampled deviation 0\\.0[01][0-9]* mm[^\n]*\n.*\\(tolerance +0\\.010000 mm. sampled deviation [^\n]*\n.*job traced 1900\\.000 of 1900\\.000 mm, deviation max 0\\.00[0-9]* mm")
if(EXISTS ${CR_HELLO})
  add_test(NAME cli.cable_robot_post_verify_maslow_real_job
           COMMAND sh -c "\"$0\" post -m \"$1\" \"$2\" --origin 1361.9 983 0 -o \"$3\" --tolerance 0.01 && \"$0\" verify -m \"$1\" \"$3\" --against \"$2\" --origin 1361.9 983 0"
                   ${PKM} ${MASLOW4} ${CR_HELLO} ${CR_OUT}/maslow-hello-joints.ngc)
  set_tests_properties(cli.cable_robot_post_verify_maslow_real_job PROPERTIES PASS_REGULAR_EXPRESSION
    "largest sampled deviation 0\\.0[01][0-9]* mm.*job traced 1411\\.573 of 1411\\.573 mm")
endif()
# workspace: the tensions, not the envelope, bound most of the Hangprinter's.
add_test(NAME cli.cable_robot_workspace_hangprinter
         COMMAND ${PKM} workspace -m ${HANGPRINTER} --resolution 100)
set_tests_properties(cli.cable_robot_workspace_hangprinter PROPERTIES PASS_REGULAR_EXPRESSION
  "limited by \\(outside and boundary cells\\): [^\n]*tension [0-9]+")

# The pages: the cables' names, limits and tensions at home, and each drawn moment's tensions
# (the first moment is home).
add_test(NAME cli.cable_robot_view_hangprinter_tensions
         COMMAND sh -c "\"$0\" post -m \"$1\" \"$2\" -o \"$3\" --tolerance 0.01 >/dev/null && \"$0\" view -m \"$1\" \"$3\" --html \"$4\" >/dev/null && grep -o '\"cables\":{[^}]*}' \"$4\" && grep -c '\"tensions\":{\"N\"' \"$4\""
                 ${PKM} ${HANGPRINTER} ${CR_SQUARE} ${CR_OUT}/view-joints.ngc ${CR_OUT}/view.html)
set_tests_properties(cli.cable_robot_view_hangprinter_tensions PROPERTIES PASS_REGULAR_EXPRESSION
  "^\"cables\":\\{\"home_N\":\\[39\\.6545,37\\.5787,30\\.2545,17\\.8454\\],\"limits\":\"\\[0, 70\\] N\",\"names\":\\[\"A\",\"B\",\"C\",\"D\"\\]\\}\n[1-9][0-9]*\n$")
add_test(NAME cli.cable_robot_plan_page_tensions
         COMMAND sh -c "\"$0\" plan -m \"$1\" \"$2\" --html \"$3\" >/dev/null && grep -o '\"tensions\":{\"N\":\\[[^]]*\\],\"held\":[a-z]*}' \"$3\" | head -1"
                 ${PKM} ${HANGPRINTER} ${CR_SQUARE} ${CR_OUT}/plan.html)
set_tests_properties(cli.cable_robot_plan_page_tensions PROPERTIES PASS_REGULAR_EXPRESSION
  "^\"tensions\":\\{\"N\":\\[39\\.6545,37\\.5787,30\\.2545,17\\.8454\\],\"held\":true\\}\n$")

# home: no switches on either; --at-home sets each joint to its value at home, read by rs274.
add_test(NAME cli.cable_robot_home_hangprinter_at_home
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" --at-home && rs274 -g \"$2\" >/dev/null 2>&1 && grep '^G10' \"$2\""
                 ${PKM} ${HANGPRINTER} ${CR_OUT}/hangprinter-home.ngc)
set_tests_properties(cli.cable_robot_home_hangprinter_at_home PROPERTIES RESOURCE_LOCK rs274
  PASS_REGULAR_EXPRESSION "hangprinter-home\\.ngc: sets A 1616\\.341 mm, B 1830\\.317 mm, C 1587\\.401 mm, D 2299\\.830 mm, the joints at home x 0\\.000 y 0\\.000 z 0\\.000 mm\nG10 L20 P1 X1616\\.34053 Y1830\\.31749 Z1587\\.40148 A2299\\.83000\n$")
add_test(NAME cli.cable_robot_home_maslow_at_home
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" --at-home >/dev/null && rs274 -g \"$2\" >/dev/null 2>&1 && grep -e '^G10' -e 'at home: tl' \"$2\""
                 ${PKM} ${MASLOW4} ${CR_OUT}/maslow-home.ngc)
set_tests_properties(cli.cable_robot_home_maslow_at_home PROPERTIES RESOURCE_LOCK rs274
  PASS_REGULAR_EXPRESSION "^\\(at home: tl 1661\\.593 mm\\)\nG10 L20 P1 X1661\\.59346 Y1638\\.25143 A1637\\.03452 B1662\\.60142\n$")
pkm_cli_refuses(cable_robot_home_without_switches
  "hangprinter-v4\\.toml: the machine file has no \\[homing\\] table \\(docs/homing\\.md\\): without switches, put the effector at home and use --at-home, or measure the joints \\(--measured\\)"
  NO_FILE ${CR_OUT}/never.ngc
  home -m ${HANGPRINTER} -o ${CR_OUT}/never.ngc)
pkm_cli_refuses(cable_robot_home_at_home_and_measured "--measured excludes --at-home"
  NO_FILE ${CR_OUT}/never.ngc
  home -m ${HANGPRINTER} -o ${CR_OUT}/never.ngc --at-home --measured 1 2 3 4)
