# MUMPS, sequential build (Debian 12: libmumps-seq-dev, MUMPS 5.5.1; no CMake or pkg-config files).
# Defines the INTERFACE target fibrane_mumps: empty when FIBRANE_MUMPS is OFF, otherwise the five
# sequential libraries and the compile definition FIBRANE_HAVE_MUMPS (src/linalg/mumps_solver.cpp).
#
# Sequential and MPI MUMPS cannot share a process. Debian's sequential libdmumps_seq exports the same
# C and Fortran symbols as the MPI libdmumps (dmumps_c and ~880 others), and it also defines the stub
# MPI_Init, MPI_Comm_rank, MPI_Finalize (the sequential MPI stand-ins) that OpenMPI's libmpi defines.
# Linking both gives no error (shared libraries may repeat a symbol); the dynamic loader binds every
# reference to the first definition in load order. Measured with a stand-in for PETSc (a shared library
# calling MPI_Init and the MPI dmumps_c), in either link order: its MPI_Init was bound to
# libdmumps_seq's stub, so MPI was never initialised and OpenMPI aborted at the first MPI_Comm_c2f;
# the sequential solver itself still ran. PETSc (petsc-dev) links the MPI MUMPS (libmumps-5.5), so a
# build that links PETSc must set FIBRANE_MUMPS=OFF; the check below makes that an error instead of a
# crash at run time, for the FIBRANE_PETSC option such a build adds. (The MPI MUMPS run on
# MPI_COMM_SELF in that build, after PETSc's MPI_Init, works beside PETSc: same library, measured
# with the same stand-in; it is what would give such a build the "mumps" kind back.)
option(FIBRANE_MUMPS "Sequential MUMPS: the 'mumps' solver kind (LDL^T with pivoting and inertia) and the fallback of 'auto'" ON)
add_library(fibrane_mumps INTERFACE)
if(FIBRANE_MUMPS AND FIBRANE_PETSC)
  message(FATAL_ERROR "FIBRANE_MUMPS (sequential MUMPS) and FIBRANE_PETSC (which links the MPI MUMPS) "
    "define the same symbols and cannot share one binary: configure with -DFIBRANE_MUMPS=OFF")
endif()
if(FIBRANE_MUMPS)
  find_path(MUMPS_INCLUDE_DIR dmumps_c.h REQUIRED)
  set(_mumps_libs)
  foreach(lib dmumps_seq smumps_seq mumps_common_seq pord_seq mpiseq_seq)
    find_library(MUMPS_${lib}_LIBRARY ${lib} REQUIRED)
    list(APPEND _mumps_libs ${MUMPS_${lib}_LIBRARY})
  endforeach()
  target_include_directories(fibrane_mumps SYSTEM INTERFACE ${MUMPS_INCLUDE_DIR})
  target_link_libraries(fibrane_mumps INTERFACE ${_mumps_libs})
  target_compile_definitions(fibrane_mumps INTERFACE FIBRANE_HAVE_MUMPS)
endif()
