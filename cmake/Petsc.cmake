# PETSc with MPI and MUMPS (Debian 12: petsc-dev, PETSc 3.18, OpenMPI; `scripts/install-deps --petsc`),
# for distributed runs (`mpirun -np N fibrane run CASE.yaml`, src/parallel). Off by default.
# Defines the INTERFACE target fibrane_petsc: PETSc's headers and library, MPI, and the compile
# definition FIBRANE_HAVE_PETSC. PETSc links the MPI MUMPS, which cannot share a binary with the
# sequential MUMPS of FIBRANE_MUMPS (cmake/Mumps.cmake checks that).
option(FIBRANE_PETSC "Distributed runs on PETSc (MPI, MUMPS): src/parallel and fibrane run under mpirun" OFF)
add_library(fibrane_petsc INTERFACE)
if(FIBRANE_PETSC)
  find_package(PkgConfig REQUIRED)
  # Debian installs PETSc's pkg-config file under its own prefix.
  set(ENV{PKG_CONFIG_PATH} "$ENV{PKG_CONFIG_PATH}:/usr/lib/petscdir/petsc-real/lib/pkgconfig")
  pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc)
  set(MPI_CXX_SKIP_MPICXX ON)  # the C API only, without OpenMPI's deprecated C++ bindings
  find_package(MPI REQUIRED COMPONENTS CXX)
  target_link_libraries(fibrane_petsc INTERFACE PkgConfig::PETSC MPI::MPI_CXX)
  target_compile_definitions(fibrane_petsc INTERFACE FIBRANE_HAVE_PETSC)
  find_program(FIBRANE_MPIEXEC NAMES mpiexec mpirun REQUIRED)
  message(STATUS "PETSc ${PETSC_VERSION}: distributed runs enabled (${FIBRANE_MPIEXEC})")
endif()
