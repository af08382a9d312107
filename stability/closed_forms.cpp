/// Closed forms of 000 §3–4 (see closed_forms.hpp for the equations and the discrepancies) and
/// the strong-ellipticity test of a material (material_stability.hpp).
#include "stability/closed_forms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "methods/kernels/kernel.hpp"
#include "methods/materials/material.hpp"
#include "stability/material_stability.hpp"

namespace mfv::closed_form {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The paper's radial weight W(r/h), h = dmx·dx, through an mfv kernel of any support():
/// value and derivatives with respect to r.
struct RadialWeight {
  const Kernel& kernel;
  double h;
  double scale;  // s_mfv = r·scale

  RadialWeight(const Kernel& k, double dmx, double dx)
      : kernel(k), h(dmx * dx), scale(k.support() / (dmx * dx)) {
    if (!(dmx > 0) || !(dx > 0)) throw std::invalid_argument("closed_form: dmx and dx must be > 0");
  }
  void operator()(double r, double& w, double& dw, double& d2w) const {
    double s = std::abs(r) * scale;
    kernel.evaluate({&s, 1}, {&w, 1}, {&dw, 1}, {&d2w, 1});
    dw *= scale;
    d2w *= scale * scale;
  }
};

/// Lattice sums of the Shepard function about a 1D point at `offset`·dx from a particle:
/// z = offset·dx + j·dx for every j with |z| < h (+ a margin; W = 0 beyond).
struct Sums1D {
  std::vector<double> z, w, dw, d2w;  // Shepard w, w', w'' (frozen normalization) at z
  /// The Shepard function's own second derivative at z, normalization included:
  /// d²/dx² [W(x − x_K)/S(x)] = W''/S − W S''/S² (S' = 0 at a particle or a midpoint).
  std::vector<double> d2w_shepard;
  double S = 0;                       // Σ W(z)
  double a = 0;                       // eq 2.20: 1/Σ_K w_{K,X} X_K = −1/Σ_z w'(z) z
};

Sums1D sums_1d(const Kernel& W, double dmx, double dx, double offset) {
  RadialWeight rw(W, dmx, dx);
  Sums1D s;
  const int jmax = static_cast<int>(std::ceil(dmx)) + 2;
  for (int j = -jmax; j <= jmax; ++j) {
    const double z = (offset + j) * dx;
    double w, dw, d2w;
    rw(z, w, dw, d2w);
    if (w == 0 && dw == 0 && d2w == 0) continue;
    s.z.push_back(z);
    s.w.push_back(w);
    s.dw.push_back(z < 0 ? -dw : dw);  // d/dz W(|z|)
    s.d2w.push_back(d2w);
    s.S += w;
  }
  double m1 = 0, S2 = 0;  // S2 = S'' = Σ W''(z)
  for (double v : s.d2w) S2 += v;
  for (std::size_t i = 0; i < s.z.size(); ++i)
    s.d2w_shepard.push_back(s.d2w[i] / s.S - s.w[i] * S2 / (s.S * s.S));
  for (std::size_t i = 0; i < s.z.size(); ++i) {
    s.w[i] /= s.S;
    s.dw[i] /= s.S;
    s.d2w[i] /= s.S;
    m1 += s.dw[i] * s.z[i];
  }
  s.a = -1 / m1;
  return s;
}

/// T = Σ w'(z) sin(κ z) and Q = Σ w''(z)(1 − cos κz).
double sine_sum(const Sums1D& s, double kappa) {
  double t = 0;
  for (std::size_t i = 0; i < s.z.size(); ++i) t += s.dw[i] * std::sin(kappa * s.z[i]);
  return t;
}
double cosine_sum(const Sums1D& s, double kappa,
                  Normalization n = Normalization::frozen) {
  const std::vector<double>& d2 = n == Normalization::frozen ? s.d2w : s.d2w_shepard;
  double q = 0;
  for (std::size_t i = 0; i < s.z.size(); ++i) q += d2[i] * (1 - std::cos(kappa * s.z[i]));
  return q;
}

}  // namespace

double correction_factor_1d(const Kernel& W, double dmx, double offset) {
  return sums_1d(W, dmx, 1.0, offset).a;
}

