# Installs barnbench's build tree into a fresh prefix under WORK_DIR, then configures, builds and
# runs tests/install/project against it with find_package(barnbench) alone (no path into the
# source or build tree): the exported package is complete and usable. Run with cmake -P:
#   -DBINARY_DIR=<build> -DSOURCE_DIR=<repo> -DWORK_DIR=<scratch> -DGENERATOR=<gen> -DCXX=<compiler>
#   [-DLAUNCHER=<ccache>] [-DBUILD_TYPE=<type>]
cmake_minimum_required(VERSION 3.22)
foreach(var BINARY_DIR SOURCE_DIR WORK_DIR GENERATOR CXX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_install: ${var} not set")
  endif()
endforeach()
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run("cmake --install" ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix})

set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
run("configuring the project" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install/project -B ${WORK_DIR}/build
    -G ${GENERATOR} -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_CXX_COMPILER=${CXX} ${launcher}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("building the project" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)

# One episode on world 0 with the shipped sim config: it runs and is scored.
run("running the project" ${WORK_DIR}/build/run_toward_goal ${SOURCE_DIR}/worlds 0 ${SOURCE_DIR}/configs/sim/barn.yaml)
if(NOT run_output MATCHES "^world 0: [a-z]+ after [0-9.]+ s, score [0-9.]+\n$")
  message(FATAL_ERROR "unexpected output of run_toward_goal:\n${run_output}")
endif()
message(STATUS "built and ran a project against the installed barnbench: ${run_output}")
