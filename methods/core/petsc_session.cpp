#include "methods/core/petsc_session.hpp"

#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv::petsc {

namespace {

void finalize() {
  PetscBool done = PETSC_FALSE;
  PetscFinalized(&done);
  if (!done) PetscFinalize();
}

}  // namespace

bool launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

bool initialized() {
  PetscBool yes = PETSC_FALSE;
  PetscInitialized(&yes);
  return yes == PETSC_TRUE;
}

void ensure_initialized() {
  if (initialized()) return;
  // Before PetscInitialize the options database takes values for the initialization itself.
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  int argc = 0;
  char** argv = nullptr;
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0)
    throw std::runtime_error("PETSc (MPI) could not be initialized");
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  std::atexit(finalize);
}

int rank() {
  if (!initialized()) return 0;
  PetscMPIInt r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

int size() {
  if (!initialized()) return 1;
  PetscMPIInt s = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &s);
  return s;
}

namespace {

/// Whether this process has passed its first agreement point (checks_done or a failing
/// finish): the one piece of state the agreement needs, kept with the rest of the session.
bool& first_point_passed() {
  static bool passed = false;
  return passed;
}

/// The largest code of all ranks and rank 0's (one allreduce and one broadcast).
Agreement agree(int code) {
  if (!launched_by_mpirun() || !initialized()) return {code, code};
  Agreement a;
  int mine = code;
  MPI_Allreduce(&mine, &a.code, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  a.rank0_code = code;
  MPI_Bcast(&a.rank0_code, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  return a;
}

}  // namespace

void checks_done() {
  if (!launched_by_mpirun() || !initialized() || first_point_passed()) return;
  first_point_passed() = true;
  const Agreement a = agree(0);
  if (a.code != 0) throw OtherRankFailed(a.code);
}

Agreement finish(int code) {
  if (!first_point_passed()) {
    first_point_passed() = true;
    agree(code);
  }
  return agree(code);
}

void insert_options(const std::string& options) {
  ensure_initialized();
  if (PetscOptionsInsertString(nullptr, options.c_str()) != 0)
    throw InputError(fmt::format("PETSc refused the options '{}': give them as PETSc's command "
                                 "line, e.g. '-ksp_type gmres -ksp_rtol 1e-10'",
                                 options));
}

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(
      fmt::format("PETSc: {} failed: {} (error {})", what, text ? text : "unknown", int(code)));
}

}  // namespace mfv::petsc
