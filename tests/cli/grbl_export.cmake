# pkm export grbl|grblhal: the $ settings of the example wall plotter (80 steps/mm, 150 mm/s =
# 9000 mm/min, 1000 mm/s^2, cords 150..2100 mm: 1950 mm), written atomically with -o; the
# refusals write nothing.
set(GRBL_OUT ${CLI_OUT}/grbl)
file(MAKE_DIRECTORY ${GRBL_OUT})
add_test(NAME cli.export_grbl_wall_plotter
         COMMAND sh -c "\"$0\" export grbl -m \"$1\" -o \"$2\" && grep -c -e '^\\$100=80\\.000 (X = joint left: steps/mm)$' -e '^\\$111=9000\\.000 (Y = joint right: max rate, mm/min)$' -e '^\\$120=1000\\.000 ' -e '^\\$131=1950\\.000 ' -e '^\\$11=0\\.010 ' -e '^\\$13=0 ' -e '^\\$1=255 ' \"$2\" && wc -l < \"$2\""
                 ${PKM} ${MACHINES}/wall-plotter.toml ${GRBL_OUT}/wall-plotter.settings)
set_tests_properties(cli.export_grbl_wall_plotter PROPERTIES PASS_REGULAR_EXPRESSION
  "wall-plotter\\.settings: 11 grbl settings for Wall plotter 1500: send it line by line, waiting for each ok\n7\n11\n$")
add_test(NAME cli.export_grbl_to_standard_output
         COMMAND ${PKM} export grbl -m ${MACHINES}/triaglide.toml)
set_tests_properties(cli.export_grbl_to_standard_output PROPERTIES PASS_REGULAR_EXPRESSION
  "\\$102=80\\.000 \\(Z = joint rail3: steps/mm\\)\n.*\\$112=15000\\.000 \\(Z = joint rail3: max rate, mm/min\\)\n.*\\$132=1200\\.000 ")
set(GRBL_NEVER ${GRBL_OUT}/never.settings)
pkm_cli_refuses(export_grbl_without_controller
                "maslow\\.toml: has no \\[controller\\] table. pkm export grbl needs one"
                NO_FILE ${GRBL_NEVER}
                export grbl -m ${MACHINES}/maslow.toml -o ${GRBL_NEVER})
pkm_cli_refuses(export_grblhal_of_a_grbl_machine
                "wall-plotter\\.toml: its \\[controller\\] kind is \"grbl\": use pkm export grbl"
                NO_FILE ${GRBL_NEVER}
                export grblhal -m ${MACHINES}/wall-plotter.toml -o ${GRBL_NEVER})
pkm_cli_refuses(export_grbl_steps_missing
                "steps-missing\\.toml:15:joints\\[2\\]\\.steps_per_unit: joint 'right' has no steps_per_unit"
                NO_FILE ${GRBL_NEVER}
                export grbl -m ${CLI_DATA}/steps-missing.toml -o ${GRBL_NEVER})
pkm_cli_refuses(export_grbl_letter_a
                "letter-a\\.toml:[0-9]+:joints\\[2\\]\\.axis: joint 'right' is on axis A, which grbl with 3 axes lacks \\(it has X Y Z\\)"
                NO_FILE ${GRBL_NEVER}
                export grbl -m ${CLI_DATA}/letter-a.toml -o ${GRBL_NEVER})
pkm_cli_refuses(export_grbl_baud_zero
                "baud-zero\\.toml:[0-9]+:controller\\.baud: must be between 300 and 10000000 bit/s, not 0"
                NO_FILE ${GRBL_NEVER}
                export grbl -m ${CLI_DATA}/baud-zero.toml -o ${GRBL_NEVER})
