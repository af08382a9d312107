/// PETSc (and through it MPI) for the distributed paths: one initialization per process,
/// started at program start under mpirun or on first use otherwise, finalized at exit.
///
/// PETSc's state is per process by design (PetscInitialize/PetscFinalize, the options
/// database); this file is the one place mfv touches it, so no other code keeps global state.
#pragma once
#include <string>

#include <petscsys.h>

namespace mfv::petsc {

/// Whether this process was started by mpirun/mpiexec (Open MPI's or a PMI launcher's
/// environment): then MPI must be initialized at start so every rank knows its number.
bool launched_by_mpirun();

/// Initializes PETSc once (with -no_signal_handler: mfv's own errors and the sanitizers keep
/// their signals); PetscFinalize runs at exit. Later calls do nothing.
void ensure_initialized();
bool initialized();

/// This process's rank and the number of ranks of PETSC_COMM_WORLD (0 and 1 before
/// initialization: a plain run is one rank).
int rank();
int size();

/// Adds options to PETSc's database, e.g. "-ksp_type gmres -ksp_rtol 1e-10" (a user's
/// pass-through). Throws InputError naming the text when PETSc refuses it.
void insert_options(const std::string& options);

/// Throws std::runtime_error with PETSc's message for a non-zero error code; `what` names the
/// call. PETSc returns its errors (PetscReturnErrorHandler) instead of printing tracebacks.
void check(PetscErrorCode code, const char* what);

}  // namespace mfv::petsc
