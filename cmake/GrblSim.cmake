# grbl-sim: grbl 1.1h compiled for Linux with a simulated clock (../shared/controllers/grbl-1.1h,
# its README), the controller `pkm stream --dry-run` and the grbl tests run programs through. It
# is built from the sources beside the clone into the build directory, once (build-sim: gcc and
# make, a few seconds to a minute; its step file then line-buffered and its timer interrupts
# freed from its racy interrupt flag, build-grbl-sim.sh), by the
# target grbl_sim; nothing of grbl is in the repository.
# Sets PKM_GRBL_SIM_EXE (empty when the sources are missing, said as a missing part of the
# suite).
get_filename_component(PKM_GRBL_SOURCES_DEFAULT
                       ${PROJECT_SOURCE_DIR}/../shared/controllers/grbl-1.1h ABSOLUTE)
set(PKM_GRBL_SOURCES ${PKM_GRBL_SOURCES_DEFAULT} CACHE PATH
    "grbl 1.1h and grbl-sim with their build-sim script (../shared/controllers/grbl-1.1h)")
set(PKM_GRBL_SIM_EXE "")
# build-sim runs grbl-sim's Makefile; make comes with cmake only as a recommended package.
find_program(PKM_MAKE make)
if(NOT PKM_MAKE)
  pkm_suite_part_missing("the tests that stream through grbl 1.1h (grbl-sim)"
                         "make builds grbl-sim: apt-get install make")
elseif(EXISTS ${PKM_GRBL_SOURCES}/build-sim)
  set(grbl_sim_dir ${CMAKE_BINARY_DIR}/grbl-sim)
  set(PKM_GRBL_SIM_EXE ${grbl_sim_dir}/grbl/grbl-sim/grbl_sim.exe)
  file(GLOB_RECURSE grbl_sources CONFIGURE_DEPENDS ${PKM_GRBL_SOURCES}/*.c ${PKM_GRBL_SOURCES}/*.h)
  add_custom_command(
    OUTPUT ${PKM_GRBL_SIM_EXE}
    COMMAND ${CMAKE_CURRENT_LIST_DIR}/build-grbl-sim.sh ${PKM_GRBL_SOURCES}/build-sim ${grbl_sim_dir}
    DEPENDS ${PKM_GRBL_SOURCES}/build-sim ${CMAKE_CURRENT_LIST_DIR}/build-grbl-sim.sh ${grbl_sources}
    COMMENT "Building grbl-sim (grbl 1.1h for Linux) from ${PKM_GRBL_SOURCES}"
    VERBATIM)
  add_custom_target(grbl_sim ALL DEPENDS ${PKM_GRBL_SIM_EXE})
else()
  pkm_suite_part_missing("the tests that stream through grbl 1.1h (grbl-sim)"
                         "no ${PKM_GRBL_SOURCES}/build-sim: put the shared controllers beside "
                         "the clone, in ../shared/controllers/grbl-1.1h, or configure with "
                         "-DPKM_GRBL_SOURCES=DIR")
endif()
