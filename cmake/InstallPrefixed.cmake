# Runs at install time (cmake/Install.cmake): writes the job templates with their install prefix
# filled in, and the Lmod module file. CMAKE_INSTALL_PREFIX is the --prefix given to cmake --install
# (/usr when CPack stages the .deb under DESTDIR).
set(share "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/${TEXSIM_DATADIR}/texsim")
set(executable OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ
    WORLD_EXECUTE)

foreach(job slurm/texsim.sbatch pbs/texsim.pbs)
  file(READ "${TEXSIM_SOURCE_DIR}/jobs/${job}" text)
  string(FIND "${text}" "\ntexsim_prefix=\"\"\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "jobs/${job}: no line texsim_prefix=\"\" to fill with the prefix")
  endif()
  string(REPLACE "\ntexsim_prefix=\"\"\n" "\ntexsim_prefix=\"${CMAKE_INSTALL_PREFIX}\"\n" text
                 "${text}")
  message(STATUS "Installing: ${share}/jobs/${job}")
  file(WRITE "${share}/jobs/${job}" "${text}")
  file(CHMOD "${share}/jobs/${job}" PERMISSIONS ${executable})
endforeach()

set(module "${share}/modulefiles/texsim/${TEXSIM_VERSION}.lua")
set(TEXSIM_PREFIX "${CMAKE_INSTALL_PREFIX}")
file(READ "${TEXSIM_SOURCE_DIR}/cmake/texsim_module.lua.in" text)
string(CONFIGURE "${text}" text @ONLY)
message(STATUS "Installing: ${module}")
file(WRITE "${module}" "${text}")
