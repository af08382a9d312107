/// `j2-jaumann`: J2 flow theory with the Jaumann rate of the Kirchhoff stress τ = F·P = Jσ
/// (001 eq 76 = 000 eq 5.2), τ^∇J = C : (D − Dᵖ), f = σ̄ − σ_Y(ε̄), σ̄ = [3/2 τ':τ']^{1/2},
/// linear hardening (H > 0) or softening (H < 0), σ_Y = max(σ_Y0·ξ + H ε̄, 0) with a seeded
/// per-point yield factor ξ (the imperfection that triggers the steel ring's shear bands,
/// 001 §9.5). One step from F_old to F_new: the Hughes–Winget rotated elastic trial τ_trial
/// (jaumann_update.hpp, shared with j2-viscoplastic), radial return Δε̄ = f_trial/(3μ + H),
/// P = τ F⁻ᵀ. 2D is plane strain (F33 = 1, τ33 kept), 1D uniaxial strain (F = diag(F11, 1, 1)).
#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods/materials/jaumann_update.hpp"
#include "methods/materials/material.hpp"

namespace mfv {

namespace {

/// Per-point history: the shared F − I and τ (jaumann::Slots), then ε̄ and ξ − 1.
struct Layout {
  int dim;
  int plastic_strain() const { return jaumann::Slots{dim}.end(); }
  int yield_factor() const { return plastic_strain() + 1; }
  int size() const { return yield_factor() + 1; }
};

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
    std::vector<std::string> names = jaumann::slot_names(dim);
    names.push_back("plastic_strain");
    names.push_back("yield_factor_minus_1");
    return names;
  }

  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    jaumann::check_call("j2-jaumann", dim, state);
    const Layout l{dim};
    const int dd = dim * dim;
    for (int q = 0; q < n; ++q) {
      double* s = state + static_cast<long>(l.size()) * q;
      Eigen::Matrix3d F_old, F_new, tau;
      jaumann::load(dim, s, F + dd * q, F_old, F_new, tau);
      update(F_old, F_new, 1 + s[l.yield_factor()], tau, s[l.plastic_strain()]);
      jaumann::store(dim, F_new, tau, P + dd * q, s);
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
    jaumann::elastic_trial(F_old, F_new, lambda_, mu_, tau);

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
