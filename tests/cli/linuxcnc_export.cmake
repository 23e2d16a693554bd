# pkm export linuxcnc: what it refuses, each with a message a user can act on, and no directory
# left behind.
set(LCNC_NEVER ${CLI_OUT}/lcnc-never)
pkm_cli_refuses(export_linuxcnc_no_finite_reach
                "matrix-no-reach\\.toml: the machine's reach along x is not finite .*give \\[cartesian\\] min and max for x$"
                NO_FILE ${LCNC_NEVER}
                export linuxcnc -m ${CLI_DATA}/matrix-no-reach.toml -o ${LCNC_NEVER} --sim)
pkm_cli_refuses(export_linuxcnc_directory_in_use
                "data exists and is not empty: give another directory, or --force"
                export linuxcnc -m ${MACHINES}/hektor.toml -o ${CLI_DATA} --sim)
pkm_cli_refuses(export_linuxcnc_over_a_file "square\\.ngc exists and is not a directory$"
                export linuxcnc -m ${MACHINES}/hektor.toml -o ${CLI_DATA}/square.ngc)
pkm_cli_refuses(export_linuxcnc_under_a_file
                "cannot create the directory .*square\\.ngc/\\.config\\.tmp-[0-9]+: Not a directory$"
                export linuxcnc -m ${MACHINES}/hektor.toml -o ${CLI_DATA}/square.ngc/config)
pkm_cli_refuses(export_linuxcnc_needs_a_machine "--machine is required"
                export linuxcnc -o ${LCNC_NEVER})
pkm_cli_refuses(export_linuxcnc_needs_a_directory "--output is required"
                export linuxcnc -m ${MACHINES}/hektor.toml)
pkm_cli_refuses(export_linuxcnc_machine_missing
                "no-such-file\\.toml: cannot open \\(No such file or directory\\)$"
                export linuxcnc -m ${NOWHERE}.toml -o ${LCNC_NEVER})

# And what it writes: a directory with the INI naming pkmkins and the machine file beside it, the
# bound's verdict and its cost on the terminal.
set(LCNC_PEN ${CLI_OUT}/lcnc-pen)
add_test(NAME cli.export_linuxcnc_pen_plotter_sim
         COMMAND sh -c "rm -rf \"$1\" && out=$(\"$0\" export linuxcnc -m \"$2\" -o \"$1\" --sim) && printf '%s\\n' \"$out\" && printf '%s\\n' \"$out\" | grep -q 'joint-rate bound over the work envelope: proven' && printf '%s\\n' \"$out\" | grep -q 'X: 4732.3 mm/min = 78.9 % of max_feed 6000' && grep -qx 'KINEMATICS = pkmkins machine=pen-plotter.toml' \"$1/pen-plotter.ini\" && cmp -s \"$2\" \"$1/pen-plotter.toml\" && grep -q '^net pen-z axis.z.pos-cmd => pen-up.in1$' \"$1/pen-plotter.hal\" && test -f \"$1/sim.hal\" && ! test -e \"$1/hardware.hal\""
                 ${PKM} ${LCNC_PEN} ${MACHINES}/pen-plotter.toml)

# --force over an existing configuration, from the machine file inside it (as pkmkins' message
# says to): the INI records the file's SHA-256 as sha256sum computes it, a file of the user's is
# carried over and named, and nothing is left beside the directory.
set(LCNC_FORCE ${CLI_OUT}/lcnc-force)
add_test(NAME cli.export_linuxcnc_force_replaces_whole_and_keeps_user_files
         COMMAND sh -c "rm -rf \"$1\" && mkdir -p \"$1\" && \"$0\" export linuxcnc -m \"$2\" -o \"$1/cfg\" --sim >/dev/null && echo 'net mine' > \"$1/cfg/mine.hal\" && printf '# calibrated\\n' >> \"$1/cfg/pen-plotter.toml\" && out=$(\"$0\" export linuxcnc -m \"$1/cfg/pen-plotter.toml\" -o \"$1/cfg\" --sim --force) && printf '%s\\n' \"$out\" && printf '%s\\n' \"$out\" | grep -qx 'carried over from the configuration replaced (not written by pkm): mine.hal' && printf '%s\\n' \"$out\" | grep -q '^kept from the configuration replaced .*: pen-plotter.tbl, pen-plotter.var$' && grep -qx \"PKM_MACHINE_SHA256 = $(sha256sum \"$1/cfg/pen-plotter.toml\" | cut -d' ' -f1)\" \"$1/cfg/pen-plotter.ini\" && test \"$(cat \"$1/cfg/mine.hal\")\" = 'net mine' && test \"$(ls -A \"$1\")\" = cfg"
                 ${PKM} ${LCNC_FORCE} ${MACHINES}/pen-plotter.toml)
