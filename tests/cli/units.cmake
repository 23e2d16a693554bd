# Units a user can act on (issue 25, item 6): on a machine file in inches every length typed on
# the command line is in inches, as ik, fk and check print them, and every command prints inches.
# Before, --origin 0 0 20 on LinuxCNC's inch hexapod put an inch job 20 mm above the base plane.
set(INCH_HEXAPOD ${MACHINES}/linuxcnc-hexapod-sim.toml)
set(INCH_JOB ${CLI_DATA}/inch-square-at-z0.ngc)

# --origin 0 0 20 is the hexapod's home height, 20 in: check certifies the job there...
add_test(NAME cli.units.check_origin_in_inches
         COMMAND ${PKM} check -m ${INCH_HEXAPOD} ${INCH_JOB} --origin 0 0 20)
set_tests_properties(cli.units.check_origin_in_inches PROPERTIES PASS_REGULAR_EXPRESSION
  "certified: .*inch-square-at-z0\\.ngc on LinuxCNC hexapod-sim \\(genhexkins, inch\\): all 7 moves proven")
# ... plan prints the legs, path and speeds in inches, as check does ...
add_test(NAME cli.units.plan_origin_and_joints_in_inches
         COMMAND ${PKM} plan -m ${INCH_HEXAPOD} ${INCH_JOB} --origin 0 0 20)
set_tests_properties(cli.units.plan_origin_and_joints_in_inches PROPERTIES PASS_REGULAR_EXPRESSION
  "path 5\\.598 in\n.*\n  leg0 +2[0-9]\\.[0-9]+ \\.\\. +[23][0-9]\\.[0-9]+ in, peak +[0-9.]+ of 20\\.0 in/s")
# ... and post and verify take the tolerance in inches and say the deviation in inches.
add_test(NAME cli.units.post_and_verify_in_inches
         COMMAND sh -c "\"$0\" post -m \"$1\" \"$2\" -o \"$3\" --origin 0 0 20 --tolerance 0.0005 && \"$0\" verify -m \"$1\" \"$3\" --against \"$2\" --origin 0 0 20"
                 ${PKM} ${INCH_HEXAPOD} ${INCH_JOB} ${CLI_OUT}/inch-square-joints.ngc)
set_tests_properties(cli.units.post_and_verify_in_inches PROPERTIES PASS_REGULAR_EXPRESSION
  "deviation bounded by 0\\.000[45][0-9]* in \\(line [0-9]+\\), tolerance 0\\.000500 in\n.*job traced 5\\.600 of 5\\.600 in, deviation max 0\\.000[0-4][0-9]* in .* tolerance 0\\.0005000 in")
# 20 mm typed as inches (0.787) is below the base's reach: refused, the boxes and the --origin
# that would centre the job in inches (it suggested "--origin -13 -20 477", mm, on this machine).
pkm_cli_refuses(units_origin_hint_in_inches
  "hint: the job spans x 0\\.000\\.\\.1\\.000 y 0\\.000\\.\\.1\\.000 z 0\\.737\\.\\.1\\.287 in. the machine reaches x -7\\.932\\.\\.7\\.932 y -9\\.068\\.\\.8\\.515 z 9\\.547\\.\\.28\\.480 in \\(along lines through home\\). --origin -0\\.50 -0\\.78 18\\.79 would centre it"
  plan -m ${INCH_HEXAPOD} ${INCH_JOB} --origin 0 0 0.787)
# --start is a pose in inches too.
add_test(NAME cli.units.plan_start_in_inches
         COMMAND ${PKM} plan -m ${INCH_HEXAPOD} ${INCH_JOB} --origin 0 0 20 --start 0 0 22)
set_tests_properties(cli.units.plan_start_in_inches PROPERTIES PASS_REGULAR_EXPRESSION
  "path 6\\.598 in")
# The workspace's resolution is typed, and its boxes printed, in inches.
add_test(NAME cli.units.workspace_in_inches
         COMMAND ${PKM} workspace -m ${INCH_HEXAPOD} --resolution 1)
