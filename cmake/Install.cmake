# `cmake --install build/release --prefix P` (and the .deb, whose prefix is /usr) lays texsim out as
# clusters install HPC codes:
#   P/bin/texsim, P/bin/texsim-render (scripts/render), P/bin/texsim-fetch-data (scripts/fetch-data)
#   P/share/texsim/config/      the example configs (data under ${TEXSIM_DATA})
#   P/share/texsim/jobs/        the Slurm and PBS templates, running P/bin/texsim by default
#   P/share/texsim/modulefiles/texsim/<version>.lua   the Lmod module (PATH, TEXSIM_DATA)
#   P/share/doc/texsim/         README and docs
include(GNUInstallDirs)
install(TARGETS texsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(PROGRAMS scripts/render DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME texsim-render)
install(PROGRAMS scripts/fetch-data DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME texsim-fetch-data)
install(DIRECTORY config/ DESTINATION ${CMAKE_INSTALL_DATADIR}/texsim/config)
install(FILES jobs/texsim_job.sh DESTINATION ${CMAKE_INSTALL_DATADIR}/texsim/jobs)
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
# The job templates and the module name the prefix, which is known only when installing.
install(CODE "set(TEXSIM_SOURCE_DIR \"${PROJECT_SOURCE_DIR}\")
  set(TEXSIM_VERSION \"${PROJECT_VERSION}\")
  set(TEXSIM_DATADIR \"${CMAKE_INSTALL_DATADIR}\")
  include(\"${PROJECT_SOURCE_DIR}/cmake/InstallPrefixed.cmake\")")

# scripts/package: texsim_<version>_amd64.deb, its Depends derived by dpkg-shlibdeps from the
# libraries the binary links, plus openmpi-bin for mpirun.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME texsim)
set(CPACK_PACKAGE_CONTACT "texsim developers <texsim-developers@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Texture synthesis on surfaces, in volumes and on fluids (MPI + OpenMP + PETSc)")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "openmpi-bin")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_PREFIX /usr)
# The install(CODE) above writes into DESTDIR/prefix, so the package must stage through DESTDIR.
set(CPACK_SET_DESTDIR ON)
include(CPack)
