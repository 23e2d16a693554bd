# pkm check -m MACHINE JOB, the certified check (docs/certified-check.md): the example jobs proven
# on their machines; a job whose joint-limit crossing falls between plan's samples passes plan and
# is refused by check at its move; a tilt past max_joint_angle named at the hand-computed angle.
set(BETWEEN_SAMPLES ${CLI_DATA}/between-samples.ngc)
add_test(NAME cli.check_job_sphere_is_certified
         COMMAND ${PKM} check -m ${MACHINES}/hexapod-bit.toml ${PROJECT_SOURCE_DIR}/examples/jobs/sphere.ngc)
set_tests_properties(cli.check_job_sphere_is_certified PROPERTIES PASS_REGULAR_EXPRESSION
  "certified: .*sphere\\.ngc on Hexapod of the interpolation paper \\(BIT\\): all 157 moves proven")
add_test(NAME cli.check_job_hyperboloid_is_certified
         COMMAND ${PKM} check -m ${MACHINES}/hexapod-bit-200.toml ${PROJECT_SOURCE_DIR}/examples/jobs/hyperboloid.ngc --json)
set_tests_properties(cli.check_job_hyperboloid_is_certified PROPERTIES PASS_REGULAR_EXPRESSION
  "\"certified\": true,.*\"moves\": 232,.*\"undecided\": 0")
# plan writes every sample and checks each (leg1 stays at 600.000 mm): it passes.
add_test(NAME cli.plan_passes_the_job_between_samples
         COMMAND ${PKM} plan -m ${MACHINES}/hexapod-bit.toml ${BETWEEN_SAMPLES} -o ${CLI_OUT}/between-samples.csv)
set_tests_properties(cli.plan_passes_the_job_between_samples PROPERTIES PASS_REGULAR_EXPRESSION
  "leg1 +600\\.000 \\.\\.")
pkm_cli_refuses(check_job_crossing_between_samples
  "between-samples\\.ngc:4: move 2 violated: at 51\\.2326[0-9]* % of the move: pose x 200\\.361 y 153\\.887 z 570\\.000 mm .*joint 'leg1' = 600\\.000 mm passes its min 600\\.000 mm .*the farthest past it: 9\\.[0-9]*e-09 mm at 51\\.245[0-9]* % of the move \\(2 of 3 moves proven, 1 violated, 0 undecided\\)"
  check -m ${MACHINES}/hexapod-bit.toml ${BETWEEN_SAMPLES})
pkm_cli_refuses(check_job_tilt_past_the_joint_angle
  "tilt-28\\.ngc:3: move 2 violated: at 85\\.65195[0-9]* % of the move: pose .* a 25\\.417 b 0\\.000 c 0\\.000 deg: joint_angle: the platform joint of 'leg5' is at 30\\.000 deg from its axis. max_joint_angle is 30\\.000 deg"
  check -m ${CLI_DATA}/tilting-hexapod.toml ${CLI_DATA}/tilt-28.ngc)
pkm_cli_refuses(ik_past_the_joint_angle
  "a 28\\.000 b 0\\.000 c 0\\.000 deg: joint_angle: the platform joint of 'leg4' is at 30\\.325 deg from its axis. max_joint_angle is 30\\.000 deg"
  ik -m ${CLI_DATA}/tilting-hexapod.toml 0 0 500 28 0 0)
pkm_cli_refuses(check_job_undecided_without_a_bound
  "move 1 undecided: no bound on the derivatives of this kinematics model \\(formula\\)"
  check -m ${MACHINES}/mach3-formula.toml ${CLI_DATA}/hektor-job.ngc)
pkm_cli_refuses(check_origin_without_a_job "--origin is only read with a JOB"
  check -m ${MACHINES}/hexapod-bit.toml --origin 1 2)
# The machine summary shows the leg limits the file sets.
add_test(NAME cli.check_shows_leg_limits COMMAND ${PKM} check -m ${CLI_DATA}/tilting-hexapod.toml)
set_tests_properties(cli.check_shows_leg_limits PROPERTIES PASS_REGULAR_EXPRESSION
  "  leg limits: max_joint_angle 30 deg \\(inner\\), 30 deg \\(platform\\). leg_diameter 40 mm\n")
add_test(NAME cli.check_json_leg_limits
         COMMAND ${PKM} check -m ${CLI_DATA}/tilting-hexapod.toml --json)
set_tests_properties(cli.check_json_leg_limits PROPERTIES PASS_REGULAR_EXPRESSION
  "\"leg_limits\": \\{\n *\"leg_diameter\": 40\\.0,\n *\"max_joint_angle_deg\": \\[\n *30\\.0,\n *30\\.0\n")
