# Every example machine as a user runs it (tests/linuxcnc/run-exported): `pkm export linuxcnc
# --sim` by the pkm binary, then the real LinuxCNC headless on that configuration (a joint jog,
# then lines, a circle, a helix and the angular axes through LinuxCNC's planner, sampled every
# servo period): joints = pkm IK of the commanded pose within 1e-6 mm or deg, the module's
# forward at rest and in joint mode, and no joint past its [JOINT_n] velocity or acceleration.
# Included by tests/linuxcnc/CMakeLists.txt once the pkmkins target exists.
set(RUN_EXPORTED ${CMAKE_CURRENT_SOURCE_DIR}/run-exported --pkm $<TARGET_FILE:pkm>
    --module $<TARGET_FILE:pkmkins> --checker $<TARGET_FILE:pkm_linuxcnc_check>)
function(pkm_exported_machine_test name machine)
  add_test(NAME linuxcnc.exported.${name}
           COMMAND ${RUN_EXPORTED} --machine ${PROJECT_SOURCE_DIR}/examples/machines/${machine}
                   --work ${CMAKE_CURRENT_BINARY_DIR}/runs/exported-${name} ${ARGN})
  set_tests_properties(linuxcnc.exported.${name} PROPERTIES LABELS linuxcnc RESOURCE_LOCK linuxcnc
                       TIMEOUT 420 SKIP_RETURN_CODE 77)
endfunction()

file(GLOB EXAMPLE_MACHINES RELATIVE ${PROJECT_SOURCE_DIR}/examples/machines
     ${PROJECT_SOURCE_DIR}/examples/machines/*.toml)
foreach(machine IN LISTS EXAMPLE_MACHINES)
  string(REGEX REPLACE "\\.toml$" "" name ${machine})
  pkm_exported_machine_test(${name} ${machine})
endforeach()
