# Every example machine as a user runs it (tests/linuxcnc/run-exported): `pkm export linuxcnc
# --sim` by the pkm binary, then the real LinuxCNC headless on that configuration (a joint jog,
# then lines, an arc, a helix and the angular axes through LinuxCNC's planner, sampled every
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

# LinuxCNC's linear delta runs its job 90 % of the way to the edge of the exported box, every
# move at full length: the job that, with [AXIS_x]/[TRAJ] speeds from [cartesian] max_feed and
# max_acceleration alone, drives its joint 1 to 119 % of its MAX_VELOCITY (the second test).
set(LDELTA_EDGE_JOB --share 0.9 --move-seconds 0)
file(GLOB EXAMPLE_MACHINES RELATIVE ${PROJECT_SOURCE_DIR}/examples/machines
     ${PROJECT_SOURCE_DIR}/examples/machines/*.toml)
foreach(machine IN LISTS EXAMPLE_MACHINES)
  string(REGEX REPLACE "\\.toml$" "" name ${machine})
  if(name STREQUAL "linuxcnc-ldelta")
    pkm_exported_machine_test(${name} ${machine} ${LDELTA_EDGE_JOB})
  else()
    pkm_exported_machine_test(${name} ${machine})
  endif()
endforeach()
# The same job with the joints' limits left out of the axes' speeds: a joint passes its limit
# (what the exported configuration above prevents; LinuxCNC issue #97).
pkm_exported_machine_test(linuxcnc-ldelta-cartesian-limits-only linuxcnc-ldelta.toml
                          ${LDELTA_EDGE_JOB} --cartesian-limits-only --joint-rates exceeded)