double omega2_lagrangian_nodal_1d(const Kernel& W, double dmx, double dx, double kappa,
                                  double C_bar, double rho0) {
  const Sums1D s = sums_1d(W, dmx, dx, 0.0);
  const double t = sine_sum(s, kappa);
  return s.a * C_bar / rho0 * t * t;
}

double omega2_eulerian_nodal_1d(const Kernel& W, double dmx, double dx, double kappa,
                                double C_sigmaT, double sigma, double rho) {
  const Sums1D s = sums_1d(W, dmx, dx, 0.0);
  const double t = sine_sum(s, kappa), q = cosine_sum(s, kappa);
  const double c_prime = C_sigmaT + sigma;  // eq 3.17
  return s.a * c_prime / rho * t * t - sigma / rho * (q - s.a * t * t);
}

double omega2_lagrangian_stress_points_1d(const Kernel& W, double dmx, double dx, double kappa,
                                          double C_bar, double rho0) {
  const Sums1D m = sums_1d(W, dmx, dx, 0.0), sp = sums_1d(W, dmx, dx, 0.5);
  const double tm = sine_sum(m, kappa), ts = sine_sum(sp, kappa);
  return C_bar / (2 * rho0) * (m.a * tm * tm + sp.a * ts * ts);
}

namespace {

/// The first κΔx in (0, π] where ω²(κ) turns negative, over π: a scan of 4000 steps, then
/// bisection to 1e-12 between the last non-negative and the first negative sample; NaN when
/// ω² stays non-negative over the zone.
template <class Omega2>
double first_negative_over_pi(const Omega2& f) {
  const int steps = 4000;
  double prev = 0;
  for (int i = 1; i <= steps; ++i) {
    const double x = M_PI * i / steps;
    if (f(x) < 0) {
      double lo = prev, hi = x;  // f(lo) >= 0 (or lo = 0), f(hi) < 0
      while (hi - lo > 1e-12) {
        const double mid = 0.5 * (lo + hi);
        (f(mid) < 0 ? hi : lo) = mid;
      }
      return hi / M_PI;
    }
    prev = x;
  }
  return kNaN;
}

}  // namespace

double onset_wavenumber_eulerian_1d(const Kernel& W, double dmx, double sigma_bar,
                                    double c_sign) {
  const double C = c_sign >= 0 ? 1.0 : -1.0;
  const double sigma = sigma_bar * C;
  return first_negative_over_pi(
      [&](double x) { return omega2_eulerian_nodal_1d(W, dmx, 1.0, x, C, sigma, 1.0); });
}

double omega2_eulerian_nodal_1d(const Kernel& W, double dmx, double dx, double kappa,
                                double C_sigmaT, double sigma, double rho, Normalization n) {
  const Sums1D s = sums_1d(W, dmx, dx, 0.0);
  const double t = sine_sum(s, kappa), q = cosine_sum(s, kappa, n);
  return s.a * (C_sigmaT + sigma) / rho * t * t - sigma / rho * (q - s.a * t * t);
}

double onset_wavenumber_eulerian_1d(const Kernel& W, double dmx, double sigma_bar,
                                    Normalization n) {
  return first_negative_over_pi(
      [&](double x) { return omega2_eulerian_nodal_1d(W, dmx, 1.0, x, 1.0, sigma_bar, 1.0, n); });
}

double onset_wavenumber_eulerian_three_point(const Kernel& W, double dmx, double sigma_bar,
                                             Normalization n) {
  if (!(dmx > 1 && dmx <= 2))
    throw std::invalid_argument("closed_form: the three-point onset needs 1 < D_mx <= 2");
  const Sums1D s = sums_1d(W, dmx, 1.0, 0.0);
  const std::vector<double>& d2 = n == Normalization::frozen ? s.d2w : s.d2w_shepard;
  double w1 = 0, w2 = 0;  // w'(Δx) and w''(Δx): the neighbour at z = +Δx
  for (std::size_t i = 0; i < s.z.size(); ++i)
    if (std::abs(s.z[i] - 1.0) < 1e-12) {
      w1 = s.dw[i];
      w2 = d2[i];
    }
  // ω²ρ/C^{σT} = (1 − cos κ)[4a(1 + 2σ̄)w'² (1 + cos κ) − 2σ̄ w'']: negative iff
  // cos κ < β − 1, β = 2σ̄ w''/(4a(1 + 2σ̄) w'²).
  const double beta = 2 * sigma_bar * w2 / (4 * s.a * (1 + 2 * sigma_bar) * w1 * w1);
  if (!(beta > 0)) return kNaN;  // never negative
  if (beta >= 2) return 0.0;     // negative at every κ > 0
  return std::acos(beta - 1) / M_PI;
}

