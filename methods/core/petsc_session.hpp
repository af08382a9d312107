/// PETSc (and through it MPI) for the distributed paths: one initialization per process,
/// started at program start under mpirun or on first use otherwise, finalized at exit.
///
/// PETSc's state is per process by design (PetscInitialize/PetscFinalize, the options
/// database); this file is the one place mfv touches it, so no other code keeps global state.
#pragma once
#include <exception>
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

/// What the ranks of an mpirun agreed on: the largest exit code any rank gave, and rank 0's.
struct Agreement {
  int code = 0;       ///< every rank exits with it
  int rank0_code = 0; ///< rank 0's own: a failing rank prints its message only if rank 0 did not fail
};

/// Every rank's agreement points under mpirun, so that no rank waits for ever in a collective
/// call while another has left (a report target refused by rank 0 alone used to hang rank 1
/// in PETSc): each rank passes checks_done() once its own up-front checks have passed, before
/// any collective work, and finish() with its exit code at the end; a rank that fails before
/// checks_done() passes both points through finish(). Without MPI both do nothing.
///
/// checks_done() throws OtherRankFailed when another rank's checks failed.
void checks_done();
/// The agreement at the end (and at checks_done() if this rank never reached it).
Agreement finish(int code);

/// Thrown by checks_done() on the ranks whose own checks passed when another's failed.
struct OtherRankFailed : std::exception {
  int code = 0;
  explicit OtherRankFailed(int c) : code(c) {}
  const char* what() const noexcept override { return "another rank failed its checks"; }
};

/// Adds options to PETSc's database, e.g. "-ksp_type gmres -ksp_rtol 1e-10" (a user's
/// pass-through). Throws InputError naming the text when PETSc refuses it.
void insert_options(const std::string& options);

/// Throws std::runtime_error with PETSc's message for a non-zero error code; `what` names the
/// call. PETSc returns its errors (PetscReturnErrorHandler) instead of printing tracebacks.
void check(PetscErrorCode code, const char* what);

}  // namespace mfv::petsc
