#include "analyses/static_solve.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "analyses/analysis.hpp"
#include "analyses/norms.hpp"
#include "analyses/petsc_solver.hpp"
#include "analyses/report_section.hpp"
#include "analyses/solver.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

double condition_number(const Eigen::SparseMatrix<double>& A) {
  if (A.rows() > kMaxConditionSize) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd sv = Eigen::BDCSVD<Eigen::MatrixXd>(Eigen::MatrixXd(A)).singularValues();
  return sv[sv.size() - 1] > 0 ? sv[0] / sv[sv.size() - 1]
                               : std::numeric_limits<double>::infinity();
}

namespace {

/// solver=petsc with Lagrange multipliers: the augmented Lagrangian's penalty over the
/// largest stiffness diagonal, and the most multiplier updates before giving up.
constexpr double kAugmentedPenalty = 1e4;
constexpr int kMaxMultiplierUpdates = 50;

/// The PETSc solve's set-up common to penalty and elimination: block size, coordinates for
/// the rigid-body modes, tolerance and options.
PetscSolveSetup petsc_setup(const AssembledSystem& sys, const Discretization& d,
                            const SolverChoice& solver, bool symmetric) {
  PetscSolveSetup s;
  s.symmetric = symmetric;
  const int nc = sys.components;
  // Blocks of whole particles when the unknowns are the particles' (no enrichment).
  if (nc > 0 && sys.K.rows() == static_cast<Eigen::Index>(d.particles.size()) * nc) {
    s.components = nc;
    if (d.particles.x.rows() == nc) s.coordinates = d.particles.x;
  }
  s.rtol = solver.ksp_rtol;
  s.options = solver.petsc_options;
  return s;
}

/// K with the fixed unknowns' rows and columns replaced by the diagonal PETSc leaves there
/// (for the condition-number diagnostic of small systems).
Eigen::SparseMatrix<double> eliminated(const Eigen::SparseMatrix<double>& K,
                                       const PetscSolveSetup& s) {
  std::vector<char> fixed(K.rows(), 0);
  for (int r : s.fixed) fixed[r] = 1;
  std::vector<Eigen::Triplet<double>> trip;
  for (int k = 0; k < K.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, k); it; ++it)
      if (!fixed[it.row()] && !fixed[it.col()])
        trip.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
  for (int r : s.fixed) trip.emplace_back(r, r, s.fixed_diagonal);
  Eigen::SparseMatrix<double> out(K.rows(), K.cols());
  out.setFromTriplets(trip.begin(), trip.end(), [](double, double b) { return b; });
  return out;
}

}  // namespace

