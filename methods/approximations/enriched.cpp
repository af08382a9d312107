/// Crack enrichment decorator and the crack-split Gauss cells of the extended EFG (003 §3,
/// eqs 8-10); see enriched.hpp for the formulas.
#include "methods/approximations/enriched.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

/// Branch function k (0..3) and its gradient at x (003 eq 8's B_K, the LEFM tip basis). The
/// crack runs along +y up to the tip, so the local frame has x' = y − y_tip ahead of the tip
/// and y' = x_crack − x; θ = atan2(y', x') is ±π on the faces, which no Gauss point touches.
void branch(const Crack& c, int k, const double* x, double& f, double g[2]) {
  const double xl = x[1] - c.tip, yl = c.position - x[0];
  const double r = std::max(std::hypot(xl, yl), 1e-300);
  const double th = std::atan2(yl, xl);
  const double sr = std::sqrt(r), s2 = std::sin(th / 2), c2 = std::cos(th / 2);
  const double st = std::sin(th), ct = std::cos(th);
  double fr = 0, ft = 0;  // ∂f/∂r, ∂f/∂θ
  switch (k) {
    case 0: f = sr * s2; fr = s2 / (2 * sr); ft = sr * c2 / 2; break;
    case 1: f = sr * c2; fr = c2 / (2 * sr); ft = -sr * s2 / 2; break;
    case 2: f = sr * s2 * st; fr = s2 * st / (2 * sr); ft = sr * (c2 / 2 * st + s2 * ct); break;
    default: f = sr * c2 * st; fr = c2 * st / (2 * sr); ft = sr * (-s2 / 2 * st + c2 * ct); break;
  }
  const double dxl = fr * ct - ft * st / r, dyl = fr * st + ft * ct / r;
  g[0] = -dyl;  // ∂/∂x = −∂/∂y'
  g[1] = dxl;   // ∂/∂y = ∂/∂x'
}

}  // namespace

std::vector<Enrichment> crack_enrichments(const Crack& crack, const ParticleSet& particles,
                                          double kernel_support) {
  std::vector<Enrichment> out;
  for (int I = 0; I < particles.size(); ++I) {
    const double R = particles.dilation[I] * kernel_support;
    const double dx = std::abs(particles.x(0, I) - crack.position);
    if (!(dx < R)) continue;  // the crack line misses the support
    if (crack.dim == 1 || !crack.has_tip()) {
      out.push_back({I, EnrichmentKind::step});
      continue;
    }
    // The chord of the support disk on the crack line spans y_I ± w.
    const double w = std::sqrt(R * R - dx * dx), y = particles.x(1, I);
    if (crack.tip <= y - w) continue;  // the crack ends below the support
    if (crack.tip >= y + w) {
      out.push_back({I, EnrichmentKind::step});  // W_b: completely cut
    } else if (crack.branch) {
      for (auto k : {EnrichmentKind::branch1, EnrichmentKind::branch2, EnrichmentKind::branch3,
                     EnrichmentKind::branch4})
        out.push_back({I, k});  // W_s: the tip lies inside the support
    }
  }
  return out;
}

EnrichedApproximation::EnrichedApproximation(std::shared_ptr<const Approximation> base,
                                             Crack crack, double kernel_support)
    : base_(std::move(base)), crack_(crack), kernel_support_(kernel_support) {}

ShapeTable EnrichedApproximation::evaluate(const ParticleSet& particles,
                                           const Eigen::MatrixXd& points, int order) const {
  ShapeTable b = base_->evaluate(particles, points, order);
  const std::vector<Enrichment> enr = enrichments(particles);
  if (enr.empty()) return b;
  const bool branches = std::any_of(enr.begin(), enr.end(), [](const Enrichment& e) {
    return e.kind != EnrichmentKind::step;
  });
  if (order >= 2 && branches)
    throw InputError("xefg: second derivatives of the tip (branch) enrichment are not "
                     "implemented; use tip=none or a first-order weak form");
  const int N = particles.size(), dim = b.dim, nh = dim * dim;
  // Enriched columns of node I: first[I] .. first[I] + count[I] − 1 (consecutive by node).
  std::vector<int> first(N, -1), count(N, 0);
  for (int e = 0; e < static_cast<int>(enr.size()); ++e) {
    if (first[enr[e].node] < 0) first[enr[e].node] = e;
    ++count[enr[e].node];
  }
  ShapeTable t;
  t.dim = dim;
  t.order = b.order;
  t.offsets.assign(1, 0);
  for (int q = 0; q < b.points(); ++q) {
    const double* x = points.col(q).data();
    const double H = crack_.side(x) >= 0 ? 1.0 : -1.0;  // eq 9
    for (int k = b.offsets[q]; k < b.offsets[q + 1]; ++k) {
      t.index.push_back(b.index[k]);
      t.value.push_back(b.value[k]);
      for (int d = 0; d < dim && order >= 1; ++d) t.grad.push_back(b.grad[k * dim + d]);
      for (int d = 0; d < nh && order >= 2; ++d) t.hess.push_back(b.hess[k * nh + d]);
    }
    for (int k = b.offsets[q]; k < b.offsets[q + 1]; ++k) {
      const int I = b.index[k];
      for (int e = first[I]; e >= 0 && e < first[I] + count[I]; ++e) {
        double psi = H, gpsi[2] = {0, 0};
        if (enr[e].kind != EnrichmentKind::step)
          branch(crack_, static_cast<int>(enr[e].kind) - 1, x, psi, gpsi);
        t.index.push_back(N + e);
        t.value.push_back(psi * b.value[k]);
        for (int d = 0; d < dim && order >= 1; ++d)
          t.grad.push_back(psi * b.grad[k * dim + d] + b.value[k] * gpsi[d]);
        for (int d = 0; d < nh && order >= 2; ++d) t.hess.push_back(psi * b.hess[k * nh + d]);
      }
    }
    t.offsets.push_back(t.entries());
  }
  return t;
}

