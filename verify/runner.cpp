#include "verify/runner.hpp"

#include <cmath>
#include <ctime>
#include <limits>

#include <Eigen/SVD>
#include <Eigen/SparseLU>
#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "verify/norms.hpp"

namespace mfv {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double condition_number(const Eigen::SparseMatrix<double>& A) {
  if (A.rows() > kMaxConditionSize) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd sv = Eigen::BDCSVD<Eigen::MatrixXd>(Eigen::MatrixXd(A)).singularValues();
  return sv[sv.size() - 1] > 0 ? sv[0] / sv[sv.size() - 1]
                               : std::numeric_limits<double>::infinity();
}

Eigen::VectorXd solve_constrained(const AssembledSystem& sys, const Discretization& d,
                                  SolveInfo& info, Eigen::SparseMatrix<double>* solved) {
  const int n = static_cast<int>(sys.K.rows());
  const ShapeTable g = d.trial_at(sys.constraint_points, 0);
  const int nb = g.points();
  using Trip = Eigen::Triplet<double>;
  std::vector<Trip> trip;
  Eigen::SparseMatrix<double> A;
  Eigen::VectorXd b;
  if (d.essential == EssentialBC::lagrange) {
    // [K G; Gᵀ 0] [u; λ] = [f; g], G_Jb = N_J(x_b): λ_b is the reaction flux at x_b.
    A.resize(n + nb, n + nb);
    trip.reserve(sys.K.nonZeros() + 2 * g.entries());
    for (int k = 0; k < sys.K.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(sys.K, k); it; ++it)
        trip.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
    for (int bq = 0; bq < nb; ++bq)
      for (int k = g.offsets[bq]; k < g.offsets[bq + 1]; ++k) {
        trip.emplace_back(g.index[k], n + bq, g.value[k]);
        trip.emplace_back(n + bq, g.index[k], g.value[k]);
      }
    A.setFromTriplets(trip.begin(), trip.end());
    b.resize(n + nb);
    b << sys.f, sys.constraint_values;
  } else {
    // K + β G Gᵀ, β = penalty × the largest diagonal entry of K.
    double kmax = 0;
    for (int i = 0; i < n; ++i) kmax = std::max(kmax, std::abs(sys.K.coeff(i, i)));
    const double beta = d.penalty * std::max(kmax, 1.0);
    A = sys.K;
    b = sys.f;
    for (int bq = 0; bq < nb; ++bq)
      for (int k = g.offsets[bq]; k < g.offsets[bq + 1]; ++k) {
        b[g.index[k]] += beta * g.value[k] * sys.constraint_values[bq];
        for (int l = g.offsets[bq]; l < g.offsets[bq + 1]; ++l)
          trip.emplace_back(g.index[k], g.index[l], beta * g.value[k] * g.value[l]);
      }
    Eigen::SparseMatrix<double> P(n, n);
    P.setFromTriplets(trip.begin(), trip.end());
    A += P;
  }
  A.makeCompressed();
  info.solver = d.essential == EssentialBC::lagrange ? "SparseLU (Lagrange multipliers)"
                                                     : "SparseLU (penalty)";
  info.unknowns = static_cast<int>(A.rows());
  info.nonzeros = A.nonZeros();
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(A);
  if (lu.info() != Eigen::Success)
    throw SingularError(fmt::format(
        "the global system ({} unknowns) is singular: {}. Typical causes: a support too small "
        "for the particle spacing (raise the dilation), or boundary conditions that do not fix "
        "the solution",
        info.unknowns, lu.lastErrorMessage()));
  Eigen::VectorXd x = lu.solve(b);
  const double bn = b.norm();
  info.residual = (A * x - b).norm() / (bn > 0 ? bn : 1.0);
  if (!x.allFinite() || !(info.residual < 1e-6))
    throw SingularError(fmt::format(
        "the global system ({} unknowns) is numerically singular: relative residual {:.2e} after "
        "the LU solve. Raise the dilation or use another boundary treatment",
        info.unknowns, info.residual));
  if (solved) *solved = std::move(A);
  return x.head(n);
}

std::string study_label(const CaseSpec& spec) {
  const std::string p = spec.method_params.to_string();
  return p.empty() ? spec.method : spec.method + " " + p;
}

CaseResult run_case(const Catalogue& catalogue, const CaseSpec& spec) {
  CaseResult r;
  r.spec = spec;
  const auto problem = catalogue.problems.create(spec.problem, spec.problem_params);
  r.method_params = catalogue.methods.resolve(spec.method, spec.method_params);
  const auto method = catalogue.methods.create(spec.method, spec.method_params);
  const Domain domain = problem->domain();

  double t0 = cpu_seconds();
  ParticleSet particles = uniform_line(domain, spec.nodes, spec.perturbation);
  Discretization d = method->discretize(domain, std::move(particles), problem->derivative_order());
  double t1 = cpu_seconds();
  r.cpu.setup = t1 - t0;
  const AssembledSystem sys = problem->assemble(d);
  double t2 = cpu_seconds();
  r.cpu.assembly = t2 - t1;
  Eigen::SparseMatrix<double> solved;
  const Eigen::VectorXd u = solve_constrained(sys, d, r.solve, &solved);
  r.cpu.solve = cpu_seconds() - t2;
  // A diagnostic for the report, outside the timed solve: the dense SVD costs far more than
  // the sparse LU it describes.
  r.solve.condition = condition_number(solved);

  r.method_description = d.description;
  r.h = d.particles.spacing;
  r.particles = d.particles.size();
  r.quadrature_points = d.quadrature.size();
  r.cells = d.quadrature.cells;
  r.errors = error_norms(*problem, d, u, common_error_rule(domain, spec.nodes));
  r.errors_paper = error_norms(*problem, d, u,
                               paper_error_rule(domain, d.particles, problem->paper_error_points()));
  r.headline = problem->headline(d, u);

  CaseFields& f = r.fields;
  f.x = d.particles.x.row(0).transpose();
  f.coefficient = u;
  f.volume = d.particles.volume;
  const ShapeTable at_nodes = d.trial_at(d.particles.x, 1);
  f.u_h = at_nodes.interpolate(u);
  f.du_h = at_nodes.interpolate_derivative(u);
  problem->exact(d.particles.x, f.u_exact, f.du_exact);
  const int ns = 1201;
  Eigen::MatrixXd xs(1, ns);
  for (int i = 0; i < ns; ++i)
    xs(0, i) = domain.lower[0] + (domain.upper[0] - domain.lower[0]) * i / (ns - 1);
  const ShapeTable dense = d.trial_at(xs, 1);
  f.sx = xs.row(0).transpose();
  f.su_h = dense.interpolate(u);
  f.sdu_h = dense.interpolate_derivative(u);
  problem->exact(xs, f.su, f.sdu);
  return r;
}

StudyResult run_study(const Catalogue& catalogue, const CaseSpec& base,
                      const std::vector<int>& nodes, const StudyProgress& progress) {
  StudyResult s;
  s.label = study_label(base);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (progress) progress(static_cast<int>(i), static_cast<int>(nodes.size()), nodes[i]);
    CaseSpec c = base;
    c.nodes = nodes[i];
    s.cases.push_back(run_case(catalogue, c));
  }
  s.rates = study_rates(s.cases, false);
  s.rates_paper = study_rates(s.cases, true);
  return s;
}

}  // namespace mfv
