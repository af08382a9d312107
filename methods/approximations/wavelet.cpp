/// Multi-scale RKPM (004 I §5, eqs 5.3-5.8): a reproducing-kernel low band plus M bands of
/// Mexican-hat wavelets ψ(z) = (1 - 2z²) e^{-z²} (minus half the second derivative of the
/// Gaussian scaling function), centred on the particles.
///
/// Reading used (the paper leaves the discrete form open, eq 5.5): with the RK interpolant
/// R[f](x) = Σ_K N_K(x) f(x_K), the shape functions are
///   N_J(x) = N^RK_J(x) + Σ_m Σ_a c_{maJ} (ψ_ma(x) - R[ψ_ma](x)),
/// c_{maJ} = ψ̂_ma(x_J) ΔV_J the quadrature of the window transform ⟨u, ψ_ma⟩ (eq 4.7a), where
/// ψ̂ is ψ corrected by a Gaussian-weighted linear term so that Σ_J ψ̂(x_J) ΔV_J {1, x_J} = 0.
/// The wavelet bands then vanish on linear fields and N_J keeps linear reproduction. Band m
/// has dilation a_m = 2^{m-1} · wscale · Δx (wavelets scaled to the particle spacing, 004 I §6).
#include <cmath>

#include <fmt/format.h>

#include "methods/approximations/register.hpp"

namespace mfv {

namespace {

double mexican_hat(double z, double& d1, double& d2) {
  const double e = std::exp(-z * z);
  d1 = (-6 * z + 4 * z * z * z) * e;
  d2 = (-6 + 24 * z * z - 8 * z * z * z * z) * e;
  return (1 - 2 * z * z) * e;
}

class WaveletApproximation final : public Approximation {
 public:
  WaveletApproximation(std::shared_ptr<const Approximation> low, int bands, double wscale)
      : low_(std::move(low)), bands_(bands), wscale_(wscale) {}

  int minimum_support_count(int dim) const override { return low_->minimum_support_count(dim); }
  int reproduction_order() const override { return low_->reproduction_order(); }

  ShapeTable evaluate(const ParticleSet& p, const Eigen::MatrixXd& points, int order) const override {
    if (p.dim != 1) throw InputError("the wavelet approximation is implemented in 1D");
    const int n = p.size(), nq = static_cast<int>(points.cols());
    const ShapeTable rk_q = low_->evaluate(p, points, order);
    const ShapeTable rk_nodes = low_->evaluate(p, p.x, 0);
    // Dense accumulation: N(q, J) and derivatives (1D problems have at most a few hundred
    // particles; the wavelet supports overlap most of them anyway).
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(nq, n), D1 = N, D2 = N;
    auto scatter = [&](const ShapeTable& t, Eigen::MatrixXd& v, Eigen::MatrixXd& g, Eigen::MatrixXd& h) {
      for (int q = 0; q < t.points(); ++q)
        for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
          v(q, t.index[k]) += t.value[k];
          if (t.order >= 1) g(q, t.index[k]) += t.grad[k];
          if (t.order >= 2) h(q, t.index[k]) += t.hess[k];
        }
    };
    scatter(rk_q, N, D1, D2);
    Eigen::MatrixXd Rn = Eigen::MatrixXd::Zero(n, n), unused1 = Rn, unused2 = Rn;
    scatter(rk_nodes, Rn, unused1, unused2);  // Rn(I, K) = N^RK_K(x_I)
    Eigen::MatrixXd Rq = N, Rq1 = D1, Rq2 = D2;  // RK tables at the evaluation points

