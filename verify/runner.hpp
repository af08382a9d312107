/// Runs cases and refinement studies: particles → discretization → assembly → solve →
/// errors, headline quantities, CPU times and sampled fields.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "problems/problem.hpp"
#include "verify/case.hpp"
#include "verify/catalogue.hpp"

namespace mfv {

/// Solves K u = f with the essential conditions of `sys` imposed as the discretization says
/// (Lagrange multipliers or penalty; particle values directly for SPH/RLM), with
/// solve_sparse (UMFPACK, iterative fallback); fills `info` except `condition`. Throws
/// SingularError with the cause when the system cannot be factorized or the solution is not
/// finite. When `solved` is given it receives the factorized matrix (for condition_number).
Eigen::VectorXd solve_constrained(const AssembledSystem& sys, const Discretization& d,
                                  SolveInfo& info, Eigen::SparseMatrix<double>* solved = nullptr,
                                  const std::string& solver = "auto");

/// 2-norm condition number by dense SVD for up to kMaxConditionSize rows; NaN above, inf
/// when the smallest singular value is zero.
double condition_number(const Eigen::SparseMatrix<double>& A);

/// Runs one case. Throws InputError on bad names or parameters, SingularError on a singular
/// moment matrix or global system.
CaseResult run_case(const Catalogue& catalogue, const CaseSpec& spec);

/// Called before each resolution of a study: (index, count, nodes).
using StudyProgress = std::function<void(int, int, int)>;

/// Runs one method on one problem at each resolution and computes the rates.
StudyResult run_study(const Catalogue& catalogue, const CaseSpec& base,
                      const std::vector<int>& nodes, const StudyProgress& progress = {});

/// "rkpm j=1,kernel=gaussian": the method and the parameters the user set.
std::string study_label(const CaseSpec& spec);

/// Process CPU time in seconds.
double cpu_seconds();

}  // namespace mfv
