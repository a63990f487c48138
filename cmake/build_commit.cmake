# Writes OUTPUT, a header defining BARN_BUILD_COMMIT: `git rev-parse HEAD` of SOURCE_DIR, with
# "-dirty" if a tracked file has changes, or "unknown" outside a git checkout (or without GIT).
# Run at every build (the barn_build_commit target); the file is rewritten only when its text
# changes, so a build of an unchanged tree recompiles nothing and one after a new commit
# recompiles src/bench/build_commit.cpp alone. `--no-optional-locks`: never takes the
# checkout's .git/index.lock (a concurrent `git commit` there must not fail).
set(commit unknown)
if(GIT)
  execute_process(COMMAND ${GIT} -C ${SOURCE_DIR} rev-parse HEAD
                  OUTPUT_VARIABLE head RESULT_VARIABLE status OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(status EQUAL 0 AND head MATCHES "^[0-9a-f]+$")
    set(commit ${head})
    execute_process(COMMAND ${GIT} -C ${SOURCE_DIR} --no-optional-locks status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE changes RESULT_VARIABLE status ERROR_QUIET)
    if(NOT status EQUAL 0 OR NOT changes STREQUAL "")
      string(APPEND commit "-dirty")
    endif()
  endif()
endif()
set(text "// Generated at build time by cmake/build_commit.cmake; do not edit.\n#define BARN_BUILD_COMMIT \"${commit}\"\n")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
