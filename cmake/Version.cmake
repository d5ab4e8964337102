# Records the git hash and the dependency versions for `texsim --version`.
execute_process(COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
  OUTPUT_VARIABLE TEXSIM_GIT_HASH OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT TEXSIM_GIT_HASH)
  set(TEXSIM_GIT_HASH "unknown")
endif()
set(TEXSIM_VTK_VERSION "${VTK_VERSION}")
set(TEXSIM_OPENVDB_VERSION "${OpenVDB_VERSION}")
set(TEXSIM_PETSC_VERSION "${PETSC_VERSION}")
configure_file(${CMAKE_SOURCE_DIR}/src/core/version.hpp.in
               ${CMAKE_BINARY_DIR}/generated/texsim/version.hpp @ONLY)
