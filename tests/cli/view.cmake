# pkm view: a joint program drawn without its job (docs/html-views.md, "A joint program alone").
# The wall plotter's cords from home to 1250 mm each (a 300 mm rapid straight down to (750,
# -1000)), then to (900, -800): a stroke of 250.420 mm, the cords interpolated linearly.
set(VIEW_OUT ${CLI_OUT}/view)
file(MAKE_DIRECTORY ${VIEW_OUT})
add_test(NAME cli.view_summary
         COMMAND ${PKM} view -m ${MACHINES}/wall-plotter.toml ${CLI_DATA}/view-stroke.ngc
                 --report ${VIEW_OUT}/stroke.json --html ${VIEW_OUT}/stroke.html)
set_tests_properties(cli.view_summary PROPERTIES PASS_REGULAR_EXPRESSION
  "2 blocks.  drawn 250.420 mm \\(G1 blocks\\), travel 300.000 mm \\(G0 blocks\\), of it rapid \\(G0\\) 300.000 mm.  drawing's extent: x 750.000 mm .. 900.000 mm, y -1000.000 mm .. -800.000 mm.  joint left: 1025.914 mm \\(at the start\\) .. 1250.000 mm \\(line 1\\) of its travel 150.000 mm .. 2100.000 mm: margin 875.914 mm below, 850.000 mm above.*wrote the page")
# A block past a joint's travel: a warning at its line, the page still written, and a failure.
add_test(NAME cli.view_past_travel_warns_writes_its_page_and_fails
         COMMAND sh -c "\"$0\" view -m \"$1\" \"$2\" --html \"$3\" 2>&1; status=$?; test -s \"$3\" && exit $status"
                 ${PKM} ${MACHINES}/wall-plotter.toml ${CLI_DATA}/view-past-travel.ngc
                 ${VIEW_OUT}/past.html)
set_tests_properties(cli.view_past_travel_warns_writes_its_page_and_fails PROPERTIES WILL_FAIL TRUE)
pkm_cli_refuses(view_past_travel
                "view-past-travel.ngc: 1 block end lies beyond a joint's travel, the first at line 2"
                view -m ${MACHINES}/wall-plotter.toml ${CLI_DATA}/view-past-travel.ngc)
pkm_cli_refuses(view_past_travel_warns_at_its_line
                "warning: .*view-past-travel.ngc:2: joint 'left' = 2200.000 mm passes its max 2100.000 mm"
                view -m ${MACHINES}/wall-plotter.toml ${CLI_DATA}/view-past-travel.ngc)
# Words the machine or the dialect does not have: refused at their column, no page.
pkm_cli_refuses(view_cartesian_job "view-cartesian-z.ngc:2:10: Z word: no joint of Wall plotter 1500 is on Z"
                NO_FILE ${VIEW_OUT}/never.html
                view -m ${MACHINES}/wall-plotter.toml ${CLI_DATA}/view-cartesian-z.ngc
                --html ${VIEW_OUT}/never.html)
pkm_cli_refuses(view_grbl_has_no_parameters "view-params.ngc:2:1: grbl has no #parameters"
                NO_FILE ${VIEW_OUT}/never.html
                view -m ${MACHINES}/wall-plotter.toml ${CLI_DATA}/view-params.ngc --dialect grbl
                --html ${VIEW_OUT}/never.html)
pkm_cli_refuses(view_no_such_program "no-such.ngc: cannot open"
                view -m ${MACHINES}/wall-plotter.toml ${CLI_DATA}/no-such.ngc)
