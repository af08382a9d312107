/// Variationally consistent integration (Chen, Hillman & Rüter 2013) of linear order (one
/// constant correction of the test-function gradients per particle) or quadratic order (a
/// linear one, fixed by the second divergence identity too): see vci.hpp.
#include "methods/methods/vci.hpp"

#include <cmath>
#include <vector>

#include <Eigen/LU>

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

/// Σ_b w_b Ψ_I(x_b) n_b over every side of the box, on the method's boundary rule, and (if
/// `second`) Σ_b w_b Ψ_I(x_b) n_b x_bᵀ, row c·dim + e for entry (c, e).
Eigen::MatrixXd boundary_sums(const Discretization& d, Eigen::MatrixXd* second = nullptr) {
  const int dim = d.particles.dim, n = d.particles.size();
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(dim, n);
  if (second) *second = Eigen::MatrixXd::Zero(dim * dim, n);
  for (int side = 0; side < 2 * dim; ++side) {
    const IntegrationRule r = d.boundary_rule(side);
    const ShapeTable t = d.test_on(r);
    // Side s lies on axis s/2, the outward normal points down for even s, up for odd s.
    const int axis = side / 2;
    const double normal = side % 2 == 0 ? -1.0 : 1.0;
    for (int q = 0; q < r.size(); ++q)
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
        const double v = r.weights[q] * t.value[k] * normal;
        b(axis, t.index[k]) += v;
        if (second)
          for (int e = 0; e < dim; ++e) (*second)(axis * dim + e, t.index[k]) += v * r.points(e, q);
      }
  }
  return b;
}

/// Σ_q w_q [∇Ψ_I(x_q) x_qᵀ + Ψ_I(x_q) 𝟙] (row c·dim + e) and the moments of each particle's
/// support, m0, m1 (dim) and M2 (dim × dim, row-major), about x_I: (1 + dim + dim²) × n.
void second_sums(const Discretization& d, Eigen::MatrixXd& sums, Eigen::MatrixXd& moments) {
  const ShapeTable& t = d.test_q;
  const int dim = t.dim, n = d.particles.size();
  if (t.value.size() != static_cast<std::size_t>(t.entries()))
    throw std::logic_error("quadratic VCI needs the test functions' values");
  sums = Eigen::MatrixXd::Zero(dim * dim, n);
  moments = Eigen::MatrixXd::Zero(1 + dim + dim * dim, n);
  for (int q = 0; q < t.points(); ++q) {
    const double w = d.quadrature.weights[q];
    for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
      const int I = t.index[k];
      for (int c = 0; c < dim; ++c) {
        for (int e = 0; e < dim; ++e)
          sums(c * dim + e, I) += w * t.grad[k * dim + c] * d.quadrature.points(e, q);
        sums(c * dim + c, I) += w * t.value[k];
      }
      moments(0, I) += w;
      for (int e = 0; e < dim; ++e) {
        const double re = d.quadrature.points(e, q) - d.particles.x(e, I);
        moments(1 + e, I) += w * re;
        for (int f = 0; f < dim; ++f)
          moments(1 + dim + e * dim + f, I) +=
              w * re * (d.quadrature.points(f, q) - d.particles.x(f, I));
      }
    }
  }
}

std::string position_text(const Discretization& d, int I) {
  const int dim = d.particles.dim;
  return fmt::format("{}", fmt::join(d.particles.x.col(I).data(),
                                     d.particles.x.col(I).data() + dim, ", "));
}

class VciMethod final : public Method {
 public:
  VciMethod(std::unique_ptr<Method> inner, VciOrder order)
      : inner_(std::move(inner)), order_(order) {}

  FormalOrder formal_order() const override { return inner_->formal_order(); }

  Discretization discretize(const Domain& domain, ParticleSet particles, int order) const override {
    // Quadratic VCI needs the test functions' values as well as their gradients.
    Discretization d = inner_->discretize(domain, std::move(particles), order);
    apply_vci(d, order_);
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
  VciOrder order_;
};

}  // namespace

VciOrder vci_order_from(const std::string& name) {
  if (name == "true" || name == "linear") return VciOrder::linear;
  if (name == "quadratic") return VciOrder::quadratic;
  throw InputError(fmt::format("vci={} is not an order of VCI; use false, true (= linear), "
                               "linear or quadratic",
                               name));
}