IntegrationRule CrackCellScheme::rule(const Domain& domain, const ParticleSet& p) const {
  IntegrationRule r;
  r.kind = "gauss-cells";
  std::vector<double> gx, wx, gy, wy;
  std::vector<std::array<double, 5>> cells;  // x0, x1, y0, y1, parent
  // Splits [a, b] at the crack when it lies strictly inside.
  const auto pieces = [&](double a, double b, bool cut) {
    std::vector<std::pair<double, double>> s;
    const double c = crack_.position, tol = 1e-12 * (b - a);
    if (cut && c > a + tol && c < b - tol) {
      s.emplace_back(a, c);
      s.emplace_back(c, b);
    } else {
      s.emplace_back(a, b);
    }
    return s;
  };
  if (p.dim == 1) {
    std::vector<double> xs(p.x.row(0).data(), p.x.row(0).data() + p.size());
    std::sort(xs.begin(), xs.end());
    xs.front() = std::min(xs.front(), domain.lower[0]);
    xs.back() = std::max(xs.back(), domain.upper[0]);
    for (std::size_t k = 0; k + 1 < xs.size(); ++k)
      for (auto [a, b] : pieces(xs[k], xs[k + 1], true))
        cells.push_back({a, b, 0, 0, static_cast<double>(k)});
    r.cells = static_cast<int>(xs.size()) - 1;
  } else {
    const int nx = p.lattice[0], ny = p.lattice[1];
    if (p.dim != 2 || nx < 2 || ny < 2 || nx * ny != p.size() ||
        p.placement != Placement::boundary)
      throw InputError("xefg with a crack integrates on the lattice cells: give it a 1D line or "
                       "a 2D rectangular lattice with particles on the boundary");
    std::vector<double> X(nx), Y(ny);
    for (int i = 0; i < nx; ++i) X[i] = p.x(0, i);
    for (int j = 0; j < ny; ++j) Y[j] = p.x(1, nx * j);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        if (std::abs(p.x(0, i + nx * j) - X[i]) + std::abs(p.x(1, i + nx * j) - Y[j]) >
            1e-9 * p.spacing)
          throw InputError("xefg with a crack needs an unperturbed lattice (its cells are split "
                           "along the crack); set the perturbation to 0");
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        const bool cut = Y[j] < crack_.tip;
        for (auto [a, b] : pieces(X[i], X[i + 1], cut))
          cells.push_back({a, b, Y[j], Y[j + 1], static_cast<double>(i + (nx - 1) * j)});
      }
    r.cells = (nx - 1) * (ny - 1);
  }
  const int per = p.dim == 1 ? n_ : n_ * n_;
  r.points.resize(p.dim, static_cast<Eigen::Index>(cells.size()) * per);
  r.weights.resize(static_cast<Eigen::Index>(cells.size()) * per);
  Eigen::Index q = 0;
  for (const auto& c : cells) {
    gauss_legendre(n_, c[0], c[1], gx, wx);
    if (p.dim == 2) gauss_legendre(n_, c[2], c[3], gy, wy);
    for (int j = 0; j < (p.dim == 2 ? n_ : 1); ++j)
      for (int i = 0; i < n_; ++i, ++q) {
        r.points(0, q) = gx[i];
        r.weights[q] = wx[i];
        if (p.dim == 2) {
          r.points(1, q) = gy[j];
          r.weights[q] *= wy[j];
        }
        r.cell.push_back(static_cast<int>(c[4]));
      }
  }
  return r;
}

}  // namespace mfv