Eigen::VectorXd solve_constrained(const AssembledSystem& sys, const Discretization& d,
                                  SolveInfo& info, Eigen::SparseMatrix<double>* solved,
                                  const SolverChoice& solver) {
  check_solver_choice(solver);
  const bool petsc = solver.kind == "petsc";
  const int n = static_cast<int>(sys.K.rows());
  const int nc = sys.components;
  const int nb = static_cast<int>(sys.constraint_values.size());
  // G_(J·nc + c, b) = N_J(x_b) for the component c of constraint b; for particle-value methods
  // (SPH, RLM) the constraint fixes the particle's own unknown.
  ShapeTable g;
  if (d.particle_values) {
    std::vector<int> at = sys.constraint_particles;
    if (at.empty())
      for (int bq = 0; bq < nb; ++bq) {
        // The particle sitting on the constraint point (1D ends).
        int found = -1;
        for (int J = 0; J < d.particles.size() && found < 0; ++J)
          if ((d.particles.x.col(J) - sys.constraint_points.col(bq)).norm() <=
              1e-12 * (1 + sys.constraint_points.col(bq).norm()))
            found = J;
        if (found < 0)
          throw InputError(fmt::format(
              "{} fixes particle values, but no particle lies on the essential boundary point "
              "{}: use a particle set with particles on the boundary",
              d.description, bq));
        at.push_back(found);
      }
    for (int b = 0; b < nb; ++b) {
      g.index.push_back(at[b]);
      g.value.push_back(1.0);
      g.offsets.push_back(g.entries());
    }
  } else {
    g = d.trial_at(sys.constraint_points, 0);
  }
  // Petrov–Galerkin: the reactions enter the test equations through the test functions
  // (∫ δu·λ dΓ with δu = Σ Ψ_I δu_I), the constraints act on the trial field.
  const bool petrov = !d.particle_values && d.form == Form::petrov_galerkin;
  const ShapeTable gt = petrov ? d.test->evaluate(d.particles, sys.constraint_points, 0) : g;
  auto comp = [&](int b) { return sys.constraint_components.empty() ? 0 : sys.constraint_components[b]; };
  using Trip = Eigen::Triplet<double>;
  std::vector<Trip> trip;
  Eigen::SparseMatrix<double> A;
  // The largest stiffness diagonal: the scale of the constraint rows and of the penalty.
  const double kmax = n > 0 ? sys.K.diagonal().cwiseAbs().maxCoeff() : 0.0;
  Eigen::VectorXd b;
  // K + β Gt Gᵀ and f + β Gt g: the penalized system (Gt = G for Galerkin forms).
  auto penalized = [&](double beta, Eigen::SparseMatrix<double>& Ap, Eigen::VectorXd& bp) {
    Ap = sys.K;
    bp = sys.f;
    trip.clear();
    for (int bq = 0; bq < nb; ++bq)
      for (int k = gt.offsets[bq]; k < gt.offsets[bq + 1]; ++k) {
        const int row = gt.index[k] * nc + comp(bq);
        bp[row] += beta * gt.value[k] * sys.constraint_values[bq];
        for (int l = g.offsets[bq]; l < g.offsets[bq + 1]; ++l)
          trip.emplace_back(row, g.index[l] * nc + comp(bq), beta * gt.value[k] * g.value[l]);
      }
    Eigen::SparseMatrix<double> P(n, n);
    P.setFromTriplets(trip.begin(), trip.end());
    Ap += P;
    Ap.makeCompressed();
  };
  if (petsc && d.particle_values) {
    // Elimination of the fixed particle values: the system keeps K's size and symmetry.
    PetscSolveSetup setup = petsc_setup(sys, d, solver, false);
    for (int bq = 0; bq < nb; ++bq) setup.fixed.push_back(g.index[bq] * nc + comp(bq));
    setup.fixed_diagonal = kmax > 0 ? kmax : 1.0;
    const Eigen::VectorXd rhs = eliminated_rhs(sys.K, sys.f, setup.fixed, sys.constraint_values,
                                               setup.fixed_diagonal);
    Eigen::VectorXd x = petsc_solve(sys.K, rhs, setup, info);
    info.solver += " (particle values fixed by elimination)";
    if (solved && n <= kMaxConditionSize) *solved = eliminated(sys.K, setup);
    return x;
  }
  if (petsc && d.essential == EssentialBC::lagrange) {
    // The multiplier solution without the saddle point, which CG and AMG cannot take:
    // augmented Lagrangian (iterated penalty; Fortin & Glowinski 1983, ch. 1) on
    // K + β Gt Gᵀ with a moderate β,
    //   (K + β Gt Gᵀ) u_k = f + β Gt g − Gt λ_k,   λ_(k+1) = λ_k + β (Gᵀ u_k − g),
    // whose fixed point is K u + Gt λ = f, Gᵀ u = g. A penalty of 1e8 × the diagonal makes
    // the Krylov solve the bottleneck (efg-ni, 8,514 unknowns: 6,290 CG iterations against
    // 364 at 1e2) while 1e4 costs as little as 1e2 and cuts the constraint violation ~1e3-fold
    // per update.
    const double beta = kAugmentedPenalty * std::max(kmax, 1.0);
    Eigen::SparseMatrix<double> A;
    Eigen::VectorXd b0;
    penalized(beta, A, b0);
    Eigen::SparseMatrix<double> Gm(n, nb), Gtm(n, nb);
    {
      std::vector<Trip> tg, tgt;
      for (int bq = 0; bq < nb; ++bq) {
        for (int k = g.offsets[bq]; k < g.offsets[bq + 1]; ++k)
          tg.emplace_back(g.index[k] * nc + comp(bq), bq, g.value[k]);
        for (int k = gt.offsets[bq]; k < gt.offsets[bq + 1]; ++k)
          tgt.emplace_back(gt.index[k] * nc + comp(bq), bq, gt.value[k]);
      }
      Gm.setFromTriplets(tg.begin(), tg.end());
      Gtm.setFromTriplets(tgt.begin(), tgt.end());
    }
    const PetscSolveSetup setup = petsc_setup(sys, d, solver, d.form == Form::galerkin);
    PetscSolver ps(A, setup);
    // PETSc holds its own copy: the Eigen one is kept only for the condition diagnostic.
    if (!solved || n > kMaxConditionSize) A = Eigen::SparseMatrix<double>();
    // The residual of the multiplier system as solve_sparse sees it (constraint rows scaled
    // by the largest diagonal, s): ‖(f − K u − Gt λ, s (g − Gᵀ u))‖ / ‖(f, s g)‖.
    const double sc = kmax > 0 ? kmax : 1.0;
    const double kkt_norm = std::sqrt(sys.f.squaredNorm() +
                                      sc * sc * sys.constraint_values.squaredNorm());
    const double scale = kkt_norm > 0 ? kkt_norm : 1.0;
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(nb), u;
    info.iterations = 0;
    int updates = 0;
    double kkt = NAN;
    for (; updates < kMaxMultiplierUpdates; ++updates) {
      const Eigen::VectorXd rhs = b0 - Gtm * lambda;
      // The inner tolerance relative to the multiplier system's right-hand side, not to
      // rhs (which β Gt g dominates).
      u = ps.solve(rhs, info, u, scale / std::max(rhs.norm(), 1e-300));
      const Eigen::VectorXd violation = Gm.transpose() * u - sys.constraint_values;
      lambda += beta * violation;
      kkt = std::sqrt((sys.f - sys.K * u - Gtm * lambda).squaredNorm() +
                      sc * sc * violation.squaredNorm()) /
            scale;
      if (kkt <= solver.ksp_rtol * 10) break;
    }
    info.residual = kkt;
    const int solves = std::min(updates + 1, kMaxMultiplierUpdates);
    info.solver += fmt::format(
        " (Lagrange multipliers by augmented Lagrangian: K + β G Gᵀ, β = {:g} × the largest "
        "diagonal, {} multiplier update{})",
        kAugmentedPenalty, solves, solves == 1 ? "" : "s");
    if (!(kkt <= solver.ksp_rtol * 10))
      throw SingularError(fmt::format(
          "{}: the multiplier iterations did not converge on the global system ({} unknowns): "
          "relative residual {:.2e} after {} updates (ksp_rtol {:.1e}). Try bc=penalty, a "
          "looser ksp_rtol, or solver=direct",
          info.solver, n, kkt, solves, solver.ksp_rtol));
    if (solved && A.rows() > 0) *solved = std::move(A);
    return u;
  }
  if (!petsc && (d.essential == EssentialBC::lagrange || d.particle_values)) {
    // [K G; Gᵀ 0] [u; λ] = [f; g]: λ_b is the reaction at x_b.
    A.resize(n + nb, n + nb);
    trip.reserve(sys.K.nonZeros() + 2 * g.entries());
    for (int k = 0; k < sys.K.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(sys.K, k); it; ++it)
        trip.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
    // Scale the constraint rows like the stiffness so the pivots stay balanced.
    const double s = kmax > 0 ? kmax : 1.0;
    for (int bq = 0; bq < nb; ++bq) {
      for (int k = g.offsets[bq]; k < g.offsets[bq + 1]; ++k)
        trip.emplace_back(n + bq, g.index[k] * nc + comp(bq), s * g.value[k]);
      for (int k = gt.offsets[bq]; k < gt.offsets[bq + 1]; ++k)
        trip.emplace_back(gt.index[k] * nc + comp(bq), n + bq, s * gt.value[k]);
    }
    A.setFromTriplets(trip.begin(), trip.end());
    b.resize(n + nb);
    b << sys.f, s * sys.constraint_values;
  } else {
    // K + β G Gᵀ, β = penalty × the largest diagonal entry of K.
    penalized(d.penalty * std::max(kmax, 1.0), A, b);
  }
  A.makeCompressed();
  if (petsc) {
    // bc=penalty: the method's own penalty system (β = its penalty × the largest diagonal).
    // Galerkin forms with the symmetric G Gᵀ are symmetric positive definite.
    const PetscSolveSetup setup = petsc_setup(sys, d, solver, d.form == Form::galerkin);
    PetscSolver ps(A, setup);
    if (!solved || n > kMaxConditionSize) A = Eigen::SparseMatrix<double>();
    info.iterations = 0;
    Eigen::VectorXd x = ps.solve(b, info);
    info.solver += fmt::format(" (penalty β = {:g} × the largest diagonal)", d.penalty);
    if (solved && A.rows() > 0) *solved = std::move(A);
    return x;
  }
  Eigen::VectorXd x = solve_sparse(A, b, solver.kind, info);
  info.solver += d.particle_values                      ? " (particle values fixed)"
                 : d.essential == EssentialBC::lagrange ? " (Lagrange multipliers)"
                                                        : " (penalty)";
  if (solved) *solved = std::move(A);
  return x.head(n);
}

