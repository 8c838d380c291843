# SPDX-License-Identifier: Apache-2.0
# Writes OUTPUT (a .cpp in the build tree) from TEMPLATE with the project version VERSION and the
# source tree's `git describe --always --dirty`, or "unknown" where there is no git or no
# repository. Run at build time (cmake -P) by the target ncqual_version_info; configure_file
# leaves OUTPUT untouched when its text is unchanged, so only a new commit or a change of the
# dirty state recompiles it, and only the executables that print the version relink.
set(NCQUAL_GIT_DESCRIBE "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty
                  WORKING_DIRECTORY "${SOURCE_DIR}"
                  OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE failed ERROR_QUIET)
  if(NOT failed AND NOT described STREQUAL "")
    set(NCQUAL_GIT_DESCRIBE "${described}")
  endif()
endif()
set(NCQUAL_VERSION "${VERSION}")
configure_file("${TEMPLATE}" "${OUTPUT}" @ONLY)
