# Run at every build (cmake -P): writes OUT, a header defining TRISNAP_GIT_BUILD, the build's
# identity in git terms: "g<commit>" for a clean checkout, "g<commit>.dirty-<hash>" when tracked
# files differ from the commit (the hash is of `git diff HEAD`, so two different edits of one
# commit get different ids), or "" without git (a source tarball, the Docker build: build_id.cpp
# falls back to its own compile time and compiler). OUT is rewritten only when the id changed,
# so an unchanged tree recompiles nothing. Inputs: SOURCE_DIR, OUT.
set(id "")
find_program(GIT git)
if(GIT)
  execute_process(COMMAND ${GIT} --no-optional-locks -C ${SOURCE_DIR} rev-parse --short=12 HEAD
    OUTPUT_VARIABLE commit RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0 AND commit)
    set(id "g${commit}")
    execute_process(COMMAND ${GIT} --no-optional-locks -C ${SOURCE_DIR} diff HEAD --no-ext-diff
      OUTPUT_VARIABLE diff RESULT_VARIABLE rc ERROR_QUIET)
    if(NOT rc EQUAL 0)
      set(id "")
    elseif(diff)
      string(SHA256 hash "${diff}")
      string(SUBSTRING "${hash}" 0 12 hash)
      set(id "${id}.dirty-${hash}")
    endif()
  endif()
endif()
set(text "#define TRISNAP_GIT_BUILD \"${id}\"\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