namespace {

/// 1D: the fields at the particles and a dense sampling of the line (plots, VTK).
void sample_line(const BoundaryValueProblem& problem, const Discretization& d, const Eigen::VectorXd& u,
                 CaseFields& f) {
  const Domain domain = d.domain;
  f.x = d.particles.x.row(0).transpose();
  f.coefficient = u;
  f.volume = d.particles.volume;
  const ShapeTable at_nodes = d.trial_at(d.particles.x, 1);
  f.u_h = at_nodes.interpolate(u);
  f.du_h = at_nodes.interpolate_derivative(u);
  Eigen::MatrixXd u_exact, du_exact;
  problem.exact_field(d.particles.x, u_exact, du_exact);
  f.u_exact = u_exact.row(0).transpose();
  f.du_exact = du_exact.row(0).transpose();
  const int ns = 1201;
  Eigen::MatrixXd xs(1, ns);
  for (int i = 0; i < ns; ++i)
    xs(0, i) = domain.lower[0] + (domain.upper[0] - domain.lower[0]) * i / (ns - 1);
  const ShapeTable dense = d.trial_at(xs, 1);
  f.sx = xs.row(0).transpose();
  f.su_h = dense.interpolate(u);
  f.sdu_h = dense.interpolate_derivative(u);
  problem.exact_field(xs, u_exact, du_exact);
  f.su = u_exact.row(0).transpose();
  f.sdu = du_exact.row(0).transpose();
}

/// 2D: displacement and stress at the particles and the method's own points. Where the
/// particles are quadrature points (nodal, stress-point rules) the method's own values and
/// gradients are used; otherwise the trial field's.
void sample_particles(const BoundaryValueProblem& problem, const Discretization& d, const Eigen::VectorXd& u,
                      CaseFields& f) {
  const int nc = problem.components();
  const int n = d.particles.size();
  f.points = d.particles.x;
  f.coefficient = u;
  f.volume = d.particles.volume;
  f.stress_names = problem.flux_names();
  Eigen::MatrixXd qv, qg, g, ue, ge;
  d.trial_q.field(u, nc, qv, qg);
  if (d.quadrature.nodal_points == n) {
    f.disp_h = qv.leftCols(n);
    g = qg.leftCols(n);
  } else {
    d.trial_at(d.particles.x, 1).field(u, nc, f.disp_h, g);
  }
  problem.exact_field(d.particles.x, f.disp_exact, ge);
  f.stress_h = problem.flux(g);
  f.stress_exact = problem.flux(ge);
  f.q_points = d.quadrature.points;
  f.q_stress_h = problem.flux(qg);
  problem.exact_field(d.quadrature.points, ue, ge);
  f.q_stress_exact = problem.flux(ge);
}


class StaticSolve final : public Analysis {
 public:
  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const BoundaryValueProblem*>(&problem) != nullptr;
  }
  explicit StaticSolve(const Params& p)
      : solver_{p.text("solver"), p.number("ksp_rtol"), p.text("petsc_options")} {
    check_solver_choice(solver_);
  }