double cell_alpha_limit(const Kernel& W, CellLumping lumping, bool trimmed) {
  // φ(ξ) = W(|ξ|)/∫W over the support ξ ∈ [−1, 1] (ξ in support radii); the integrands are
  // even in ξ, so integrate over [0, 1] (or [0, 1/2] trimmed): composite 5-point
  // Gauss–Legendre on 2000 panels (a panel edge falls on ξ = 1/2, the cubic spline's break
  // point, so each panel integrates a smooth piece).
  static const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                               0.5384693101056831, 0.9061798459386640};
  static const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
  const double q = W.support();
  auto integrate = [&](double b, auto&& f) {
    const int panels = 2000;
    const double h = b / panels;
    double sum = 0;
    for (int p = 0; p < panels; ++p)
      for (int k = 0; k < 5; ++k) {
        const double xi = h * (p + 0.5 + 0.5 * gx[k]);
        double s = xi * q, w, dw;
        W.evaluate({&s, 1}, {&w, 1}, {&dw, 1}, {});
        sum += 0.5 * h * gw[k] * f(w, dw * q);  // dW/dξ = q dW/ds
      }
    return 2 * sum;  // both halves of the support
  };
  const double b = trimmed ? 0.5 : 1.0;
  const double total = integrate(1.0, [](double w, double) { return w; });
  const double kept = integrate(b, [](double w, double) { return w; }) / total;  // ∫φ kept
  if (lumping == CellLumping::row_sum) {
    const double fisher = integrate(b, [](double w, double dw) { return w > 0 ? dw * dw / w : 0.0; });
    return fisher / total / kept;
  }
  if (!trimmed) return std::numeric_limits<double>::infinity();
  const double phi2 = integrate(b, [](double w, double) { return w * w; }) / (total * total);
  const double log_fisher =
      integrate(b, [](double w, double dw) { return w > 0 ? dw * dw / (w * w) : 0.0; });
  return phi2 * log_fisher;
}

StressThreshold stable_threshold_lagrangian_1d(const Kernel& W, double dmx, double kappa_dx,
                                               double c_sign) {
  const Sums1D s = sums_1d(W, dmx, 1.0, 0.0);
  const double t = sine_sum(s, kappa_dx);
  // ω²ρ0/|C^{σT}| = sign·a(1 + σ̄)T²: zero at σ̄ = −1 unless T = 0.
  const bool marginal = std::abs(t) < 1e-12 * std::abs(s.a > 0 ? 1 / s.a : 1.0);
  return {marginal ? kNaN : -1.0, c_sign >= 0};
}

StressThreshold stable_threshold_eulerian_1d(const Kernel& W, double dmx, double kappa_dx,
                                             double c_sign) {
  const Sums1D s = sums_1d(W, dmx, 1.0, 0.0);
  const double t = sine_sum(s, kappa_dx), q = cosine_sum(s, kappa_dx);
  const double at2 = s.a * t * t, b = 2 * at2 - q;  // ω²ρ/C = aT² + σ̄ b
  if (std::abs(at2) < 1e-14 && std::abs(b) < 1e-14) return {kNaN, c_sign >= 0};
  const double sgn = c_sign >= 0 ? 1.0 : -1.0;
  return {-at2 / b, sgn * b > 0};
}

// ───────────────────────────── 2D ─────────────────────────────

