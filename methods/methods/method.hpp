/// Methods: named combinations of trial/test approximation, integration scheme and essential
/// boundary treatment. Following 001 Table 1, every method is read as two operators on its
/// integration points: the gradient of the field (deformation gradient) and the internal force
/// assembled from fluxes (stresses). Static solvers, explicit dynamics and stability analyses
/// all go through these two, so a method plugs into every analysis at once.
#pragma once
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "methods/approximations/approximation.hpp"
#include "methods/core/registry.hpp"
#include "methods/integration/integration.hpp"
#include "methods/kernels/register.hpp"
#include "methods/neighbours.hpp"
#include "methods/particles.hpp"

namespace mfv {

/// How the discrete equations are formed (001 §4).
enum class Form {
  galerkin,         ///< test = trial functions (Bubnov–Galerkin)
  petrov_galerkin,  ///< test functions differ (e.g. Shepard tests with corrected trials, KBM)
  collocation       ///< equations at particles (SPH): test functions are Dirac deltas
};

/// Essential boundary enforcement for non-interpolating approximations.
enum class EssentialBC { lagrange, penalty };

/// Everything a solver or analysis needs from a method on one particle set.
struct Discretization {
  ParticleSet particles;
  IntegrationRule quadrature;
  std::shared_ptr<const Approximation> trial, test;
  ShapeTable trial_q;  ///< trial shape functions at the quadrature points
  ShapeTable test_q;   ///< test shape functions there (same table for Galerkin)
  Form form = Form::galerkin;
  EssentialBC essential = EssentialBC::lagrange;
  double penalty = 1e8;       ///< penalty factor relative to the stiffness diagonal
  std::string description;    ///< resolved components, printed in reports
  /// The unknowns are the particle displacements themselves (SPH, RLM: collocation on the
  /// particles): essential conditions fix them directly, tractions act on the particles of
  /// the loaded side, and the method's own values at a particle are its unknowns.
  bool particle_values = false;
  int enriched_unknowns = 0;  ///< unknowns after the particles' (xefg enrichment dofs)
  /// Set by a method whose gradient table is not the trial approximation's and is less
  /// consistent than it: symmetrized SPH (001 eq 25) differentiates constants exactly but not
  /// linear fields, so 0; unset when consistency() is the trial approximation's order.
  std::optional<int> gradient_consistency;
  Domain domain;
  std::shared_ptr<const IntegrationScheme> integration;  ///< for boundary rules