  void run(const AnalysisContext& c, CaseResult& r) const override {
    const auto& problem = definition_of<BoundaryValueProblem>(
        c, "static-solve", "a weak form (a BoundaryValueProblem's assemble)");
    Discretization d = discretize_case(problem, c, r);
    StaticSolveData& out = r.emplace<StaticSolveData>();
    const double t1 = cpu_seconds();
    const AssembledSystem sys = problem.assemble(d);
    const double t2 = cpu_seconds();
    r.cpu.assembly = t2 - t1;
    Eigen::SparseMatrix<double> solved;
    const Eigen::VectorXd u = solve_constrained(sys, d, out.solve, &solved, solver_);
    r.cpu.solve = cpu_seconds() - t2;
    // A diagnostic for the report, outside the timed solve: the dense SVD costs far more than
    // the sparse LU it describes.
    out.solve.condition = solved.rows() > 0 ? condition_number(solved)
                                            : std::numeric_limits<double>::quiet_NaN();

    const Domain domain = problem.domain();
    r.errors = error_norms(problem, d, u, problem.common_error_rule(d.particles));
    r.errors_paper =
        problem.errors_on_method_rule()
            ? method_rule_error_norms(problem, d, u)
            : error_norms(problem, d, u,
                          paper_error_rule(domain, d.particles, problem.paper_error_points()));
    r.headline = problem.headline(d, u);
    if (domain.dim == 1 && r.components == 1)
      sample_line(problem, d, u, out.fields);
    else
      sample_particles(problem, d, u, out.fields);
  }

