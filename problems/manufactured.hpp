/// Manufactured solutions (problems/manufactured.cpp): each a smooth exact field with its
/// derivatives and the source of its operator derived by hand, so that tests can check the
/// derivation against finite differences (tests/test_manufactured.cpp) and the problems can
/// stay plain BoundaryValueProblems. The wavenumber κ keeps each out of every polynomial basis.
#pragma once
#include <array>
#include <cmath>

namespace mfv::mms {

/// u = sin(κx) + x² for −k u″ = f: f = k (κ² sin κx − 2).
struct SineQuadratic1D {
  double kappa = 3, k = 1;
  double u(double x) const { return std::sin(kappa * x) + x * x; }
  double du(double x) const { return kappa * std::cos(kappa * x) + 2 * x; }
  double source(double x) const { return k * (kappa * kappa * std::sin(kappa * x) - 2); }
};

/// u = sin(κx) cos(κy) + x² y for −k Δu = f: f = k (2κ² sin κx cos κy − 2y).
struct SineQuadratic2D {
  double kappa = 3, k = 1;
  double u(double x, double y) const {
    return std::sin(kappa * x) * std::cos(kappa * y) + x * x * y;
  }
  std::array<double, 2> grad(double x, double y) const {
    return {kappa * std::cos(kappa * x) * std::cos(kappa * y) + 2 * x * y,
            -kappa * std::sin(kappa * x) * std::sin(kappa * y) + x * x};
  }
  double source(double x, double y) const {
    return k * (2 * kappa * kappa * std::sin(kappa * x) * std::cos(kappa * y) - 2 * y);
  }
};

/// Plane-strain linear elasticity with Lamé constants λ, μ:
///   u_x = sin κx cos κy,  u_y = cos κx sin κy + x y²,
///   ε_xx = κ cos κx cos κy, ε_yy = κ cos κx cos κy + 2xy, γ_xy = −2κ sin κx sin κy + y²,
///   σ = (λ + 2μ, λ; λ, λ + 2μ) (ε_xx, ε_yy), σ_xy = μ γ_xy, and b = −∇·σ:
///   b_x = (2λ + 4μ) κ² sin κx cos κy − 2(λ + μ) y,
///   b_y = (2λ + 4μ) κ² cos κx sin κy − 2(λ + 2μ) x.
struct ElasticWave2D {
  double kappa = 2, lambda = 1, mu = 1;
  std::array<double, 2> u(double x, double y) const {
    return {std::sin(kappa * x) * std::cos(kappa * y),
            std::cos(kappa * x) * std::sin(kappa * y) + x * y * y};
  }
  /// (∂u_x/∂x, ∂u_x/∂y, ∂u_y/∂x, ∂u_y/∂y).
  std::array<double, 4> grad(double x, double y) const {
    const double cx = std::cos(kappa * x), sx = std::sin(kappa * x);
    const double cy = std::cos(kappa * y), sy = std::sin(kappa * y);
    return {kappa * cx * cy, -kappa * sx * sy, -kappa * sx * sy + y * y, kappa * cx * cy + 2 * x * y};
  }
  /// (σ_xx, σ_yy, σ_xy).
  std::array<double, 3> stress(double x, double y) const {
    const auto g = grad(x, y);
    const double exx = g[0], eyy = g[3], gxy = g[1] + g[2];
    return {(lambda + 2 * mu) * exx + lambda * eyy, lambda * exx + (lambda + 2 * mu) * eyy,
            mu * gxy};
  }
  std::array<double, 2> body_force(double x, double y) const {
    const double sc = std::sin(kappa * x) * std::cos(kappa * y);
    const double cs = std::cos(kappa * x) * std::sin(kappa * y);
    const double k2 = kappa * kappa;
    return {(2 * lambda + 4 * mu) * k2 * sc - 2 * (lambda + mu) * y,
            (2 * lambda + 4 * mu) * k2 * cs - 2 * (lambda + 2 * mu) * x};
  }
};

}  // namespace mfv::mms