  /// Σ_J ∂N_J/∂x (x_q) u_J at every quadrature point: dim rows × nq (for a scalar field:
  /// the field gradient; for a vector field applied per component, the deformation gradient).
  Eigen::MatrixXd gradient(const Eigen::VectorXd& u) const;
  /// f_I = Σ_q w_q ∂N^test_I/∂x (x_q) · flux_q: the internal force from fluxes/stresses.
  Eigen::VectorXd internal_force(const Eigen::MatrixXd& flux) const;
  /// Values of the trial field at arbitrary points (errors, plots, VTK). For particle_values
  /// methods this is a reconstruction (see the method's description), not the method itself.
  ShapeTable trial_at(const Eigen::MatrixXd& points, int order) const;
  /// The integration scheme's rule on side s of the domain (tractions), consistent with the
  /// domain rule.
  IntegrationRule boundary_rule(int side) const;
  /// Test function values on a boundary rule: the test approximation there, or δ at the
  /// rule's particles (`cell`) for particle_values methods.
  ShapeTable test_on(const IntegrationRule& boundary) const;
  /// The highest degree of polynomial fields whose gradients the gradient table reproduces
  /// exactly on any particle set (001 §3): 1, linear consistency, is what the patch test
  /// needs; -1 when not even constants are reproduced (uncorrected kernel sums).
  int consistency() const {
    return gradient_consistency ? *gradient_consistency : trial->reproduction_order();
  }
};

/// Throws InputError when `d` carries crack-enrichment unknowns (xefg), which `user` (e.g.
/// "problem 'laplace-tanh'", "the time-step analysis") cannot handle: the message names the
/// method, the count and the fixes (crack=none, or the enriched-bar analysis).
void refuse_enrichment(const Discretization& d, const std::string& user);

/// What the recomputations of an Eulerian kernel keep from one call to the next (explicit
/// dynamics owns one per engine and hands it to Method::retabulate): Verlet lists for the two
/// point sets tables are evaluated at, the kernel tables the particle methods build their
/// gradients from (storage reused, no allocation once warm), and the OpenMP threads to spread
/// the points over. The tables come out as a fresh retabulation's, bit for bit.
struct Retabulation {
  explicit Retabulation(double skin = 0, int threads = 1)
      : at_particles(skin), at_points(skin), threads(threads) {}
  NeighbourLists at_particles;  ///< points: the particles themselves (sph, rlm)
  NeighbourLists at_points;     ///< points: the integration rule's (Galerkin, kbm)
  ShapeTable kernel_table;      ///< sph's kernel sums, kbm's MLS values
  int threads = 1;
  /// Where a support is degenerate (too few or collinear particles for the correction):
  /// false throws SingularError as before; true falls back (documented per method).
  bool degenerate_fallback = false;
  /// Points that took the fallback at the last recomputation (0 when the option is off).
  long degenerate_points = 0;
  long rebuilds() const { return at_particles.rebuilds() + at_points.rebuilds(); }
};

/// The order of accuracy a method declares on a smooth solution (issue 46): the exponents of
/// h in the L2 and H1-seminorm errors that its theory gives, with the source; NaN when it
/// declares none (then `source` says why: e.g. nodal sums that miss the divergence identity).
struct FormalOrder {
  double l2 = NAN, h1 = NAN;
  std::string source;
  bool declared() const { return std::isfinite(l2) || std::isfinite(h1); }
};

class Method {
 public:
  virtual ~Method() = default;
  /// The formal order of accuracy on a smooth solution (issue 46); undeclared by default.
  virtual FormalOrder formal_order() const {
    return {NAN, NAN, "the method declares no formal order"};
  }
  /// Sets particle dilations from the method's parameters, builds the quadrature and the
  /// shape function tables up to derivative `order` (the weak form's need).
  virtual Discretization discretize(const Domain& domain, ParticleSet particles,
                                    int order) const = 0;
  /// Eulerian kernels (001 Table 2): recomputes the tables of `d` at its current particle
  /// positions and volumes and its current quadrature points and weights (the caller moves
  /// them), keeping the dilations, the rule's points and the method's composition.
  virtual void retabulate(Discretization& d, int order) const = 0;
  /// The same with what the previous recomputations kept (neighbour lists, table storage,
  /// threads); the tables equal retabulate(d, order)'s. With cache.degenerate_fallback a
  /// degenerate support falls back instead of throwing: the corrected-kernel approximations
  /// to Shepard functions (zero row where empty), rlm to B = I, kbm to a = I (zero row
  /// where empty); cache.degenerate_points counts the points that did. The default ignores
  /// the cache (no fallback, degenerate_points 0).
  virtual void retabulate(Discretization& d, int order, Retabulation& cache) const {
    cache.degenerate_points = 0;
    retabulate(d, order);
  }
};

using MethodRegistry = Registry<Method>;

/// A Galerkin (or Petrov–Galerkin) method assembled from registered parts.
struct GalerkinRecipe {
  std::shared_ptr<const Approximation> trial;
  std::shared_ptr<const Approximation> test;  ///< null: Bubnov–Galerkin
  std::shared_ptr<const IntegrationScheme> integration;
  double dilation_over_spacing = 1.0;  ///< a_J = this × Δx
  double dilation = 0;                 ///< when > 0: a_J = this, whatever Δx (001 Fig. 7)
  EssentialBC essential = EssentialBC::lagrange;
  double penalty = 1e8;
  std::string description;
  FormalOrder formal;  ///< the order it declares (formal_order_of helps)
};

std::unique_ptr<Method> make_galerkin_method(GalerkinRecipe recipe);

/// Parameters every Galerkin method shares: boundary enforcement and quadrature.
ParamSchema common_galerkin_schema(int default_gauss_points);
EssentialBC essential_from(const Params& p);

/// Builds the tables of a method whose operators are not plain shape functions at a rule
/// (SPH, RLM, KBM): given the particles (dilations set) and the rule, fills trial_q, test_q,
/// trial, test, form and particle_values of the discretization; with a cache (Eulerian
/// recomputations) through the approximations' evaluate_into, otherwise evaluate. With
/// cache->degenerate_fallback it hands the table builders a DegenerateMarks and sets
/// cache->degenerate_points to its count (to 0 without the option).
using TableBuilder = std::function<void(Discretization&, int order, Retabulation* cache)>;

/// A particle method of 001 Table 1: dilation rule, integration scheme and table builder.
struct ParticleRecipe {
  std::shared_ptr<const IntegrationScheme> integration;
  double dilation_over_spacing = 1.0;
  double dilation = 0;  ///< when > 0: constant support whatever the spacing (001 Fig. 7)
  EssentialBC essential = EssentialBC::lagrange;
  double penalty = 1e8;
  TableBuilder build;
  std::string description;
  FormalOrder formal;  ///< the order it declares (formal_order_of helps)
};

/// The formal order of a method with a linearly consistent trial gradient (or not), given how
/// its quadrature meets the divergence identities: quadratic VCI meets both (L2 2, H1 1:
/// Chen, Hillman & Rüter 2013); linear VCI meets the first, enough with linearly complete
/// test functions; otherwise `consistent_quadrature` (Gauss cells: source `why`) or none
/// (`why` says why). `p` is the method's parameters (its `vci`, if it has one).
FormalOrder formal_order_of(const Params& p, bool linear_trial, bool linear_tests,
                            bool consistent_quadrature, const std::string& why);
std::unique_ptr<Method> make_particle_method(ParticleRecipe recipe);
/// `method` wrapped in variationally consistent integration (methods/methods/vci.hpp) when the
/// parameters say vci=true (particle_method_schema declares it), else `method` itself.
std::unique_ptr<Method> vci_if_asked(const Params& p, std::unique_ptr<Method> method);

/// Parameters of the 2D particle methods: kernel, support dmax·Δx or a fixed radius, and
/// (for MLS trial functions) the essential boundary treatment.
ParamSchema particle_method_schema(const KernelRegistry& kernels, bool essential_choice);
/// "radius 4.5" or "2.4 dx": the support of a particle method, for descriptions.
std::string support_text(const Params& p);
/// a_J from dmax·Δx (or the fixed radius) over the kernel's own support.
void set_particle_dilation(const Params& p, const KernelRegistry& kernels, double& over_spacing,
                           double& absolute);

}  // namespace mfv
