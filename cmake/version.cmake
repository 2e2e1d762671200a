# Writes version.cpp from src/version.cpp.in with the current `git describe`.
# Run at every build (the softflow_version target), so the version a binary
# and the perf harness report names the commit it was built from; the file is
# rewritten, and recompiled, only when the description changes.
# In: SOURCE_DIR, BINARY_DIR, PROJECT_VERSION.
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE SOFTFLOW_GIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT SOFTFLOW_GIT)
  set(SOFTFLOW_GIT "unknown")
endif()
configure_file(${SOURCE_DIR}/src/version.cpp.in ${BINARY_DIR}/version.cpp @ONLY)
