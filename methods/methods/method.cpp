#include "methods/methods/method.hpp"

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/kernels/kernel_choice.hpp"
#include "methods/methods/vci.hpp"

namespace mfv {

void refuse_enrichment(const Discretization& d, const std::string& user) {
  if (d.enriched_unknowns > 0)
    throw InputError(fmt::format("the method's crack enrichment adds {} unknowns, which {} "
                                 "cannot handle; set crack=none, or use the analysis "
                                 "enriched-bar for the cracked bar (method: {})",
                                 d.enriched_unknowns, user, d.description));
}

Eigen::MatrixXd Discretization::gradient(const Eigen::VectorXd& u) const {
  const int dim = trial_q.dim;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(dim, trial_q.points());
  for (int q = 0; q < trial_q.points(); ++q)
    for (int k = trial_q.offsets[q]; k < trial_q.offsets[q + 1]; ++k)
      for (int d = 0; d < dim; ++d) g(d, q) += trial_q.grad[k * dim + d] * u[trial_q.index[k]];
  return g;
}

Eigen::VectorXd Discretization::internal_force(const Eigen::MatrixXd& flux) const {
  const int dim = test_q.dim;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(particles.size());
  for (int q = 0; q < test_q.points(); ++q)
    for (int k = test_q.offsets[q]; k < test_q.offsets[q + 1]; ++k) {
      double v = 0;
      for (int d = 0; d < dim; ++d) v += test_q.grad[k * dim + d] * flux(d, q);
      f[test_q.index[k]] += quadrature.weights[q] * v;
    }
  return f;
}

ShapeTable Discretization::trial_at(const Eigen::MatrixXd& points, int order) const {
  return trial->evaluate(particles, points, order);
}

IntegrationRule Discretization::boundary_rule(int side) const {
  if (!integration) throw std::logic_error("discretization without an integration scheme");
  return integration->boundary_rule(domain, particles, side);
}

ShapeTable Discretization::test_on(const IntegrationRule& b) const {
  if (!particle_values) return test->evaluate(particles, b.points, 0);
  ShapeTable t;
  t.dim = particles.dim;
  for (int q = 0; q < b.size(); ++q) {
    if (b.cell.size() != static_cast<std::size_t>(b.size()) || b.cell[q] < 0 ||
        b.cell[q] >= particles.size())
      throw std::logic_error("a boundary rule for a particle method must name its particles");
    t.index.push_back(b.cell[q]);
    t.value.push_back(1.0);
    t.offsets.push_back(t.entries());
  }
  return t;
}

namespace {

/// What every method does first: dilations (a fixed one, or a multiple of the spacing or of
/// each particle's local spacing), the integration rule and the recipe's boundary treatment.
Discretization prepare(const Domain& domain, ParticleSet& particles,
                       const std::shared_ptr<const IntegrationScheme>& integration,
                       double dilation, double over_spacing, EssentialBC essential, double penalty,
                       const std::string& description) {
  if (dilation <= 0 && particles.local_spacing.size() > 0) {
    // A set whose spacing varies (an annulus: Δr or r Δθ) scales each support by its own.
    if (particles.local_spacing.size() != particles.size())
      throw InputError(fmt::format("the particle set has {} local spacings for {} particles; "
                                   "give one per particle or none",
                                   particles.local_spacing.size(), particles.size()));
    particles.dilation = over_spacing * particles.local_spacing;
  } else {
    particles.dilation.setConstant(dilation > 0 ? dilation : over_spacing * particles.spacing);
  }
  Discretization d;
  d.domain = domain;
  d.integration = integration;
  d.quadrature = integration->rule(domain, particles);
  d.essential = essential;
  d.penalty = penalty;
  d.description = description;
  return d;
}

class GalerkinMethod final : public Method {
 public:
  explicit GalerkinMethod(GalerkinRecipe r) : r_(std::move(r)) {}
  FormalOrder formal_order() const override { return r_.formal; }

  Discretization discretize(const Domain& domain, ParticleSet particles, int order) const override {
    if (particles.size() < r_.trial->minimum_support_count(particles.dim) + 1)
      throw InputError(fmt::format("{} particles are fewer than the basis needs ({}); use more "
                                   "nodes",
                                   particles.size(),
                                   r_.trial->minimum_support_count(particles.dim) + 1));
    Discretization d = prepare(domain, particles, r_.integration, r_.dilation,
                               r_.dilation_over_spacing, r_.essential, r_.penalty, r_.description);
    d.trial = r_.trial;
    d.test = r_.test ? r_.test : r_.trial;
    d.form = r_.test ? Form::petrov_galerkin : Form::galerkin;
    d.particles = std::move(particles);
    retabulate(d, order);
    return d;
  }

  void retabulate(Discretization& d, int order) const override {
    d.trial_q = r_.trial->evaluate(d.particles, d.quadrature.points, order);
    d.test_q = r_.test ? r_.test->evaluate(d.particles, d.quadrature.points, order) : d.trial_q;
  }

  void retabulate(Discretization& d, int order, Retabulation& c) const override {
    // Trial and test tables are at the same points: one set of marks counts a point once.
    DegenerateMarks marks;
    DegenerateMarks* degenerate = c.degenerate_fallback ? &marks : nullptr;
    r_.trial->evaluate_into(d.particles, d.quadrature.points, order, c.at_points, c.threads,
                            d.trial_q, degenerate);
    if (r_.test)
      r_.test->evaluate_into(d.particles, d.quadrature.points, order, c.at_points, c.threads,
                             d.test_q, degenerate);
    else
      d.test_q = d.trial_q;
    c.degenerate_points = marks.count();
  }

