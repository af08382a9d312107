/// Variationally consistent integration of linear order (Chen, Hillman & Rüter 2013): one
/// constant correction of the test-function gradients per particle (see vci.hpp).
#include "methods/methods/vci.hpp"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

/// Σ_q w_q ∇Ψ_I(x_q) (dim × n) and, if `volume`, Σ_{q ∋ I} w_q; optionally Σ_q w_q |∇Ψ_I|.
void domain_sums(const Discretization& d, Eigen::MatrixXd& grad_sum, Eigen::VectorXd* volume,
                 Eigen::VectorXd* magnitude) {
  const ShapeTable& t = d.test_q;
  const int dim = t.dim, n = d.particles.size();
  if (t.grad.size() != static_cast<std::size_t>(t.entries()) * dim)
    throw std::logic_error("VCI needs the test functions' gradient table");
  if (t.points() != d.quadrature.size())
    throw std::logic_error("VCI: the test table and the quadrature rule differ in size");
  grad_sum = Eigen::MatrixXd::Zero(dim, n);
  if (volume) *volume = Eigen::VectorXd::Zero(n);
  if (magnitude) *magnitude = Eigen::VectorXd::Zero(n);
  for (int q = 0; q < t.points(); ++q) {
    const double w = d.quadrature.weights[q];
    for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
      const int I = t.index[k];
      double m2 = 0;
      for (int c = 0; c < dim; ++c) {
        grad_sum(c, I) += w * t.grad[k * dim + c];
        m2 += t.grad[k * dim + c] * t.grad[k * dim + c];
      }
      if (volume) (*volume)[I] += w;
      if (magnitude) (*magnitude)[I] += std::abs(w) * std::sqrt(m2);
    }
  }
}

/// Σ_b w_b Ψ_I(x_b) n_b over every side of the box, on the method's boundary rule.
Eigen::MatrixXd boundary_sums(const Discretization& d) {
  const int dim = d.particles.dim, n = d.particles.size();
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(dim, n);
  for (int side = 0; side < 2 * dim; ++side) {
    const IntegrationRule r = d.boundary_rule(side);
    const ShapeTable t = d.test_on(r);
    // Side s lies on axis s/2, the outward normal points down for even s, up for odd s.
    const int axis = side / 2;
    const double normal = side % 2 == 0 ? -1.0 : 1.0;
    for (int q = 0; q < r.size(); ++q)
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k)
        b(axis, t.index[k]) += r.weights[q] * t.value[k] * normal;
  }
  return b;
}

class VciMethod final : public Method {
 public:
  explicit VciMethod(std::unique_ptr<Method> inner) : inner_(std::move(inner)) {}

  Discretization discretize(const Domain& domain, ParticleSet particles, int order) const override {
    Discretization d = inner_->discretize(domain, std::move(particles), order);
    apply_vci(d);
    return d;
  }

  void retabulate(Discretization&, int) const override {
    throw InputError(
        "vci=true corrects the test gradients against the boundary of the reference box; "
        "with an Eulerian kernel (tables recomputed on the moved particles) that boundary is "
        "no longer the body's: use frame=lagrangian or vci=false");
  }

 private:
  std::unique_ptr<Method> inner_;
};

}  // namespace

Eigen::MatrixXd divergence_defect(const Discretization& d) {
  Eigen::MatrixXd a;
  domain_sums(d, a, nullptr, nullptr);
  return boundary_sums(d) - a;
}

DefectSummary summarize_defect(const Discretization& d, const Eigen::MatrixXd& defect) {
  Eigen::MatrixXd a;
  Eigen::VectorXd magnitude;
  domain_sums(d, a, nullptr, &magnitude);
  DefectSummary s;
  double sum2 = 0;
  int counted = 0;
  for (int I = 0; I < defect.cols(); ++I) {
    if (magnitude[I] <= 0) continue;
    const double r = defect.col(I).norm() / magnitude[I];
    sum2 += r * r;
    ++counted;
    if (r > s.max_relative || s.worst_particle < 0) {
      s.max_relative = r;
      s.worst_particle = I;
    }
  }
  s.rms_relative = counted > 0 ? std::sqrt(sum2 / counted) : 0.0;
  return s;
}

void apply_vci(Discretization& d) {
  Eigen::MatrixXd a;
  Eigen::VectorXd volume;
  domain_sums(d, a, &volume, nullptr);
  const Eigen::MatrixXd defect = boundary_sums(d) - a;
  const int dim = d.test_q.dim;
  Eigen::MatrixXd xi = Eigen::MatrixXd::Zero(dim, d.particles.size());
  for (int I = 0; I < d.particles.size(); ++I) {
    if (volume[I] > 0) {
      xi.col(I) = defect.col(I) / volume[I];
    } else if (defect.col(I).norm() > 0) {
      throw InputError(fmt::format(
          "vci=true: particle {} at ({}) has no quadrature weight in its support, so its test "
          "gradient cannot be corrected; use a larger support (dmax) or vci=false",
          I, fmt::join(d.particles.x.col(I).data(), d.particles.x.col(I).data() + dim, ", ")));
    }
  }
  ShapeTable& t = d.test_q;
  for (int k = 0; k < t.entries(); ++k)
    for (int c = 0; c < dim; ++c) t.grad[k * dim + c] += xi(c, t.index[k]);
  if (d.form == Form::galerkin) d.form = Form::petrov_galerkin;
  d.description += ", VCI (linear, Chen-Hillman-Ruter 2013)";
}

std::unique_ptr<Method> with_vci(std::unique_ptr<Method> inner) {
  return std::make_unique<VciMethod>(std::move(inner));
}

}  // namespace mfv