# Cable plotters as built (docs/cable-bounds.md): hektor-pulleys' job proven; a gondola's left
# cable dipping 1e-8 N below tension_limits' min over 0.23 mm between post's samples: post passes
# it, check refuses it where the dip starts; sagging cables undecided, saying why.
set(TENSION_DIP ${CLI_DATA}/tension-between-samples.ngc)
add_test(NAME cli.check_job_on_pulleys_is_certified
         COMMAND ${PKM} check -m ${MACHINES}/hektor-pulleys.toml ${CLI_DATA}/hektor-job.ngc)
set_tests_properties(cli.check_job_on_pulleys_is_certified PROPERTIES PASS_REGULAR_EXPRESSION
  "certified: .*hektor-job\\.ngc on Hektor with GT2 pulleys \\(d = 100\\): all 4 moves proven")
add_test(NAME cli.post_passes_the_tension_dip_between_samples
         COMMAND ${PKM} post -m ${CLI_DATA}/makelangelo-straight.toml ${TENSION_DIP}
                 -o ${CLI_OUT}/tension-between-samples.ngc)
set_tests_properties(cli.post_passes_the_tension_dip_between_samples PROPERTIES
  PASS_REGULAR_EXPRESSION "blocks for 2 moves")
pkm_cli_refuses(check_job_tension_dip_between_samples
  "tension-between-samples\\.ngc:6: move 2 violated: at 50\\.4377[0-9]* % of the move: pose x 237\\.840 y 0\\.113 mm: tension: the left cable would go slack: .*the farthest past it: 9\\.9[0-9]*e-09 N at 51\\.03[0-9]* % of the move \\(1 of 2 moves proven, 1 violated, 0 undecided\\)"
  check -m ${CLI_DATA}/makelangelo-straight.toml ${TENSION_DIP})
pkm_cli_refuses(check_job_sagging_cables_undecided
  "move 1 undecided: no bound on the balance of cables that sag \\(cable_density > 0\\)"
  check -m ${MACHINES}/makelangelo.toml ${CLI_DATA}/hektor-job.ngc)
# A plotter's pen (docs/post.md, "The pen channel"): the LinuxCNC polargraph's guilloche draws at
# Z65; on pen-plotter.toml (down below 0) the pen never goes down. plan, post and check finish
# (exit 0: EXIT0 follows) and warn, naming the job's Z and the [tool] setting that draws it.
set(GUILLOCHE ${CLI_DATA}/polargraph-guilloche-z65.ngc)
set(PEN_NEVER_DOWN "pkm: warning: [^\n]*polargraph-guilloche-z65\\.ngc:6: the pen never goes down: the job's moves in X and Y run at Z 0 and 65 mm \\(feed\\), its moves in Z alone to Z 90 mm; the pen draws below Z 0 mm \\(\\[tool\\] down_below\\); \\[tool\\] down_above = 32\\.5 would draw at Z 65 and lift the pen at Z 0\n.*EXIT0")
foreach(command post plan check)
  set(output)
  if(command STREQUAL "post")
    set(output -o ${CLI_OUT}/guilloche-joints.ngc)
  elseif(command STREQUAL "plan")
    set(output -o ${CLI_OUT}/guilloche-samples.csv)
  endif()
  add_test(NAME cli.${command}_warns_when_the_pen_never_goes_down
           COMMAND sh -c "\"$@\" 2>&1 && echo EXIT0" sh ${PKM} ${command}
                   -m ${MACHINES}/pen-plotter.toml ${GUILLOCHE} --origin 700 -900 ${output})
  set_tests_properties(cli.${command}_warns_when_the_pen_never_goes_down PROPERTIES
    PASS_REGULAR_EXPRESSION "${PEN_NEVER_DOWN}")
endforeach()
# A hexapod's path through its base plane leaves home's assembly mode (issue 25): LinuxCNC's
# hexapod sample (legs 20..40 in) refuses the drilling cycle at its line, with the leg and how far
# past the plane; ik refuses home's mirror image below the base.
set(SAMPLE_HEXAPOD ${CLI_DATA}/linuxcnc-hexapod-sample-legs-20-40.toml)
pkm_cli_refuses(check_job_through_the_hexapods_base_plane
  "drill-through-the-base-plane\\.ngc:6: move [0-9]+ violated: .* pose x 0\\.9000 y -0\\.4500 z 0\\.0000 in .*another assembly mode than home's: the platform joint of 'leg[0-5]' is 0\\.0000 in past the base joints' plane.*the farthest past it: 0\\.063 in at 100\\.0* % of the move"
  check -m ${SAMPLE_HEXAPOD} ${CLI_DATA}/drill-through-the-base-plane.ngc)
pkm_cli_refuses(ik_the_hexapods_mirror_image
  "the platform joint of 'leg0' is 20\\.0000 in past the base joints' plane, on the other side of it than at home"
  ik -m ${SAMPLE_HEXAPOD} 0 0 -20)