    const Eigen::VectorXd xs = p.x.row(0).transpose();
    for (int m = 1; m <= bands_; ++m) {
      const double am = std::ldexp(wscale_ * p.spacing, m - 1);
      const double norm = 1 / std::sqrt(am);
      // Analysis weights c(a, J) = ψ̂_ma(x_J) ΔV_J, and ψ_ma at particles and points.
      Eigen::MatrixXd C(n, n), PsiNodes(n, n), Psi(nq, n), Psi1(nq, n), Psi2(nq, n);
      for (int a = 0; a < n; ++a) {
        Eigen::VectorXd psi(n), g(n);
        double d1, d2;
        for (int J = 0; J < n; ++J) {
          const double z = (xs[J] - xs[a]) / am;
          psi[J] = norm * mexican_hat(z, d1, d2);
          g[J] = std::exp(-z * z);
        }
        PsiNodes.col(a) = psi;
        // Correct ψ̂ = ψ - g (β0 + β1 z) so that its discrete moments 0 and 1 vanish.
        Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
        Eigen::Vector2d b = Eigen::Vector2d::Zero();
        for (int J = 0; J < n; ++J) {
          const double z = (xs[J] - xs[a]) / am;
          const Eigen::Vector2d pz(1, z);
          A += p.volume[J] * g[J] * pz * pz.transpose();
          b += p.volume[J] * psi[J] * pz;
        }
        const Eigen::Vector2d beta = A.ldlt().solve(b);
        for (int J = 0; J < n; ++J) {
          const double z = (xs[J] - xs[a]) / am;
          C(a, J) = (psi[J] - g[J] * (beta[0] + beta[1] * z)) * p.volume[J];
        }
        for (int q = 0; q < nq; ++q) {
          const double z = (points(0, q) - xs[a]) / am;
          Psi(q, a) = norm * mexican_hat(z, d1, d2);
          Psi1(q, a) = norm * d1 / am;
          Psi2(q, a) = norm * d2 / (am * am);
        }
      }
      // G(q, a) = ψ_ma(x_q) - Σ_K N^RK_K(x_q) ψ_ma(x_K)
      const Eigen::MatrixXd G = Psi - Rq * PsiNodes;
      N += G * C;
      if (order >= 1) D1 += (Psi1 - Rq1 * PsiNodes) * C;
      if (order >= 2) D2 += (Psi2 - Rq2 * PsiNodes) * C;
    }

    ShapeTable t;
    t.dim = 1;
    t.order = order;
    for (int q = 0; q < nq; ++q) {
      for (int J = 0; J < n; ++J) {
        if (N(q, J) == 0 && D1(q, J) == 0 && D2(q, J) == 0) continue;
        t.index.push_back(J);
        t.value.push_back(N(q, J));
        if (order >= 1) t.grad.push_back(D1(q, J));
        if (order >= 2) t.hess.push_back(D2(q, J));
      }
      t.offsets.push_back(t.entries());
    }
    return t;
  }

 private:
  std::shared_ptr<const Approximation> low_;
  int bands_;
  double wscale_;
};

/// M, at most 16: band m has dilation 2^(m-1)·wscale·Δx, so band 16 already spans 32,768
/// spacings; more bands only multiply the work (bands=1e9 used to run for ever).
ParamSpec wavelet_bands_spec() {
  ParamSpec s = ParamSpec::count("bands", 2, 0, "number of wavelet dilations M (at most 16)");
  s.max = 16;
  return s;
}

}  // namespace

void register_wavelet_approximation(ApproximationRegistry& r, const KernelRegistry& k) {
  r.add("wavelet", "multi-scale RKPM: Gaussian RK low band + Mexican-hat wavelet bands (004 I §5)",
        {wavelet_bands_spec(),
         ParamSpec::positive("wscale", 1.0, "wavelet dilation of the first band over dx")},
        [&k](const Params& p) {
          std::shared_ptr<const Approximation> low = std::make_unique<CorrectedKernelApproximation>(
              k.create("gaussian"),
              CorrectedKernelOptions{.basis_order = 1, .volume_weighted = true}, "rkpm");
          return std::make_unique<WaveletApproximation>(low, p.integer("bands"), p.number("wscale"));
        });
}

}  // namespace mfv