namespace {

struct Geometry2D {
  Eigen::Vector2d a1, a2;
  double area;
  std::vector<Eigen::Vector2d> offsets;  // kinds of integration points: particles first
};

Geometry2D geometry(const Setup2D& s) {
  Geometry2D g;
  const double d = s.dx;
  if (s.lattice == Lattice2D::rectangular) {
    g.a1 = {d, 0};
    g.a2 = {0, d};
  } else {
    g.a1 = {d, 0};
    g.a2 = {0.5 * d, 0.5 * std::sqrt(3.0) * d};
  }
  g.area = std::abs(g.a1.x() * g.a2.y() - g.a1.y() * g.a2.x());
  g.offsets.push_back(Eigen::Vector2d::Zero());
  if (s.stress_points) {
    if (s.lattice == Lattice2D::rectangular) {
      g.offsets.push_back(0.5 * (g.a1 + g.a2));  // quadrilateral centre
    } else {
      g.offsets.push_back((g.a1 + g.a2) / 3);      // centroid of (0, a1, a2)
      g.offsets.push_back(2 * (g.a1 + g.a2) / 3);  // centroid of (a1, a2, a1 + a2)
    }
  }
  return g;
}

/// Shepard function, gradient and (frozen-normalization) Hessian at z = x_q − X_K for every
/// particle K in the support of a point x_q at `offset` from a particle.
struct Sums2D {
  std::vector<Eigen::Vector2d> z;
  std::vector<double> w;
  std::vector<Eigen::Vector2d> grad;
  std::vector<Eigen::Matrix2d> hess;
  Eigen::Matrix2d a;  // eqs 2.14–2.16
};

Sums2D sums_2d(const Kernel& W, const Setup2D& s, const Geometry2D& g,
               const Eigen::Vector2d& offset) {
  RadialWeight rw(W, s.dmx, s.dx);
  Sums2D out;
  const int nmax = static_cast<int>(std::ceil(2 * s.dmx)) + 3;
  double S = 0;
  for (int i = -nmax; i <= nmax; ++i)
    for (int j = -nmax; j <= nmax; ++j) {
      const Eigen::Vector2d z = offset + i * g.a1 + j * g.a2;
      const double r = z.norm();
      if (r >= rw.h * (1 + 1e-12)) continue;
      double w, dw, d2w;
      rw(r, w, dw, d2w);
      if (w == 0 && dw == 0 && d2w == 0) continue;
      Eigen::Vector2d gr = Eigen::Vector2d::Zero();
      Eigen::Matrix2d he = d2w * Eigen::Matrix2d::Identity();  // r = 0 limit
      if (r > 0) {
        const Eigen::Vector2d e = z / r;
        gr = dw * e;
        he = (d2w - dw / r) * e * e.transpose() + dw / r * Eigen::Matrix2d::Identity();
      }
      out.z.push_back(z);
      out.w.push_back(w);
      out.grad.push_back(gr);
      out.hess.push_back(he);
      S += w;
    }
  // A_ij = Σ_K w_{K,j}(x_q) X_Ki with X_K = x_q − z and Σ_K ∇w_K = 0: A_ij = −Σ_z ∂_j w(z) z_i.
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  for (std::size_t n = 0; n < out.z.size(); ++n) {
    out.w[n] /= S;
    out.grad[n] /= S;
    out.hess[n] /= S;
    A -= out.z[n] * out.grad[n].transpose();
  }
  out.a = A.inverse().transpose();  // eq 2.14: A aᵀ = I
  return out;
}

/// C_pqrs of plane strain (eqs 4.8, 4.15).
double elastic(const Setup2D& s, int p, int q, int r, int t) {
  auto d = [](int i, int j) { return i == j ? 1.0 : 0.0; };
  return s.lambda * d(p, q) * d(r, t) + s.mu * (d(p, r) * d(q, t) + d(p, t) * d(q, r));
}

/// The tensor E_pqrs multiplying w_{I,p} (a g)_s ũ_r in the q-th equation (see D3–D5).
double tangent(const Setup2D& s, int p, int q, int r, int t) {
  auto d = [](int i, int j) { return i == j ? 1.0 : 0.0; };
  const Eigen::Matrix2d& S = s.stress;
  double e = elastic(s, p, q, r, t) + S(p, t) * d(q, r);
  if (s.frame == Frame::eulerian) e += d(p, r) * S(t, q);
  return e;
}

}  // namespace