Eigen::MatrixXd second_divergence_defect(const Discretization& d) {
  Eigen::MatrixXd b2, sums, moments;
  boundary_sums(d, &b2);
  second_sums(d, sums, moments);
  return b2 - sums;
}

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

void apply_vci(Discretization& d, VciOrder order) {
  Eigen::MatrixXd a;
  Eigen::VectorXd volume;
  domain_sums(d, a, &volume, nullptr);
  Eigen::MatrixXd b2;
  const Eigen::MatrixXd defect =
      boundary_sums(d, order == VciOrder::quadratic ? &b2 : nullptr) - a;
  const int dim = d.test_q.dim;
  if (order == VciOrder::quadratic) {
    Eigen::MatrixXd sums, moments;
    second_sums(d, sums, moments);
    const Eigen::MatrixXd defect2 = b2 - sums;
    const int n = d.particles.size(), m = 1 + dim;
    // Per particle: the moment matrix [m0 m1ᵀ; m1 M2] and, per component c, the right-hand
    // side (d1_c, d2_c· − x_I d1_c); the solution is (ξ_c, η_c·).
    std::vector<Eigen::MatrixXd> coef(n, Eigen::MatrixXd::Zero(dim, m));
    for (int I = 0; I < n; ++I) {
      if (moments(0, I) <= 0) {
        if (defect.col(I).norm() > 0 || defect2.col(I).norm() > 0)
          throw InputError(fmt::format(
              "vci=quadratic: particle {} at ({}) has no quadrature weight in its support, so "
              "its test gradient cannot be corrected; use a larger support (dmax) or vci=false",
              I, position_text(d, I)));
        continue;
      }
      Eigen::MatrixXd A(m, m);
      A(0, 0) = moments(0, I);
      for (int e = 0; e < dim; ++e) {
        A(0, 1 + e) = A(1 + e, 0) = moments(1 + e, I);
        for (int f = 0; f < dim; ++f) A(1 + e, 1 + f) = moments(1 + dim + e * dim + f, I);
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
      if (lu.rank() < m)
        throw InputError(fmt::format(
            "vci=quadratic: particle {} at ({}) has too few quadrature points in its support "
            "(moment matrix of rank {} < {}) to fix a linear correction; use a larger support "
            "(dmax), more quadrature points, or vci=linear",
            I, position_text(d, I), lu.rank(), m));
      for (int c = 0; c < dim; ++c) {
        Eigen::VectorXd rhs(m);
        rhs[0] = defect(c, I);
        for (int e = 0; e < dim; ++e)
          rhs[1 + e] = defect2(c * dim + e, I) - d.particles.x(e, I) * defect(c, I);
        coef[I].row(c) = lu.solve(rhs).transpose();
      }
    }
    ShapeTable& t = d.test_q;
    for (int q = 0; q < t.points(); ++q)
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
        const int I = t.index[k];
        for (int c = 0; c < dim; ++c) {
          double g = coef[I](c, 0);
          for (int e = 0; e < dim; ++e)
            g += coef[I](c, 1 + e) * (d.quadrature.points(e, q) - d.particles.x(e, I));
          t.grad[k * dim + c] += g;
        }
      }
    if (d.form == Form::galerkin) d.form = Form::petrov_galerkin;
    d.description += ", VCI (quadratic, Chen-Hillman-Ruter 2013)";
    return;
  }
  Eigen::MatrixXd xi = Eigen::MatrixXd::Zero(dim, d.particles.size());
  for (int I = 0; I < d.particles.size(); ++I) {
    if (volume[I] > 0) {
      xi.col(I) = defect.col(I) / volume[I];
    } else if (defect.col(I).norm() > 0) {
      throw InputError(fmt::format(
          "vci=true: particle {} at ({}) has no quadrature weight in its support, so its test "
          "gradient cannot be corrected; use a larger support (dmax) or vci=false",
          I, position_text(d, I)));
    }
  }
  ShapeTable& t = d.test_q;
  for (int k = 0; k < t.entries(); ++k)
    for (int c = 0; c < dim; ++c) t.grad[k * dim + c] += xi(c, t.index[k]);
  if (d.form == Form::galerkin) d.form = Form::petrov_galerkin;
  d.description += ", VCI (linear, Chen-Hillman-Ruter 2013)";
}

std::unique_ptr<Method> with_vci(std::unique_ptr<Method> inner, VciOrder order) {
  return std::make_unique<VciMethod>(std::move(inner), order);
}

}  // namespace mfv
