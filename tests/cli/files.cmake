# Files that cannot be opened: the file and the reason, without a line or column it does not have
# (they read "job.ngc:0:0: cannot open the program" before).
set(NOWHERE ${CLI_OUT}/no-such-file)
pkm_cli_refuses(program_missing "no-such-file\\.ngc: cannot open \\(No such file or directory\\)$"
                gcode --canon ${NOWHERE}.ngc)
pkm_cli_refuses(program_is_a_directory "cli-out: cannot open \\(it is a directory\\)$"
                plan ${CLI_OUT} -o ${CLI_OUT}/never.csv)
pkm_cli_refuses(tool_table_missing
                "no-such-file\\.tbl: the tool table: cannot open \\(No such file or directory\\)$"
                gcode --canon --tool-table ${NOWHERE}.tbl ${PROJECT_SOURCE_DIR}/examples/jobs/sphere.ngc)
pkm_cli_refuses(machine_missing "no-such-file\\.toml: cannot open \\(No such file or directory\\)$"
                check -m ${NOWHERE}.toml)
pkm_cli_refuses(joint_program_missing
                "no-such-file\\.ngc: cannot open \\(No such file or directory\\)$"
                verify ${NOWHERE}.ngc --against ${PROJECT_SOURCE_DIR}/examples/jobs/sphere.ngc)
# A machine file or an INI that is a device is refused at once, not read for gigabytes.
pkm_cli_refuses(machine_is_a_device "/dev/zero: cannot open \\(it is a device, not a regular file\\)$"
                check -m /dev/zero)
pkm_cli_refuses(linuxcnc_ini_is_a_device "/dev/zero: cannot open \\(it is a device, not a regular file\\)"
                import linuxcnc /dev/zero)
# What a command writes to its standard output is checked: on a full disk (/dev/full) the
# command fails, naming the reason, instead of exiting 0 with a truncated output.
add_test(NAME cli.refuses.canon_to_a_full_disk
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/expect-refusal
                 "writing the standard output failed \\(No space left on device\\)"
                 /bin/sh -c "exec \"$0\" gcode --canon \"$1\" > /dev/full" $<TARGET_FILE:pkm>
                 ${PROJECT_SOURCE_DIR}/examples/jobs/sphere.ngc)
add_test(NAME cli.refuses.import_linuxcnc_to_a_full_disk
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/expect-refusal
                 "writing the standard output failed \\(No space left on device\\)"
                 /bin/sh -c "exec \"$0\" import linuxcnc \"$1\" > /dev/full" $<TARGET_FILE:pkm>
                 ${PKM_LINUXCNC_SAMPLES}/sim/axis/ldelta.ini)
# A machine that cannot move (legs parallel at home: base and platform joints on one circle) is
# refused at load by every command, at its home, with its conditioning and the motion no joint
# makes.
foreach(command check plan)
  pkm_cli_refuses(${command}_singular_machine
    "parallel-hexapod\\.toml:[0-9]+:cartesian\\.home: the machine is singular at home: the relative smallest singular value of its jacobian is 0, below 1e-06. the tool's motion c 1\\.000 \\(mm, deg\\) moves no joint"
    ${command} -m ${CLI_DATA}/parallel-hexapod.toml ${CLI_DATA}/hektor-job.ngc)
endforeach()
