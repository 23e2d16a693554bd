# pkm home: the homing program of a machine with switches and the set-position block for readings
# measured by hand, read by LinuxCNC's rs274 (linuxcnc and grbl dialects: G38.2, G10 L20 P1);
# Mach3's G31 is no LinuxCNC word, so its program is checked by its text. Refusals write nothing.
set(HOME_OUT ${CLI_OUT}/home)
file(MAKE_DIRECTORY ${HOME_OUT})
foreach(machine wall-plotter hektor)
  add_test(NAME cli.home_${machine}_linuxcnc_read_by_rs274
           COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" && rs274 -g \"$2\" >/dev/null"
                   ${PKM} ${MACHINES}/${machine}.toml ${HOME_OUT}/${machine}-linuxcnc.ngc)
endforeach()
add_test(NAME cli.home_wall_plotter_grbl_read_by_rs274
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" --dialect grbl && rs274 -g \"$2\" >/dev/null && test -z \"$(awk 'length > 80' \"$2\")\""
                 ${PKM} ${MACHINES}/wall-plotter.toml ${HOME_OUT}/wall-plotter-grbl.ngc)
add_test(NAME cli.home_measured_read_by_rs274
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" --measured 1025.91423 1025.91423 && rs274 -g \"$2\" >/dev/null"
                 ${PKM} ${MACHINES}/wall-plotter.toml ${HOME_OUT}/wall-plotter-set.ngc)
set_tests_properties(cli.home_wall-plotter_linuxcnc_read_by_rs274
                     cli.home_hektor_linuxcnc_read_by_rs274 cli.home_wall_plotter_grbl_read_by_rs274
                     cli.home_measured_read_by_rs274 PROPERTIES RESOURCE_LOCK rs274)
# rs274 follows the program: its simulated probe trips at the target and backs off 0.254 mm
# towards the start, so the joint reads home_switch there plus 0.254 (160.254 mm), backed off
# 10 mm (170.254), paid out 50 mm (220.254) while the right cord homes; the end is home's
# joints, sqrt(750^2 + 700^2) = 1025.9142 mm each.
add_test(NAME cli.home_wall_plotter_rs274_positions
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" >/dev/null && rs274 -g \"$2\" 2>/dev/null | grep STRAIGHT_FEED | sed 's/^.*STRAIGHT_FEED//' | tr '\\n' ' '"
                 ${PKM} ${MACHINES}/wall-plotter.toml ${HOME_OUT}/wall-plotter-positions.ngc)
set_tests_properties(cli.home_wall_plotter_rs274_positions PROPERTIES RESOURCE_LOCK rs274
  PASS_REGULAR_EXPRESSION "\\(0\\.0000, 50\\.0000, [^)]*\\) \\(170\\.2540, 50\\.0000, [^)]*\\) \\(220\\.2540, 50\\.0000, [^)]*\\) \\(220\\.2540, 170\\.2540, [^)]*\\) \\(1025\\.9142, 1025\\.9142, [^)]*\\) *\n?$")
# What the terminal says: the joints in order, where each is set (LinuxCNC: the trip point;
# grbl: where it stopped, (300 / 60)^2 / (2 * 1000) = 0.0125 mm past), where it ends.
add_test(NAME cli.home_wall_plotter_summary
         COMMAND ${PKM} home -m ${MACHINES}/wall-plotter.toml -o ${HOME_OUT}/wall-plotter-summary.ngc)
set_tests_properties(cli.home_wall_plotter_summary PROPERTIES PASS_REGULAR_EXPRESSION
  "wall-plotter-summary\\.ngc: homes left, right on their switches \\(each set at its probe's trip point\\), then moves to home x 750\\.000 y -700\\.000 mm")
add_test(NAME cli.home_wall_plotter_grbl_summary
         COMMAND ${PKM} home -m ${MACHINES}/wall-plotter.toml --dialect grbl -o ${HOME_OUT}/wall-plotter-grbl-summary.ngc)
