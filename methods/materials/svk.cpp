/// `svk`: St Venant–Kirchhoff, S = λ tr(E) I + 2μ E with E = ½(FᵀF − I), P = F S: linear
/// elasticity written for finite strains, so it reduces to Hooke's law for small strains.
/// 1D is uniaxial stress (S = E E₁₁); 2D is plane strain or plane stress.
#include <cmath>

#include <fmt/format.h>

#include "methods/materials/material.hpp"

namespace mfv {

namespace {

class StVenantKirchhoff final : public Material {
 public:
  StVenantKirchhoff(double E, double nu, bool plane_strain)
      : E_(E), nu_(nu), plane_strain_(plane_strain) {
    mu_ = E / (2 * (1 + nu));
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    // Plane stress: eliminating E₃₃ from S₃₃ = 0 gives λ* = 2λμ/(λ + 2μ).
    lambda_ = plane_strain ? lambda : 2 * lambda * mu_ / (lambda + 2 * mu_);
  }

  void first_piola(int dim, int n, const double* F, double* P, double*) const override {
    if (dim == 1) {
      for (int q = 0; q < n; ++q) P[q] = F[q] * E_ * 0.5 * (F[q] * F[q] - 1);
      return;
    }
    for (int q = 0; q < n; ++q) {
      const double* f = F + 4 * q;  // column-major: f[0]=F11 f[1]=F21 f[2]=F12 f[3]=F22
      const double e11 = 0.5 * (f[0] * f[0] + f[1] * f[1] - 1);
      const double e22 = 0.5 * (f[2] * f[2] + f[3] * f[3] - 1);
      const double e12 = 0.5 * (f[0] * f[2] + f[1] * f[3]);
      const double tr = e11 + e22;
      const double s11 = lambda_ * tr + 2 * mu_ * e11, s22 = lambda_ * tr + 2 * mu_ * e22,
                   s12 = 2 * mu_ * e12;
      double* p = P + 4 * q;
      p[0] = f[0] * s11 + f[2] * s12;  // P11
      p[1] = f[1] * s11 + f[3] * s12;  // P21
      p[2] = f[0] * s12 + f[2] * s22;  // P12
      p[3] = f[1] * s12 + f[3] * s22;  // P22
    }
  }

  double wave_speed(int dim, double density) const override {
    return std::sqrt((dim == 1 ? E_ : lambda_ + 2 * mu_) / density);
  }

  std::string description(int dim) const override {
    return fmt::format("St Venant-Kirchhoff E={:g} nu={:g}{}", E_, nu_,
                       dim == 1 ? " uniaxial" : plane_strain_ ? " plane strain" : " plane stress");
  }

 private:
  double E_, nu_;
  bool plane_strain_;
  double lambda_, mu_;
};

}  // namespace

void register_svk(MaterialRegistry& r) {
  r.add("svk",
        "St Venant-Kirchhoff: S = lambda tr(E) I + 2 mu E, P = F S (Hooke's law at small strain)",
        {ParamSpec::positive("E", 1.0, "Young's modulus"),
         ParamSpec::number("nu", 0.0, "Poisson's ratio, in [0, 0.5)"),
         ParamSpec::choice("plane", "strain", {"strain", "stress"}, "2D: plane strain or stress")},
        [](const Params& p) -> std::unique_ptr<Material> {
          const double nu = p.number("nu");
          if (nu < 0 || nu >= 0.5)
            throw InputError(fmt::format("material 'svk': nu = {} is outside [0, 0.5); give a "
                                         "Poisson's ratio such as 0.3",
                                         nu));
          return std::make_unique<StVenantKirchhoff>(p.number("E"), nu,
                                                     p.text("plane") == "strain");
        });
}

}  // namespace mfv