Eigen::Matrix2d correction_matrix_2d(const Kernel& W, const Setup2D& s,
                                     const Eigen::Vector2d& offset) {
  return sums_2d(W, s, geometry(s), offset).a;
}

Eigen::Matrix2cd dynamical_matrix_2d(const Kernel& W, const Setup2D& s, const Eigen::Vector2d& k) {
  using C = std::complex<double>;
  const Geometry2D g = geometry(s);
  const double V = g.area / static_cast<double>(g.offsets.size());  // Voronoi volumes
  const double m = s.rho * g.area;
  Eigen::Matrix2cd D = Eigen::Matrix2cd::Zero();
  for (std::size_t kind = 0; kind < g.offsets.size(); ++kind) {
    const Sums2D sm = sums_2d(W, s, g, g.offsets[kind]);
    // g_k = Σ_z w_{,k}(z) e^{−ik·z}; ψ = Σ_z w(z) e^{−ik·z} (interpolated displacement of a
    // stress point, eq 4.25, relative to e^{ik·x_q}).
    Eigen::Vector2cd gk = Eigen::Vector2cd::Zero();
    C psi = 0;
    for (std::size_t n = 0; n < sm.z.size(); ++n) {
      const C e = std::exp(C(0, -k.dot(sm.z[n])));
      gk += sm.grad[n].cast<C>() * e;
      psi += sm.w[n] * e;
    }
    const Eigen::Vector2cd ag = sm.a.cast<C>() * gk;
    // Σ_J over this kind of point, particle I = 0: y = x_J − X_I; the outer sum
    // Σ_J w_{I,p}(x_J) e^{ik·x_J} with w_{I,p}(x_J) = ∇w(y) gives conj(g_p) (w real).
    for (int q = 0; q < 2; ++q)
      for (int r = 0; r < 2; ++r) {
        C sum = 0;
        for (int p = 0; p < 2; ++p)
          for (int t = 0; t < 2; ++t) sum += std::conj(gk(p)) * tangent(s, p, q, r, t) * ag(t);
        D(q, r) += V * sum;
      }
    if (s.frame == Frame::eulerian) {
      // σ_pq Σ_J w_{I,pt}(x_J)(ũ_t(x_J) − ũ_t(X_I)) (eqs 4.12, 4.16–4.17, 4.23–4.26): the
      // perturbed kernel derivative with the Shepard normalization frozen. For I = 0 the
      // points J of this kind sit at y = x_J ∈ offset + L, the same set as z, and w_{I,pt}(x_J)
      // = H(y). ũ(x_J) is the particle's own displacement for particles, the interpolant
      // Σ_K w_K(x_J) ũ_K = A e^{ik·y} ψ (eq 4.25) for stress points.
      const bool particle = kind == 0;
      Eigen::Matrix2cd Qh = Eigen::Matrix2cd::Zero();
      for (std::size_t n = 0; n < sm.z.size(); ++n) {
        const C e = std::exp(C(0, k.dot(sm.z[n])));
        Qh += sm.hess[n].cast<C>() * ((particle ? e : e * psi) - 1.0);
      }
      D += V * s.stress.transpose().cast<C>() * Qh;  // D_qt += V σ_pq Qh_pt
    }
  }
  return D / m;
}

std::array<double, 2> omega2_2d(const Kernel& W, const Setup2D& s, double kappa, double theta) {
  const Eigen::Vector2d k = kappa * Eigen::Vector2d(std::cos(theta), std::sin(theta));
  const Eigen::Matrix2cd D = dynamical_matrix_2d(W, s, k);
  Eigen::ComplexEigenSolver<Eigen::Matrix2cd> es(D, false);
  std::array<double, 2> ev{es.eigenvalues()(0).real(), es.eigenvalues()(1).real()};
  std::sort(ev.begin(), ev.end());
  return ev;
}

