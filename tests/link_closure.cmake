# barn_add_link_closure_test(<test name> TARGET <target> FORBIDDEN <target>...): a test that
# fails if <target>'s link closure — everything linking it pulls in, through PUBLIC, INTERFACE
# and (for static libraries) PRIVATE dependencies — holds any FORBIDDEN target. The closure is
# walked here, when CMake configures, from the targets' LINK_LIBRARIES and
# INTERFACE_LINK_LIBRARIES; the test reports it (tests/check_link_closure.cmake), so a change
# to a target_link_libraries line that pulls a forbidden library in fails the suite.

# The target a name stands for (an ALIAS's real target), or the name itself if it is no target.
function(_barn_real_target name out)
  set(real ${name})
  if(TARGET ${name})
    get_target_property(aliased ${name} ALIASED_TARGET)
    if(aliased)
      set(real ${aliased})
    endif()
  endif()
  set(${out} ${real} PARENT_SCOPE)
endfunction()

function(barn_link_closure target out)
  _barn_real_target(${target} start)
  set(seen)
  set(queue ${start})
  while(queue)
    list(POP_FRONT queue current)
    if(current IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${current})
    if(NOT TARGET ${current})
      continue()
    endif()
    get_target_property(type ${current} TYPE)
    set(deps)
    get_target_property(interface ${current} INTERFACE_LINK_LIBRARIES)
    if(interface)
      list(APPEND deps ${interface})
    endif()
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${current} LINK_LIBRARIES)
      if(direct)
        list(APPEND deps ${direct})
      endif()
    endif()
    foreach(dep IN LISTS deps)
      # A static library's PRIVATE dependencies appear as $<LINK_ONLY:dep>: still linked.
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" dep "${dep}")
      if(dep MATCHES "^\\$<")
        continue()  # other generator expressions: none of ours
      endif()
      _barn_real_target(${dep} real)
      list(APPEND queue ${real})
    endforeach()
  endwhile()
  list(REMOVE_ITEM seen ${start})
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

function(barn_add_link_closure_test name)
  cmake_parse_arguments(ARG "" "TARGET" "FORBIDDEN" ${ARGN})
  barn_link_closure(${ARG_TARGET} closure)
  set(forbidden)
  foreach(f IN LISTS ARG_FORBIDDEN)
    _barn_real_target(${f} real)
    list(APPEND forbidden ${real})
  endforeach()
  list(JOIN closure "|" closure_arg)
  list(JOIN forbidden "|" forbidden_arg)
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -DTARGET=${ARG_TARGET} "-DCLOSURE=${closure_arg}" "-DFORBIDDEN=${forbidden_arg}"
            -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/check_link_closure.cmake)
endfunction()