set_tests_properties(cli.home_wall_plotter_grbl_summary PROPERTIES PASS_REGULAR_EXPRESSION
  "homes left, right on their switches \\(each set where it stopped, past its switch by up to left 0\\.0125 mm, right 0\\.0125 mm at max_acceleration\\)")
add_test(NAME cli.home_mach3_probes_with_g31
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" --dialect mach3 >/dev/null && grep -c -e '^G91 G31 [XY]-19[49]0\\.0000 F300$' -e '^G92 [XY]160\\.0000$' \"$2\""
                 ${PKM} ${MACHINES}/wall-plotter.toml ${HOME_OUT}/wall-plotter-mach3.ngc)
set_tests_properties(cli.home_mach3_probes_with_g31 PROPERTIES PASS_REGULAR_EXPRESSION "^4\n$")

set(HOME_NEVER ${HOME_OUT}/never.ngc)
pkm_cli_refuses(home_grbl_letters_a_b
                "hektor\\.toml: dialect grbl has no axis A \\(joint 'left'\\): use --dialect linuxcnc or grblhal, or change the joints' axis letters"
                NO_FILE ${HOME_NEVER}
                home -m ${MACHINES}/hektor.toml -o ${HOME_NEVER} --dialect grbl)
pkm_cli_refuses(home_mach3_rotary_probe
                "Mach3's probe \\(G31\\) moves no rotary axis, and joint 'left' is A"
                NO_FILE ${HOME_NEVER}
                home -m ${MACHINES}/hektor.toml -o ${HOME_NEVER} --dialect mach3)
pkm_cli_refuses(home_without_homing_table
                "maslow\\.toml: the machine file has no \\[homing\\] table \\(docs/homing\\.md\\)"
                NO_FILE ${HOME_NEVER}
                home -m ${MACHINES}/maslow.toml -o ${HOME_NEVER})
pkm_cli_refuses(home_measured_count
                "--measured takes 2 readings, one per joint of the mechanism \\(left right\\), not 3"
                NO_FILE ${HOME_NEVER}
                home -m ${MACHINES}/maslow.toml -o ${HOME_NEVER} --measured 1800 1800 5)
pkm_cli_refuses(home_measured_past_max
                "no pose has the readings left 500\\.000 mm, right 2500\\.000 mm on Wall plotter 1500: joint 'right' = 2500\\.000 mm passes its max 2100\\.000 mm"
                NO_FILE ${HOME_NEVER}
                home -m ${MACHINES}/wall-plotter.toml -o ${HOME_NEVER} --measured 500 2500)
pkm_cli_refuses(home_measured_nan "--measured: 'nan' is not a finite number"
                NO_FILE ${HOME_NEVER}
                home -m ${MACHINES}/wall-plotter.toml -o ${HOME_NEVER} --measured nan 700)
# grblHAL zeroes as grbl does, with its 4 decimals: both cords at home, sqrt(750^2 + 700^2).
add_test(NAME cli.home_wall_plotter_grblhal_measured
         COMMAND sh -c "\"$0\" home -m \"$1\" -o \"$2\" --dialect grblhal --measured 1025.91423 1025.91423 >/dev/null && grep -c '^G10 L20 P1 X1025\\.9142 Y1025\\.9142$' \"$2\""
                 ${PKM} ${MACHINES}/wall-plotter.toml ${HOME_OUT}/wall-plotter-grblhal-set.ngc)
set_tests_properties(cli.home_wall_plotter_grblhal_measured PROPERTIES PASS_REGULAR_EXPRESSION "^1\n$")
pkm_cli_refuses(home_bad_homing_table
                "bad-homing\\.toml:[0-9]+:homing\\.slack: paying out joint 'left' by 2000\\.000 mm before joint 'right' homes takes it past its max"
                NO_FILE ${HOME_NEVER}
                home -m ${CLI_DATA}/bad-homing.toml -o ${HOME_NEVER})
pkm_cli_refuses(home_over_its_machine_file "the output is the input file"
                home -m ${MACHINES}/wall-plotter.toml -o ${MACHINES}/wall-plotter.toml)
