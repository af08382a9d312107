/// `j2-jaumann`: J2 flow theory with the Jaumann rate of the Kirchhoff stress τ = F·P = Jσ
/// (001 eq 76 = 000 eq 5.2), τ^∇J = C : (D − Dᵖ), f = σ̄ − σ_Y(ε̄), σ̄ = [3/2 τ':τ']^{1/2},
/// linear hardening (H > 0) or softening (H < 0), σ_Y = max(σ_Y0·ξ + H ε̄, 0) with a seeded
/// per-point yield factor ξ (the imperfection that triggers the steel ring's shear bands,
/// 001 §9.5). One step from F_old to F_new (Hughes–Winget): ΔL = (F_new − F_old) F_mid⁻¹,
/// F_mid = ½(F_old + F_new), DΔt = sym ΔL, WΔt = skew ΔL, Q = (I − ½WΔt)⁻¹(I + ½WΔt);
/// τ_trial = Q τ Qᵀ + λ tr(DΔt) I + 2μ DΔt, radial return Δε̄ = f_trial/(3μ + H), P = τ F⁻ᵀ.
/// Q is exactly orthogonal and, for a rigid rotation, exactly the increment's rotation, so the
/// update is objective to round-off. 2D is plane strain (F33 = 1, τ33 kept), 1D uniaxial
/// strain (F = diag(F11, 1, 1)).
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods/materials/material.hpp"

namespace mfv {

namespace {

/// Per-point history: F − I (dim², column-major, so the engine's zero fill means F = I), the
/// symmetric τ (xx, yy, zz, then xy, yz, xz as dim asks), ε̄, and ξ − 1.
struct Layout {
  int dim;
  int f() const { return 0; }
  int tau() const { return dim * dim; }
  int tau_count() const { return 3 + dim * (dim - 1) / 2; }
  int plastic_strain() const { return tau() + tau_count(); }
  int yield_factor() const { return plastic_strain() + 1; }
  int size() const { return yield_factor() + 1; }
};

// Off-diagonal τ slots after xx, yy, zz: (0,1), (1,2), (0,2).
constexpr int kOffRow[3] = {0, 1, 0}, kOffCol[3] = {1, 2, 2};

class J2Jaumann final : public Material {
 public:
  J2Jaumann(double E, double nu, double yield, double H, double imperfection,
            std::uint64_t seed)
      : E_(E), nu_(nu), yield_(yield), H_(H), imperfection_(imperfection), seed_(seed) {
    mu_ = E / (2 * (1 + nu));
    lambda_ = E * nu / ((1 + nu) * (1 - 2 * nu));
  }

  int state_size(int dim) const override { return Layout{dim}.size(); }

  void initial_state(int dim, int n, double* state) const override {
    const Layout l{dim};
    // Drawn sequentially over the points from one generator, with the 53-bit mapping written
    // out (std::uniform_real_distribution differs between standard libraries).
    std::mt19937_64 gen(seed_);
    for (int q = 0; q < n; ++q) {
      const double u = static_cast<double>(gen() >> 11) * 0x1.0p-53;  // [0, 1)
      state[static_cast<long>(l.size()) * q + l.yield_factor()] =
          imperfection_ * (2 * u - 1);
    }
  }

  std::vector<std::string> state_names(int dim) const override {
    std::vector<std::string> names;
    for (int j = 0; j < dim; ++j)
      for (int i = 0; i < dim; ++i)
        names.push_back(i == j ? fmt::format("F{}{}_minus_1", i + 1, j + 1)
                               : fmt::format("F{}{}", i + 1, j + 1));
    const char* tau[] = {"tau_xx", "tau_yy", "tau_zz", "tau_xy", "tau_yz", "tau_xz"};
    for (int k = 0; k < Layout{dim}.tau_count(); ++k) names.push_back(tau[k]);
    names.push_back("plastic_strain");
    names.push_back("yield_factor_minus_1");
    return names;
  }

  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    if (dim < 1 || dim > 3)
      throw InputError(fmt::format("material 'j2-jaumann' works in 1D, 2D or 3D, not {}D", dim));
    if (!state)
      throw std::logic_error("material 'j2-jaumann' needs its history (state_size per point)");
    const Layout l{dim};
    const int dd = dim * dim, nt = l.tau_count();
    for (int q = 0; q < n; ++q) {
      double* s = state + static_cast<long>(l.size()) * q;
      Eigen::Matrix3d F_old = Eigen::Matrix3d::Identity(), F_new = F_old;
      for (int j = 0; j < dim; ++j)
        for (int i = 0; i < dim; ++i) {
          F_old(i, j) += s[l.f() + i + dim * j];
          F_new(i, j) = F[dd * q + i + dim * j];
        }
      Eigen::Matrix3d tau = Eigen::Matrix3d::Zero();
      for (int k = 0; k < 3; ++k) tau(k, k) = s[l.tau() + k];
      for (int k = 3; k < nt; ++k)
        tau(kOffRow[k - 3], kOffCol[k - 3]) = tau(kOffCol[k - 3], kOffRow[k - 3]) =
            s[l.tau() + k];
      double& ebar = s[l.plastic_strain()];

      update(F_old, F_new, 1 + s[l.yield_factor()], tau, ebar);

      const Eigen::Matrix3d P3 = tau * F_new.inverse().transpose();
      for (int j = 0; j < dim; ++j)
        for (int i = 0; i < dim; ++i) {
          P[dd * q + i + dim * j] = P3(i, j);
          s[l.f() + i + dim * j] = F_new(i, j) - (i == j ? 1 : 0);
        }
      for (int k = 0; k < 3; ++k) s[l.tau() + k] = tau(k, k);
      for (int k = 3; k < nt; ++k)
        s[l.tau() + k] =
            0.5 * (tau(kOffRow[k - 3], kOffCol[k - 3]) + tau(kOffCol[k - 3], kOffRow[k - 3]));
    }
  }