  std::string page(const Registries& plugins, const ReportSection& section,
                   const std::string& title, const std::filesystem::path& dir,
                   bool vtk) const override {
    return vector_field(section) ? write_elasticity_section(plugins, section, title, dir, vtk)
                                 : write_scalar_page(plugins, section, title, dir, vtk);
  }
  std::string summary(const Problem& problem, const ReportSection& section) const override {
    return ranking_block(section.studies, problem.resolution_name(),
                         vector_field(section) ? "relative L2 displacement error"
                                               : "relative L2 error");
  }
  std::string page_contents(bool vtk) const override {
    return fmt::format("every resolution's errors, rates and CPU, plots, the findings, published "
                       "values{}",
                       vtk ? " and VTK files" : "");
  }
  bool section_per_problem_params() const override { return true; }
  MeasuredErrors measured_errors() const override {
    return {{"l2", "h1_seminorm", "h1", "energy"}, true, ""};
  }
  int print_case(const CaseResult& r, std::ostream& out) const override {
    const SolveInfo& s = r.data<StaticSolveData>().solve;
    out << fmt::format("L2 error  {:.6e}  (relative {:.6e})\n", r.errors.l2, r.errors.l2_rel);
    out << fmt::format("H1 semi   {:.6e}  (relative {:.6e})\n", r.errors.h1_semi, r.errors.h1_semi_rel);
    out << fmt::format("H1 full   {:.6e}  (relative {:.6e})\n", r.errors.h1, r.errors.h1_rel);
    if (r.components > 1) {
      out << fmt::format("energy    {:.6e}  (relative {:.6e})\n", r.errors.energy,
                         r.errors.energy_rel);
      out << fmt::format("own rule  L2 relative {:.6e}, energy relative {:.6e} ({} points, {} "
                         "stress points)\n",
                         r.errors_paper.l2_rel, r.errors_paper.energy_rel, r.quadrature_points,
                         r.stress_points);
    } else {
      out << fmt::format("paper-rule L2 {:.6e}, H1 semi {:.6e}\n", r.errors_paper.l2,
                         r.errors_paper.h1_semi);
    }
    for (const auto& [k, v] : r.headline) out << fmt::format("{:<22} {:.6f}\n", k, v);
    out << fmt::format("CPU       setup {:.4f} s, assembly {:.4f} s, solve {:.4f} s\n", r.cpu.setup,
                       r.cpu.assembly, r.cpu.solve);
    if (!s.converged.empty())
      out << fmt::format("solver    {}: {} unknowns, {} nonzeros, {} iterations ({}), true "
                         "residual {:.1e}, condition {:.2e}\n",
                         s.solver, s.unknowns, s.nonzeros, s.iterations, s.converged, s.residual,
                         s.condition);
    else
      out << fmt::format("solver    {}: {} unknowns, {} nonzeros, fill {}, residual {:.1e}, "
                         "rcond {:.1e}, condition {:.2e}\n",
                         s.solver, s.unknowns, s.nonzeros, s.fill, s.residual, s.rcond,
                         s.condition);
    return 0;
  }

 private:
  /// 2D displacements (components > 1) get the elasticity page, scalar fields the line page.
  static bool vector_field(const ReportSection& section) {
    return !section.studies.empty() && !section.studies.front().cases.empty() &&
           section.studies.front().cases.front().components > 1;
  }

  SolverChoice solver_;
};

ParamSchema static_solve_schema() {
  return {
      ParamSpec::choice("solver", "auto", {std::begin(kSolverChoices), std::end(kSolverChoices)},
                        "linear solver: auto (UMFPACK LU, BiCGSTAB + ILUT if it fails), direct "
                        "(UMFPACK only), iterative (BiCGSTAB + ILUT), petsc (PETSc CG or GMRES "
                        "with GAMG on every rank of mpirun; essential conditions by penalty, "
                        "particle values by elimination)"),
      ParamSpec::positive("ksp_rtol", 1e-10,
                          "solver=petsc: relative tolerance on the true residual "
                          "‖b − A x‖/‖b‖, in (0, 1)"),
      ParamSpec::choice("petsc_options", "", {},
                        "solver=petsc: PETSc options, e.g. '-ksp_type gmres -pc_type hypre "
                        "-ksp_monitor', read after mfv's defaults and the PETSC_OPTIONS "
                        "environment variable (they override both)"),
  };
}

}  // namespace

void register_static_solve(AnalysisRegistry& r) {
  r.add("static-solve",
        "a boundary value problem's weak form on the method's tables, essential conditions, "
        "the sparse solve, errors on the common and the paper's rules",
        static_solve_schema(), [](const Params& p) { return std::make_unique<StaticSolve>(p); });
}

}  // namespace mfv
