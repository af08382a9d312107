#include "methods/methods/method.hpp"

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

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

namespace {

class GalerkinMethod final : public Method {
 public:
  explicit GalerkinMethod(GalerkinRecipe r) : r_(std::move(r)) {}

  Discretization discretize(const Domain& domain, ParticleSet particles, int order) const override {
    if (particles.size() < r_.trial->minimum_support_count(particles.dim) + 1)
      throw InputError(fmt::format("{} particles are fewer than the basis needs ({}); use more "
                                   "nodes",
                                   particles.size(),
                                   r_.trial->minimum_support_count(particles.dim) + 1));
    particles.dilation.setConstant(r_.dilation_over_spacing * particles.spacing);
    Discretization d;
    d.quadrature = r_.integration->rule(domain, particles);
    d.trial = r_.trial;
    d.test = r_.test ? r_.test : r_.trial;
    d.form = r_.test ? Form::petrov_galerkin : Form::galerkin;
    d.trial_q = r_.trial->evaluate(particles, d.quadrature.points, order);
    d.test_q = r_.test ? r_.test->evaluate(particles, d.quadrature.points, order) : d.trial_q;
    d.essential = r_.essential;
    d.penalty = r_.penalty;
    d.description = r_.description;
    d.particles = std::move(particles);
    return d;
  }

 private:
  GalerkinRecipe r_;
};

}  // namespace

std::unique_ptr<Method> make_galerkin_method(GalerkinRecipe recipe) {
  return std::make_unique<GalerkinMethod>(std::move(recipe));
}

ParamSchema common_galerkin_schema(int default_gauss_points) {
  return {
      ParamSpec::choice("bc", "lagrange", {"lagrange", "penalty"},
                        "essential boundary conditions: Lagrange multipliers or penalty"),
      ParamSpec::positive("penalty", 1e8, "penalty factor relative to the largest stiffness entry"),
      ParamSpec::count("quad", default_gauss_points, 1, "Gauss points per background cell"),
  };
}

EssentialBC essential_from(const Params& p) {
  return p.text("bc") == "penalty" ? EssentialBC::penalty : EssentialBC::lagrange;
}

}  // namespace mfv
