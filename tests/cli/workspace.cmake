# pkm workspace: the summary, the JSON document's names, and the refusals of bad ranges.
add_test(NAME cli.workspace_hektor_summary
         COMMAND ${PKM} workspace -m ${MACHINES}/hektor.toml --resolution 2)
set_tests_properties(cli.workspace_hektor_summary PROPERTIES PASS_REGULAR_EXPRESSION
  "area: [0-9.e+]+ \\.\\. [0-9.e+]+ mm\\^2 \\(proven inside \\.\\. inside \\+ boundary cells\\)\nestimate: [0-9.e+]+ mm\\^2[^\n]*\nextent: x -2\\.0\\.\\.102\\.0 y -180\\.0\\.\\.2\\.0 mm")
add_test(NAME cli.workspace_json_names
         COMMAND sh -c "\"$0\" workspace -m \"$1\" --resolution 128 --orientation 5 --json | python3 -c \"import json, sys; d = json.load(sys.stdin); assert d['orientation_deg']['a'] == [-5.0, 5.0]; assert set(d['volume_mm3']) >= {'inside', 'boundary'}; assert d['cells']['step_mm'] == 128.0; assert len(d['cells']['dims']) == 3; assert [m['name'] for m in d['maps']] == ['dexterity', 'joint_speed_per_tool_speed']; assert d['largest_cylinder_mm']['radius'] > 0; print('ok')\""
                 ${PKM} ${MACHINES}/hexapod-bit.toml)
set_tests_properties(cli.workspace_json_names PROPERTIES PASS_REGULAR_EXPRESSION "^ok\n$")
add_test(NAME cli.workspace_planar_json_has_an_area
         COMMAND ${PKM} workspace -m ${MACHINES}/pen-plotter.toml --resolution 50 --json)
set_tests_properties(cli.workspace_planar_json_has_an_area PROPERTIES PASS_REGULAR_EXPRESSION
  "\"area_mm2\":\\{\"boundary\":[0-9.e+]+,\"estimate\":[0-9.e+]+,\"inside\":[0-9.e+]+\\}")
pkm_cli_refuses(workspace_angle_the_machine_lacks "the machine does not control a"
                workspace -m ${MACHINES}/hektor.toml --orientation a=-5:5)
pkm_cli_refuses(workspace_empty_range "a=5:1 has min > max"
                workspace -m ${MACHINES}/hexapod-bit.toml --orientation a=5:1)
pkm_cli_refuses(workspace_range_not_an_angle "'x' is not an angle in degrees"
                workspace -m ${MACHINES}/hektor.toml --orientation x)
pkm_cli_refuses(workspace_resolution_not_a_length "--resolution: 0 is outside"
                workspace -m ${MACHINES}/hektor.toml --resolution 0)
# --html: the page written through the HTML view (the browser test opens one), outputs checked
# before the work, never over the machine file.
add_test(NAME cli.workspace_html_page
         COMMAND sh -c "\"$0\" workspace -m \"$1\" --resolution 4 --html \"$2\" && grep -c 'largest_box_mm' \"$2\""
                 ${PKM} ${MACHINES}/hektor.toml ${CLI_OUT}/workspace-hektor.html)
set_tests_properties(cli.workspace_html_page PROPERTIES PASS_REGULAR_EXPRESSION
  "wrote the page .*workspace-hektor.html: open it in a browser\n[1-9]")
pkm_cli_refuses(workspace_html_into_a_directory "--html .*is a directory"
                workspace -m ${MACHINES}/hektor.toml --html ${CLI_OUT})
configure_file(${MACHINES}/hektor.toml ${CLI_OUT}/workspace-machine.toml COPYONLY)
pkm_cli_refuses(workspace_html_over_the_machine "the output is the input file .*workspace-machine.toml \\(the machine file\\)"
                workspace -m ${CLI_OUT}/workspace-machine.toml
                --html ${CLI_OUT}/workspace-machine.toml)
pkm_cli_refuses(workspace_html_empty_name "--html"
                workspace -m ${MACHINES}/hektor.toml --html "")
# LinuxCNC's hexapod sample (legs 20..40 in): its largest box lies above the base, around home's
# z 20 in, not in the mirror image below (issue 25: it was z -637..-381 mm). An inch machine: the
# resolution and the output are in inches (0.625 in, 15.9 mm).
add_test(NAME cli.workspace_hexapod_sample_above_its_base
         COMMAND ${PKM} workspace -m ${CLI_DATA}/linuxcnc-hexapod-sample-legs-20-40.toml
                 --resolution 0.625)
set_tests_properties(cli.workspace_hexapod_sample_above_its_base PROPERTIES
  PASS_REGULAR_EXPRESSION "extent: x [-0-9.]+\\.\\.[0-9.]+ y [-0-9.]+\\.\\.[0-9.]+ z -?0\\.[0-9]+\\.\\.[0-9.]+ in\nlargest box inside: x [-0-9.]+\\.\\.[0-9.]+ y [-0-9.]+\\.\\.[0-9.]+ z 1[0-9]\\.[0-9]+\\.\\.2[0-9]\\.[0-9]+ in")
# Issue 26: the paper's hexapod at 0.5 mm grew to gigabytes before its cell bound refused it. The
# estimate (from a run at 64 mm, 4 times the cells with each halving) refuses it at once, before
# the page is written, naming the memory and a resolution that fits.
pkm_cli_refuses(workspace_resolution_too_fine
  "--resolution 0.5 mm: the workspace would judge about 3.0[0-9]e\\+08 cells and list 1.[0-9]+e\\+08 \\(about [0-9.]+ GB of memory\\), more than --max-cells 200000000 \\(estimated from a run at 64 mm, .*\\): --resolution 0.6[0-9] mm or coarser fits, or raise --max-cells"
  NO_FILE ${CLI_OUT}/workspace-too-fine.html
  workspace -m ${MACHINES}/hexapod-bit.toml --resolution 0.5 --html ${CLI_OUT}/workspace-too-fine.html)
pkm_cli_refuses(workspace_max_cells_zero "--max-cells: 0 is outside"
                workspace -m ${MACHINES}/hektor.toml --max-cells 0)