  double wave_speed(int, double density) const override {
    return std::sqrt((lambda_ + 2 * mu_) / density);
  }

  std::string description(int dim) const override {
    return fmt::format("J2 flow, Jaumann rate of Kirchhoff stress (001 eq 76) E={:g} nu={:g} "
                       "yield={:g} H={:g} imperfection={:g} seed={}{}",
                       E_, nu_, yield_, H_, imperfection_, seed_,
                       dim == 1 ? " uniaxial strain" : dim == 2 ? " plane strain" : "");
  }

 private:
  /// τ and ε̄ from F_old to F_new: Hughes–Winget rotation, elastic trial, radial return.
  void update(const Eigen::Matrix3d& F_old, const Eigen::Matrix3d& F_new, double factor,
              Eigen::Matrix3d& tau, double& ebar) const {
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d dL = (F_new - F_old) * (0.5 * (F_old + F_new)).inverse();
    const Eigen::Matrix3d dD = 0.5 * (dL + dL.transpose()), dW = 0.5 * (dL - dL.transpose());
    const Eigen::Matrix3d Q = (I - 0.5 * dW).inverse() * (I + 0.5 * dW);
    tau = Q * tau * Q.transpose() + lambda_ * dD.trace() * I + 2 * mu_ * dD;

    const double p = tau.trace() / 3;
    Eigen::Matrix3d dev = tau - p * I;
    const double sbar = std::sqrt(1.5 * dev.squaredNorm());
    // The linear law σ_Y0 ξ + H ε̄ and its floor at 0: softening never makes σ_Y negative.
    const double linear = yield_ * factor + H_ * ebar;
    if (sbar <= std::max(linear, 0.0)) return;
    double de = (sbar - linear) / (3 * mu_ + H_);
    if (yield_ * factor + H_ * (ebar + de) > 0) {
      dev *= 1 - 3 * mu_ * de / sbar;
    } else {
      // The return crosses the floor (or starts beyond it): σ_Y = 0 there, so the deviator
      // is removed, σ̄ − 3μΔε̄ = 0.
      de = sbar / (3 * mu_);
      dev.setZero();
    }
    ebar += de;
    tau = dev + p * I;
  }

  double E_, nu_, yield_, H_, imperfection_;
  std::uint64_t seed_;
  double lambda_, mu_;
};

}  // namespace

void register_j2_jaumann(MaterialRegistry& r) {
  r.add("j2-jaumann",
        "J2 flow, Jaumann rate of Kirchhoff stress tau = F P (001 eq 76, 000 eq 5.2), radial "
        "return, sigma_Y = max(sigma_Y0 xi + H ebar, 0) with a seeded per-point factor xi; "
        "plane strain in 2D (the steel ring, 000 5.3 / 001 9.5)",
        {ParamSpec::positive("E", 2e11, "Young's modulus, Pa (000 5.3, 001 9.5)"),
         ParamSpec::number("nu", 0.3, "Poisson's ratio in [0, 0.5) (not given by 000/001)"),
         ParamSpec::positive("yield", 2e8, "initial yield stress sigma_Y0, Pa (000 5.3; 001 9.5 "
                                           "prints 1e10)"),
         ParamSpec::number("hardening", -2e10, "plastic modulus H, Pa; negative softens "
                                               "(001 9.5: H = -E/10); must exceed -3 mu"),
         ParamSpec::number("imperfection", 0.0,
                           "relative amplitude a in [0, 1) of the per-point yield factor xi, "
                           "uniform in [1 - a, 1 + a] (catalogue: 0.01 triggers the bands)"),
         capped(ParamSpec::count("seed", 1, 1, "seed of the imperfection draw (mt19937_64)"),
                2e9)},
        [](const Params& p) -> std::unique_ptr<Material> {
          const double E = p.number("E"), nu = p.number("nu"), H = p.number("hardening"),
                       a = p.number("imperfection");
          if (nu < 0 || nu >= 0.5)
            throw InputError(fmt::format("material 'j2-jaumann': nu = {} is outside [0, 0.5); "
                                         "give a Poisson's ratio such as 0.3",
                                         nu));
          const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
          // σ̄ = √(3/2 τ':τ') squares stresses of the size of the moduli: that must not overflow.
          if (!std::isfinite(9 * (lambda + 2 * mu) * (lambda + 2 * mu)))
            throw InputError(fmt::format("material 'j2-jaumann': E = {} is too large (stresses "
                                         "of that size overflow when squared); give E in Pa, "
                                         "e.g. 2e11",
                                         E));
          if (3 * mu + H <= 0)
            throw InputError(fmt::format(
                "material 'j2-jaumann': hardening = {} is at or below -3 mu = {}, where the "
                "return mapping has no solution; give H > -3 mu, e.g. -E/10 = {}",
                H, -3 * mu, -E / 10));
          if (a < 0 || a >= 1)
            throw InputError(fmt::format("material 'j2-jaumann': imperfection = {} is outside "
                                         "[0, 1); give a relative amplitude such as 0.01",
                                         a));
          return std::make_unique<J2Jaumann>(E, nu, p.number("yield"), H, a,
                                             static_cast<std::uint64_t>(p.integer("seed")));
        });
}

}  // namespace mfv
