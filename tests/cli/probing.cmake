# A probing move (docs/post.md, "Probing"), the same job through check, plan and post on Hektor:
# check proves the probe to its end, plan times it at its F (the 14.142 mm probe at 100 mm/min
# alone is 8.485 s; with the 10 mm rapid from home before it, 8.8 s), and post refuses it at the
# G38.2's column, writing nothing. plan used to refuse it ("a feed move with no feed rate") and
# post without its file or line.
set(PROBE_JOB ${CLI_OUT}/probe.ngc)
file(WRITE ${PROBE_JOB} "G21 G90\nG0 X40 Y-50\nG91 G38.2 X10 Y-10 F100\nM2\n")
add_test(NAME cli.check_proves_a_probe_to_its_end
         COMMAND ${PKM} check -m ${MACHINES}/hektor.toml ${PROBE_JOB})
set_tests_properties(cli.check_proves_a_probe_to_its_end PROPERTIES PASS_REGULAR_EXPRESSION
  "certified: .*probe\\.ngc on Hektor .*: all 2 moves proven")
add_test(NAME cli.plan_times_a_probe_at_its_feed
         COMMAND ${PKM} plan -m ${MACHINES}/hektor.toml ${PROBE_JOB} -o ${CLI_OUT}/probe.csv)
set_tests_properties(cli.plan_times_a_probe_at_its_feed PROPERTIES PASS_REGULAR_EXPRESSION
  "8\\.8[0-9]* s of machine motion, path 24\\.142 mm on Hektor")
pkm_cli_refuses(post_refuses_a_probe_at_its_column
  "probe\\.ngc:3:5: a probing move \\(G38\\.2-G38\\.5\\) cannot go into a joint program: .* run the job on a controller that has the machine's kinematics \\(pkm export linuxcnc\\)"
  NO_FILE ${CLI_OUT}/probe-joints.ngc
  post -m ${MACHINES}/hektor.toml ${PROBE_JOB} -o ${CLI_OUT}/probe-joints.ngc)
