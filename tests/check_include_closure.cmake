# Fails if HEADER includes, directly or through other headers, any barnbench header outside
# the ALLOWED prefixes (paths relative to INCLUDE_DIR, '|'-separated). Run with cmake -P:
#   -DCXX=<compiler> -DINCLUDE_DIR=<repo>/include -DSYSTEM_DIRS=<dir|dir> -DHEADER=<file> -DALLOWED=<prefix|prefix>
# The compiler lists the closure (-MM); system directories are passed as -isystem so their
# headers stay out of the list, leaving only ours.
foreach(var CXX INCLUDE_DIR HEADER ALLOWED)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_include_closure: ${var} not set")
  endif()
endforeach()
string(REPLACE "|" ";" allowed "${ALLOWED}")
string(REPLACE "|" ";" system_dirs "${SYSTEM_DIRS}")
set(system_flags)
foreach(dir IN LISTS system_dirs)
  list(APPEND system_flags -isystem ${dir})
endforeach()

execute_process(
  COMMAND ${CXX} -std=c++20 -MM -I${INCLUDE_DIR} ${system_flags} -x c++ ${HEADER}
  OUTPUT_VARIABLE deps ERROR_VARIABLE errors RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${HEADER} does not preprocess on its own:\n${errors}")
endif()

string(REGEX MATCHALL "${INCLUDE_DIR}/barn/[^ \\\n]+" headers "${deps}")
get_filename_component(header_real ${HEADER} REALPATH)
set(offending)
set(checked 0)
foreach(h IN LISTS headers)
  get_filename_component(h_real ${h} REALPATH)
  if(h_real STREQUAL header_real)
    continue()
  endif()
  math(EXPR checked "${checked} + 1")
  file(RELATIVE_PATH rel ${INCLUDE_DIR} ${h})
  set(ok FALSE)
  foreach(prefix IN LISTS allowed)
    string(FIND "${rel}" "${prefix}" at)
    if(at EQUAL 0)
      set(ok TRUE)
    endif()
  endforeach()
  if(NOT ok)
    list(APPEND offending ${rel})
  endif()
endforeach()

if(offending)
  list(JOIN offending "\n  " listed)
  message(FATAL_ERROR "${HEADER} pulls in headers outside ${ALLOWED}:\n  ${listed}")
endif()
message(STATUS "${HEADER} includes ${checked} barnbench headers, all within ${ALLOWED}")
