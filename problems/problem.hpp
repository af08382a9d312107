/// Problems of the catalogue as definitions: domain, particles, material, loading, exact or
/// reference solution, the published values and the findings, and which analyses apply
/// (analyses/ runs them). One file per catalogue entry; no runner, report or clock here.
#pragma once
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "methods/core/registry.hpp"
#include "methods/materials/linear_elastic.hpp"
#include "methods/methods/method.hpp"
#include "reports/convergence.hpp"
#include "reports/plot.hpp"

namespace mfv {

/// A linear system from a weak form, with essential conditions u(x_b) = g_b still to impose.
struct AssembledSystem {
  Eigen::SparseMatrix<double> K;      ///< unknowns interleaved: (u_x, u_y) of particle 0, ...
  Eigen::VectorXd f;
  int components = 1;                 ///< field components per particle
  Eigen::MatrixXd constraint_points;  ///< dim × nb
  Eigen::VectorXd constraint_values;  ///< g_b
  std::vector<int> constraint_components;  ///< component of each constraint (empty: all 0)
  /// The particle at each constraint point, for methods whose unknowns are particle values
  /// (empty when the points are not particles).
  std::vector<int> constraint_particles;
};

/// A value printed in a paper, with what it must be matched against.
struct PublishedValue {
  std::string source;     ///< "004 II Table 1"
  std::string quantity;   ///< "peak du/dx at x=3", "error u"
  std::string method;     ///< method name it belongs to
  Params method_params;   ///< parameters that must match (subset)
  int nodes = 0;          ///< resolution
  double value = 0;
  std::string note;       ///< e.g. "norm not stated"
  /// Problem parameters the value belongs to (e.g. loading=gaussian); a case matches when
  /// it set each of them to the same value or left it at its default.
  Params problem_params;
  /// Relative tolerance on ours/published for the verdict (problems/comparison.hpp); the
  /// ledger row of this value (suites/ledger.toml) states the same number.
  double tolerance = 0.05;
};

/// One refinement study as the findings see it (built by the reports from a StudyResult).
struct StudySummary {
  std::string method;            ///< registered name
  std::string label;             ///< "sph radius=4.5"
  Params params;                 ///< as given (unresolved): what the user chose to set
  Params resolved;               ///< the method's parameters resolved, with defaults
  int finest_nodes = 0, finest_particles = 0, resolutions = 0;
  double l2_rate = NAN, energy_rate = NAN;          ///< common rule
  double l2_rel_finest = NAN, energy_rel_finest = NAN;
  Params problem_params;  ///< as given
  /// The problem's and its analysis's parameters resolved, with defaults (frame, sigma ...):
  /// what a finding compares, so it never re-defaults a parameter by hand.
  Params problem_resolved;
  /// Headline values of each resolution, coarsest first (transient verdicts read them).
  std::vector<std::map<std::string, double>> headlines;
  /// Per resolution, coarsest first: spacing h and relative errors on the common rule.
  std::vector<double> h, l2_rel, energy_rel;
  /// What the errors do under refinement (reports/convergence.hpp): pairwise rates, fitted
  /// rate and the trend. A finding that says "converges" asks these, not the slope alone.
  ConvergenceJudgement l2_trend, energy_trend;
};

/// A number a finding decides on (issue 44): its values at the resolutions of the study it
/// reads, coarsest first, so that the ledger can say how sure it is (reports/uncertainty.hpp).
/// A transient finding reads one resolution: one value, whose uncertainty comes from the
/// ledger row's converged check (the same number at a finer step or more particles).
struct FindingNumber {
  std::string name;               ///< "sph (lagrangian): front rms", unique within a verdict
  std::vector<double> h, values;  ///< refinement parameter and value per level
  /// The formal order, used with two levels only (F_s = 3); NaN: none is known.
  double order = NAN;
};

/// What a finding says about our run.
struct Verdict {
  std::string status;  ///< "reproduced", "not reproduced", "partly", "not run"
  std::string ours;    ///< the measured numbers behind it
  std::vector<FindingNumber> numbers = {};  ///< the numbers the status was decided on
};

/// A qualitative statement of a paper, checked against our studies by `check`.
struct Finding {
  std::string source;  ///< "001 §9.1"
  std::string claim;
  std::string criterion;  ///< how we decide, printed beside the verdict
  std::function<Verdict(const std::vector<StudySummary>&)> check;
  /// Stable key of the finding within its problem ("kbm-si-rate"), named by ledger rows.
  std::string id;
};

/// Resolutions per suite level.
enum class Level { quick, standard, full };

/// What every problem is: a domain, resolutions, the analyses that apply to it, and what the
/// papers published about it.
class Problem {
 public:
  virtual ~Problem() = default;
  virtual Domain domain() const = 0;
  /// The analyses (analyses/analysis.hpp) that apply, by registered name; the first is the
  /// default of a case that names none.
  virtual std::vector<std::string> analyses() const = 0;
  /// Parameters of `analysis` this problem sets differently from the analysis's own
  /// defaults (e.g. a smaller time-step safety); a case's own values override them.
  virtual Params analysis_defaults(const std::string& analysis) const { return {}; }
  /// Node counts of a refinement study.
  virtual std::vector<int> resolutions(Level level) const = 0;
  /// What `nodes` counts, for reports ("nodes", "particles across the depth").
  virtual std::string resolution_name() const { return "nodes"; }
  /// Published qualitative findings, each with the check that gives our verdict.
  virtual std::vector<Finding> findings() const { return {}; }
  /// Headline quantities the report compares side by side in one compact table, one row per
  /// study, before the table of everything measured (empty: no such table).
  virtual std::vector<std::string> comparison_headlines() const { return {}; }
  /// Exact values of the headline quantities (for the reports).
  virtual std::map<std::string, double> headline_exact() const { return {}; }
  virtual std::vector<PublishedValue> published() const { return {}; }
  /// What the reports say about the published values: known misprints, ambiguous readings
  /// and the best explanation of a gap (Markdown paragraphs). Numbers stay in the tables.
  virtual std::vector<std::string> published_notes() const { return {}; }
  /// A Markdown table over all the studies of a report section (e.g. every method's CPU with
  /// its ratios to the others and to the paper's), shown before the per-case tables; "": none.
  virtual std::string studies_table(const std::vector<StudySummary>& studies) const {
    return "";
  }
  /// Charts over all the studies of a report section (e.g. a bar chart of CPU per method and
  /// kernel), drawn by the report beside its own plots; empty: none.
  virtual std::vector<PlotSpec> studies_plots(const std::vector<StudySummary>& studies) const {
    return {};
  }
};

/// A problem solved on particles of its domain (static or transient): the particle sets, the
/// field's components and the derivatives the method must provide.
class ParticleProblem : public Problem {
 public:
  /// Highest derivative of the shape functions the weak form needs.
  virtual int derivative_order() const { return 1; }
  /// Field components per particle (1 scalar, 2 for 2D displacements).
  virtual int components() const { return 1; }
  /// The particles of resolution `nodes` (1D: nodes on the line; 2D problems say what it
  /// counts), perturbed by `perturbation` of the spacing.
  virtual ParticleSet particles(int nodes, double perturbation) const;
  /// The domain the method discretizes at resolution `nodes`: domain() unless the particle
  /// set reaches beyond it by a number of spacings (the hydrostatic column's layers of wall
  /// particles around its water), which cut cells and Voronoi volumes need to contain.
  virtual Domain discretized_domain(int nodes) const {
    (void)nodes;
    return domain();
  }
};

/// A static boundary value problem, run by the `static-solve` analysis: its weak form
/// (assemble), exact solution and the norms its errors are measured in.
class BoundaryValueProblem : public ParticleProblem {
 public:
  std::vector<std::string> analyses() const override { return {"static-solve"}; }
  /// Exact field (components × n) and gradient (components·dim × n; row c·dim + d holds
  /// ∂u_c/∂x_d) at the columns of x.
  virtual void exact_field(const Eigen::MatrixXd& x, Eigen::MatrixXd& u,
                           Eigen::MatrixXd& grad) const = 0;
  /// Energy density σ(∇v):ε(∇v) of gradient columns (the energy norm's integrand, 001 eq 74);
  /// the default |∇v|² is the H1 seminorm's (unit diffusion).
  virtual Eigen::VectorXd energy_density(const Eigen::MatrixXd& grad) const {
    return grad.colwise().squaredNorm().transpose();
  }
  /// Stress (flux) of gradient columns and the names of its rows, for VTK files.
  virtual Eigen::MatrixXd flux(const Eigen::MatrixXd& grad) const { return grad; }
  virtual std::vector<std::string> flux_names() const { return {"du"}; }
  /// The rule of the common error norms at a resolution (the same for every method).
  virtual IntegrationRule common_error_rule(const ParticleSet& particles) const;
  /// true: the "paper" errors are integrated with each method's own quadrature, values and
  /// gradients (001 §9.1); false: the paper's Gauss points between particles (004 II §7).
  virtual bool errors_on_method_rule() const { return false; }
  /// Gauss points per cell between particles used by the paper for error norms.
  virtual int paper_error_points() const { return 12; }
  virtual AssembledSystem assemble(const Discretization& d) const = 0;
  /// Problem-specific headline quantities of a solution (name → value), e.g. peak u'.
  virtual std::map<std::string, double> headline(const Discretization& d,
                                                 const Eigen::VectorXd& u) const {
    return {};
  }
};

/// A boundary value problem for a scalar field on a line (004's 1D problems): the exact
/// solution and its derivative, which exact_field returns as 1 × n rows.
class ScalarProblem : public BoundaryValueProblem {
 public:
  /// Exact solution and its derivative at the columns of x.
  virtual void exact(const Eigen::MatrixXd& x, Eigen::VectorXd& u, Eigen::VectorXd& du) const = 0;
  void exact_field(const Eigen::MatrixXd& x, Eigen::MatrixXd& u,
                   Eigen::MatrixXd& grad) const override;
};

using ProblemRegistry = Registry<Problem>;

/// A 2D linear elasticity boundary value problem on a rectangle: material, tractions on sides,
/// prescribed displacements on sides (001 eqs 44–50 in the static, linear case).
struct ElasticityBVP {
  LinearElastic material;
  /// Traction t(x) (2 × n from 2 × n points) per loaded side (0 left, 1 right, 2 bottom, 3 top).
  std::map<int, std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>> tractions;
  /// Prescribed displacement u(x) (2 × n) per clamped side.
  std::map<int, std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>> displacements;
  /// Body force b(x) per unit volume (2 × n), integrated on the method's domain rule with its
  /// test functions (∫ N^test_I b dΩ); empty: none.
  std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)> body_force;
  /// Clamped sides whose clamp covers the supports: besides the particles on the side, every
  /// particle whose support reaches the side is held at the prescribed displacement (at its own
  /// position). Default: only the particles on the side.
  std::set<int> clamp_supports;
};
/// K = Σ_q w_q B^test(x_q)ᵀ D B^trial(x_q) from the method's gradient tables (any of 001
/// Table 1's methods), f from the tractions on the method's boundary rule, and the
/// constraints at the boundary particles' points (or the particles, for particle values).
AssembledSystem assemble_elasticity(const Discretization& d, const ElasticityBVP& bvp);

/// Shared 1D assembly of ∫ (k w' u' + c w u' + τ R(w) R(u)) - ∫ w f (+ τ R(w) f) used by both
/// 1D problems; R(v) = -v'' + c v' is the residual operator of the stabilized form (004 I eq 6.3).
struct ScalarForm1D {
  double diffusion = 1.0;
  double advection = 0.0;
  double tau = 0.0;
};
AssembledSystem assemble_scalar_1d(const Discretization& d, const ScalarForm1D& form,
                                   const std::function<double(double)>& source);

/// −∇·(k ∇u) = f in 2D on the method's tables: K_IJ = Σ_q w_q k ∇N^test_I · ∇N^trial_J,
/// f_I = Σ_q w_q N^test_I f, and u = g held at the particles of every side of the box (their
/// projections onto the side; the particle itself for particle-value methods).
AssembledSystem assemble_scalar_2d(const Discretization& d, double k,
                                   const std::function<double(double, double)>& source,
                                   const std::function<double(double, double)>& dirichlet);

}  // namespace mfv
