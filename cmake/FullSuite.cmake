# The test suite's parts that need something outside the repository (a Debian package, the real
# G-code corpus beside the clone, LinuxCNC's sample configurations). Each part that cannot be built
# or run is said once at configure time; with PKM_REQUIRE_FULL_SUITE (scripts/test) the configure
# then fails, listing every missing part and how to get it, instead of a test run that passes
# because part of the suite was never registered.
option(PKM_REQUIRE_FULL_SUITE
       "Fail the configure when any part of the test suite cannot be built or run (scripts/test)"
       OFF)
set_property(GLOBAL PROPERTY PKM_MISSING_SUITE_PARTS "")

# pkm_suite_part_missing(PART HOW...): PART of the suite is not built or not run; HOW (its
# strings joined) gets it.
function(pkm_suite_part_missing part)
  string(JOIN "" how ${ARGN})
  message(STATUS "not tested: ${part} (${how})")
  set_property(GLOBAL APPEND PROPERTY PKM_MISSING_SUITE_PARTS "${part}: ${how}")
endfunction()

# pkm_require_python_modules(PART [PYTHON EXE] MODULES... PACKAGES...): PART needs these Python
# modules for EXE (${Python_EXECUTABLE} by default); the Debian packages that bring them follow
# PACKAGES. Sets PKM_PYTHON_MODULES_FOUND in the caller.
function(pkm_require_python_modules part)
  cmake_parse_arguments(ARG "" "PYTHON" "MODULES;PACKAGES" ${ARGN})
  if(NOT ARG_PYTHON)
    set(ARG_PYTHON ${Python_EXECUTABLE})
  endif()
  string(JOIN ", " imports ${ARG_MODULES})
  execute_process(COMMAND ${ARG_PYTHON} -c "import ${imports}" RESULT_VARIABLE status
                  OUTPUT_QUIET ERROR_QUIET)
  if(status EQUAL 0)
    set(PKM_PYTHON_MODULES_FOUND TRUE PARENT_SCOPE)
  else()
    string(JOIN " " packages ${ARG_PACKAGES})
    pkm_suite_part_missing("${part}"
                           "${imports} missing for ${ARG_PYTHON}: apt-get install ${packages}")
    set(PKM_PYTHON_MODULES_FOUND FALSE PARENT_SCOPE)
  endif()
endfunction()

# At the end of the top-level configure: fail when the full suite was asked for and a part is
# missing.
function(pkm_check_full_suite)
  get_property(missing GLOBAL PROPERTY PKM_MISSING_SUITE_PARTS)
  if(NOT missing)
    return()
  endif()
  list(LENGTH missing count)
  string(JOIN "\n  " lines ${missing})
  if(PKM_REQUIRE_FULL_SUITE)
    message(FATAL_ERROR "the full test suite was asked for (PKM_REQUIRE_FULL_SUITE=ON, as "
                        "scripts/test does), but ${count} of its parts cannot be built or run:\n"
                        "  ${lines}\n"
                        "scripts/setup test installs the Debian packages; the real corpus and "
                        "the sample configurations are described in the README, \"Tests\".")
  endif()
  message(STATUS "${count} parts of the test suite are not built or not run (listed above); "
                 "scripts/test refuses to run without them")
endfunction()
