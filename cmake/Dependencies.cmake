# Every third-party library texsim links, found once; layers link the imported targets they need.
# Order matters: TBB (CONFIG) before OpenVDB, or VTK's and OpenVDB's TBB targets collide.
find_package(MPI REQUIRED COMPONENTS C CXX)
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_package(PkgConfig REQUIRED)
pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc)

set(HDF5_PREFER_PARALLEL TRUE)
find_package(HDF5 REQUIRED COMPONENTS C)
if(NOT HDF5_IS_PARALLEL)
  message(FATAL_ERROR "texsim needs parallel HDF5 (Debian: libhdf5-openmpi-dev)")
endif()
add_library(texsim_hdf5 INTERFACE)
target_include_directories(texsim_hdf5 SYSTEM INTERFACE ${HDF5_INCLUDE_DIRS})
target_link_libraries(texsim_hdf5 INTERFACE ${HDF5_LIBRARIES})
target_compile_definitions(texsim_hdf5 INTERFACE ${HDF5_DEFINITIONS})

find_package(TBB REQUIRED CONFIG)
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
find_package(OpenVDB REQUIRED)

find_package(VTK REQUIRED COMPONENTS
  CommonCore CommonDataModel CommonExecutionModel
  IOXML IOParallelXML IOPLY IOGeometry IOLegacy IOImage
  FiltersCore FiltersGeometry ImagingCore)

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(CGAL REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(muparser REQUIRED)
find_package(ZLIB REQUIRED)

# OpenBLAS (not the reference BLAS that Debian's libblas.so may resolve to): cblas for dense
# kernels and openblas_set_num_threads, so BLAS does not spawn threads inside our OpenMP regions.
pkg_check_modules(OPENBLAS REQUIRED IMPORTED_TARGET openblas)