 private:
  GalerkinRecipe r_;
};

class ParticleMethod final : public Method {
 public:
  explicit ParticleMethod(ParticleRecipe r) : r_(std::move(r)) {}
  FormalOrder formal_order() const override { return r_.formal; }

  Discretization discretize(const Domain& domain, ParticleSet particles, int order) const override {
    Discretization d = prepare(domain, particles, r_.integration, r_.dilation,
                               r_.dilation_over_spacing, r_.essential, r_.penalty, r_.description);
    d.particles = std::move(particles);
    r_.build(d, order, nullptr);
    return d;
  }

  void retabulate(Discretization& d, int order) const override { r_.build(d, order, nullptr); }
  void retabulate(Discretization& d, int order, Retabulation& c) const override {
    r_.build(d, order, &c);
  }

 private:
  ParticleRecipe r_;
};

}  // namespace

std::unique_ptr<Method> make_galerkin_method(GalerkinRecipe recipe) {
  return std::make_unique<GalerkinMethod>(std::move(recipe));
}

std::unique_ptr<Method> make_particle_method(ParticleRecipe recipe) {
  return std::make_unique<ParticleMethod>(std::move(recipe));
}

FormalOrder formal_order_of(const Params& p, bool linear_trial, bool linear_tests,
                            bool consistent_quadrature, const std::string& why) {
  const std::string vci = p.has("vci") ? p.text("vci") : "false";
  if (!linear_trial)
    return {NAN, NAN, "the trial gradient is not linearly consistent: no order to declare"};
  if (vci == "quadratic")
    return {2, 1, "linear consistency, quadratic VCI meets both divergence identities (Chen, "
                  "Hillman & Ruter 2013)"};
  if ((vci == "true" || vci == "linear") && linear_tests)
    return {2, 1, "linear consistency, linear VCI with linearly complete test functions (Chen, "
                  "Hillman & Ruter 2013)"};
  if (consistent_quadrature) return {2, 1, why};
  return {NAN, NAN, why};
}

std::unique_ptr<Method> vci_if_asked(const Params& p, std::unique_ptr<Method> method) {
  if (!p.has("vci") || p.text("vci") == "false") return method;
  return with_vci(std::move(method), vci_order_from(p.text("vci")));
}

ParamSchema particle_method_schema(const KernelRegistry& kernels, bool essential_choice) {
  ParamSchema s = kernel_choice(kernels, "cubic-spline", "kernel W (001 eq 14)");
  for (auto& spec : ParamSchema{
      ParamSpec::positive("dmax", 2.4,
                          "support radius over particle spacing; 2.4 for the 001 particle "
                          "methods, whose cantilever and rod-pulse baselines were measured with "
                          "it (004's 1D efg keeps its 2.0)"),
      ParamSpec::number("radius", 0.0,
                        "fixed support radius (length units) for every resolution, 001 Fig. 7; "
                        "0: dmax times the spacing"),
      ParamSpec::choice("vci", "false", {"false", "true", "linear", "quadratic"},
                        "variationally consistent integration (Chen, Hillman & Ruter 2013, not "
                        "in 001): true = linear, one constant correction of the test gradients "
                        "per particle so the quadrature satisfies the divergence identity; "
                        "quadratic, a linear correction that satisfies the second identity too "
                        "(the one a linear stress needs: kbm's Shepard tests converge with it, "
                        "issue 43)"),
  })
    s.push_back(std::move(spec));
  if (essential_choice) {
    s.push_back(ParamSpec::choice("bc", "lagrange", {"lagrange", "penalty"},
                                  "essential boundary conditions on the MLS trial functions: "
                                  "Lagrange multipliers or penalty"));
    s.push_back(ParamSpec::positive("penalty", 1e8,
                                    "penalty factor relative to the largest stiffness entry"));
  }
  return s;
}

std::string support_text(const Params& p) {
  return p.number("radius") > 0 ? fmt::format("radius {}", p.number("radius"))
                                 : fmt::format("{} dx", p.number("dmax"));
}

void set_particle_dilation(const Params& p, const KernelRegistry& kernels, double& over_spacing,
                           double& absolute) {
  const auto W = make_kernel(kernels, p);
  over_spacing = dilation_for_radius(*W, p.number("dmax"));
  if (p.number("radius") < 0)
    throw InputError(fmt::format("parameter 'radius' must be >= 0, got {}", p.number("radius")));
  absolute = p.number("radius") > 0 ? dilation_for_radius(*W, p.number("radius")) : 0.0;
}

ParamSchema common_galerkin_schema(int default_gauss_points) {
  return {
      ParamSpec::choice("bc", "lagrange", {"lagrange", "penalty"},
                        "essential boundary conditions: Lagrange multipliers or penalty"),
      ParamSpec::positive("penalty", 1e8, "penalty factor relative to the largest stiffness entry"),
      capped(ParamSpec::count("quad", default_gauss_points, 1,
                              "Gauss points per 1D background cell (at most 64); 2D cells take "
                              "n_Q = ceil(sqrt(m)) + 2 with m particles in the cell (001 eq 66)"),
             64),
  };
}

EssentialBC essential_from(const Params& p) {
  return p.text("bc") == "penalty" ? EssentialBC::penalty : EssentialBC::lagrange;
}

}  // namespace mfv
