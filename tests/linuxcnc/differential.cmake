# Differential tests (tests/linuxcnc/run-differential, docs/linuxcnc-differential.md): a LinuxCNC
# configuration of one of LinuxCNC's own kinematics modules goes through `pkm import linuxcnc`
# and `pkm export linuxcnc --sim`; the same program then runs through the real LinuxCNC on the
# exported configuration once with pkmkins and once with the module (and its geometry HAL file);
# the joints must agree within 1e-6 mm (deg for rotary joints) sample by sample. Included from
# tests/linuxcnc/CMakeLists.txt once pkmkins is a target; label linuxcnc, one LinuxCNC at a time
# (RESOURCE_LOCK linuxcnc); skipped (77, the reason printed) as the harness skips.

# matrixkins' equations as a module of our own (Debian's LinuxCNC 2.9 has no matrixkins), built
# as pkmkins is, under a name no LinuxCNC module has.
add_library(pkmtest_matrixkins MODULE matrixkins/pkmtest_matrixkins.cpp)
set_target_properties(pkmtest_matrixkins PROPERTIES
  PREFIX ""
  LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/linuxcnc)
target_include_directories(pkmtest_matrixkins SYSTEM PRIVATE ${LINUXCNC_INCLUDE_DIR})
target_compile_definitions(pkmtest_matrixkins PRIVATE RTAPI USPACE __MODULE__ SIM)
target_link_libraries(pkmtest_matrixkins PRIVATE pkm_warnings)
target_link_options(pkmtest_matrixkins PRIVATE
  -Wl,--version-script=${PROJECT_SOURCE_DIR}/apps/pkmkins/pkmkins.map -Wl,-Bsymbolic)

set(RUN_DIFFERENTIAL ${CMAKE_CURRENT_SOURCE_DIR}/run-differential
    --pkm $<TARGET_FILE:pkm> --module $<TARGET_FILE:pkmkins>
    --checker $<TARGET_FILE:pkm_linuxcnc_check>)
set(DIFF_CONFIGS ${CMAKE_CURRENT_SOURCE_DIR}/diff)
function(pkm_linuxcnc_differential name)
  add_test(NAME linuxcnc.differential_${name}
           COMMAND ${RUN_DIFFERENTIAL} --work ${CMAKE_CURRENT_BINARY_DIR}/runs/differential_${name}
                   ${ARGN})
  # TIMEOUT: two runs of 120 s at most, and up to 240 s waiting for another LinuxCNC each.
  set_tests_properties(linuxcnc.differential_${name} PROPERTIES LABELS linuxcnc
                       RESOURCE_LOCK linuxcnc TIMEOUT 780 SKIP_RETURN_CODE 77)
endfunction()

# LinuxCNC's hexapod simulator on genhexkins (inch): a joint jog, lines, an arc, a helix, A B C.
pkm_linuxcnc_differential(genhexkins
  --reference ${DIFF_CONFIGS}/genhexkins --jog 0:0.5:1
  --program ${DIFF_CONFIGS}/genhexkins/program.ngc)
# LinuxCNC's linear delta on lineardeltakins (mm): a joint jog, lines, an arc, a helix.
pkm_linuxcnc_differential(lineardeltakins
  --reference ${DIFF_CONFIGS}/lineardeltakins --jog 1:-20:50
  --program ${DIFF_CONFIGS}/lineardeltakins/program.ngc)
# LinuxCNC's rotary delta on rotarydeltakins (inch, arms in deg): a joint jog, lines, an arc, a
# helix.
pkm_linuxcnc_differential(rotarydeltakins
  --reference ${DIFF_CONFIGS}/rotarydeltakins --jog 2:2:20 --rotary-joints j0,j1,j2
  --program ${DIFF_CONFIGS}/rotarydeltakins/program.ngc)
# The matrix-calibrated mill on matrixkins' equations (pkmtest_matrixkins, imported as the
# matrixkins configuration it stands in for): lines, an arc, a helix, A and B.
pkm_linuxcnc_differential(matrixkins
  --reference ${DIFF_CONFIGS}/matrixkins --reference-module $<TARGET_FILE:pkmtest_matrixkins>
  --import-as matrixkins --jog 2:-5:20 --rotary-joints j3,j4
  --program ${DIFF_CONFIGS}/matrixkins/program.ngc)
# genhexkins' spindle offset (the same hexapod, setp genhexkins.spindle-offset 1.5): the import's
# tool_length and raised base joints give genhexkins' legs at tilted poses.
pkm_linuxcnc_differential(genhexkins_spindle_offset
  --reference ${DIFF_CONFIGS}/genhexkins
  --extra-hal ${DIFF_CONFIGS}/genhexkins-spindle-offset/spindle-offset.hal
  --program ${DIFF_CONFIGS}/genhexkins-spindle-offset/program.ngc)

# The sample-by-sample comparison itself, on made-up runs (no LinuxCNC): it must pass rounding
# and fail a joint 1.02e-6 mm off, a pose that parts, an extra cycle, another motion mode.
add_test(NAME linuxcnc.differential_comparison_fails_what_it_should
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/test_compare_runs.py)
set_tests_properties(linuxcnc.differential_comparison_fails_what_it_should PROPERTIES
                     LABELS linuxcnc)