std::array<double, 2> omega2_lagrangian_nodal_2d(const Kernel& W, Setup2D s, double kappa,
                                                 double theta) {
  s.stress_points = false;
  s.frame = Frame::lagrangian;
  return omega2_2d(W, s, kappa, theta);
}
std::array<double, 2> omega2_eulerian_nodal_2d(const Kernel& W, Setup2D s, double kappa,
                                               double theta) {
  s.stress_points = false;
  s.frame = Frame::eulerian;
  return omega2_2d(W, s, kappa, theta);
}
std::array<double, 2> omega2_lagrangian_stress_points_2d(const Kernel& W, Setup2D s,
                                                         double kappa, double theta) {
  s.stress_points = true;
  s.frame = Frame::lagrangian;
  return omega2_2d(W, s, kappa, theta);
}
std::array<double, 2> omega2_eulerian_stress_points_2d(const Kernel& W, Setup2D s,
                                                       double kappa, double theta) {
  s.stress_points = true;
  s.frame = Frame::eulerian;
  return omega2_2d(W, s, kappa, theta);
}

std::array<double, 2> omega2_continuum_2d(const Setup2D& s, double kappa, double theta) {
  const Eigen::Vector2d k = kappa * Eigen::Vector2d(std::cos(theta), std::sin(theta));
  Eigen::Matrix2d Q = Eigen::Matrix2d::Zero();
  Setup2D lag = s;
  lag.frame = Frame::lagrangian;
  for (int q = 0; q < 2; ++q)
    for (int r = 0; r < 2; ++r)
      for (int p = 0; p < 2; ++p)
        for (int t = 0; t < 2; ++t) Q(q, r) += tangent(lag, p, q, r, t) * k(p) * k(t);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(Q / s.rho, Eigen::EigenvaluesOnly);
  return {es.eigenvalues()(0), es.eigenvalues()(1)};
}

}  // namespace mfv::closed_form

// ─────────────────────── material stability (001 Fig. 1) ───────────────────────

namespace mfv {

Eigen::Matrix4d tangent_modulus_2d(const Material& material, const Eigen::Matrix2d& F,
                                   double step) {
  // A(i + 2J, k + 2L) = ∂P_iJ/∂F_kL, column-major storage of P and F as first_piola uses.
  Eigen::Matrix4d A;
  for (int c = 0; c < 4; ++c) {
    Eigen::Matrix2d Fp = F, Fm = F;
    const double hstep = step * std::max(1.0, std::abs(F.data()[c]));
    Fp.data()[c] += hstep;
    Fm.data()[c] -= hstep;
    Eigen::Matrix2d Pp, Pm;
    material.first_piola(2, 1, Fp.data(), Pp.data(), nullptr);
    material.first_piola(2, 1, Fm.data(), Pm.data(), nullptr);
    const Eigen::Matrix2d d = (Pp - Pm) / (2 * hstep);
    for (int r = 0; r < 4; ++r) A(r, c) = d.data()[r];
  }
  return A;
}

double min_acoustic_eigenvalue(const Material& material, const Eigen::Matrix2d& F,
                               int directions) {
  const Eigen::Matrix4d A = tangent_modulus_2d(material, F);
  double lo = std::numeric_limits<double>::infinity();
  for (int d = 0; d < directions; ++d) {
    const double th = M_PI * d / directions;  // Q(−n) = Q(n)
    const Eigen::Vector2d n(std::cos(th), std::sin(th));
    Eigen::Matrix2d Q = Eigen::Matrix2d::Zero();  // Q_ik = A_iJkL n_J n_L
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k)
        for (int J = 0; J < 2; ++J)
          for (int L = 0; L < 2; ++L) Q(i, k) += A(i + 2 * J, k + 2 * L) * n(J) * n(L);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (Q + Q.transpose()),
                                                      Eigen::EigenvaluesOnly);
    lo = std::min(lo, es.eigenvalues()(0));
  }
  return lo;
}

bool pde_stable(const Material& material, const Eigen::Matrix2d& F, int directions) {
  const Eigen::Matrix4d A = tangent_modulus_2d(material, F);
  const double scale = A.cwiseAbs().maxCoeff();
  return min_acoustic_eigenvalue(material, F, directions) > 1e-9 * scale;
}

}  // namespace mfv