set_tests_properties(cli.units.workspace_in_inches PROPERTIES PASS_REGULAR_EXPRESSION
  "workspace at 1 in resolution\nvolume: [0-9.]+ \\.\\. [0-9.]+ in\\^3 .*\nextent: x -[0-9]\\.[0-9]+\\.\\.[0-9]\\.[0-9]+ y [-0-9.]+ z [-0-9.]+ in\n")

# "F1500.0 lowered to F271.3 by joint right" on a plotter whose joint runs at a fraction of its
# 150 mm/s: the cause was the acceleration of a G64 corner blend. The first square of the real
# corpus' vitruvianMan drawing on the Makelangelo, its joints' max_acceleration lowered from 1500
# to 1000 mm/s^2 so that the joint's bend and not the tool's own acceleration holds the corner,
# says so, with the numbers of both limits.
file(READ ${MACHINES}/makelangelo.toml SLOW_MAKELANGELO)
string(REPLACE "max_acceleration = 1500.0" "max_acceleration = 1000.0" SLOW_MAKELANGELO
       "${SLOW_MAKELANGELO}")
file(WRITE ${CLI_OUT}/makelangelo-slow-joints.toml "${SLOW_MAKELANGELO}")
add_test(NAME cli.units.plan_names_the_corner_blend
         COMMAND ${PKM} plan -m ${CLI_OUT}/makelangelo-slow-joints.toml
                 ${CLI_DATA}/vitruvian-first-square.ngc)
set_tests_properties(cli.units.plan_names_the_corner_blend PROPERTIES PASS_REGULAR_EXPRESSION
  "feed lowered by joint acceleration on 3 moves, 3 of them G64 corner blends: G64 P with a larger tolerance rounds them wider and faster \\(first at line 8, joint right\\)\n    line 8: F1500\\.0 lowered to F349\\.4 at the G64 corner blend after line 7 \\(turn 90\\.0 deg, radius 0\\.0341 mm\\): joint right's acceleration would be 18417\\.3 mm/s\\^2 at F1500\\.0, over the 999\\.0 mm/s\\^2 it may use on a bend \\(99\\.9 % of max_acceleration 1000\\.0\\). the tool's own v\\^2/r allows F384\\.0 \\(within 1200\\.0 mm/s\\^2, 100\\.0 % of max_acceleration 1200\\.0\\)")

# A pose with too few numbers says the unit it is read in (it said "(mm, deg)" on an inch machine).
pkm_cli_refuses(units_pose_says_inches
  "this machine takes the pose as x y z a b c \\(in, deg\\). got 2 numbers"
  ik -m ${INCH_HEXAPOD} 1 2)

# check refuses the job placed by 20 mm typed as inches with the same hint as plan and post: where
# it would fit, in inches (it said only which leg passes its min).
pkm_cli_refuses(units_check_hint_in_inches
  "hint: the job spans x 0\\.000\\.\\.1\\.000 y 0\\.000\\.\\.1\\.000 z 0\\.737\\.\\.1\\.287 in. .*--origin -0\\.50 -0\\.78 18\\.79 would centre it"
  check -m ${INCH_HEXAPOD} ${INCH_JOB} --origin 0 0 0.787)

# The tool table of an inch machine is read in inches unless --tool-table-units says otherwise, as
# LinuxCNC reads it: post places the job with the 0.5 in tool, and verify agrees only in inches.
add_test(NAME cli.units.tool_table_in_the_machines_units
         COMMAND sh -c "\"$0\" post -m \"$1\" \"$2\" -o \"$4\" --origin 0 0 20 --tool-table \"$3\" && \"$0\" verify -m \"$1\" \"$4\" --against \"$2\" --origin 0 0 20 --tool-table \"$3\" --tool-table-units inch && ! \"$0\" verify -m \"$1\" \"$4\" --against \"$2\" --origin 0 0 20 --tool-table \"$3\" --tool-table-units mm"
                 ${PKM} ${INCH_HEXAPOD} ${CLI_DATA}/tool-length-job.ngc ${CLI_DATA}/inch-tools.tbl
                 ${CLI_OUT}/inch-machine-tool-joints.ngc)
