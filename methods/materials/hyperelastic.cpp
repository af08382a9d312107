/// `rubber`: the compressible hyperelastic material of 000 eq 5.1 / 001 eq 18 (the rubber ring,
/// 001 §9.6), σ = I3^{-1/2}[(c1 + c2 I1)B − c2 B² − (c1 I3^{1/3} + 2c2 I3^{2/3} − λ ln I3) I],
/// B = FFᵀ, I1 = tr B, I3 = det B; P = J σ F^{-T}, J = √I3. 2D is plane strain (F33 = 1, B 3×3,
/// the in-plane block of P returned), 1D uniaxial strain (F22 = F33 = 1, P = σ11).
/// Small-strain limit (B ≈ I + 2ε): σ ≈ 2(c1 + c2) ε + (2λ − (2/3)(c1 + c2)) tr ε I, i.e. Lamé
/// constants μ0 = c1 + c2, λ0 = 2λ − (2/3)(c1 + c2) (the printed λ enters as 2λ).
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods/materials/material.hpp"

namespace mfv {

namespace {

class Rubber final : public Material {
 public:
  Rubber(double c1, double c2, double lambda) : c1_(c1), c2_(c2), lambda_(lambda) {}

  void first_piola(int dim, int n, const double* F, double* P, double*) const override {
    for (int q = 0; q < n; ++q) {
      Eigen::Matrix3d F3 = Eigen::Matrix3d::Identity();
      for (int j = 0; j < dim; ++j)
        for (int i = 0; i < dim; ++i) F3(i, j) = F[dim * dim * q + i + dim * j];
      const Eigen::Matrix3d P3 = first_piola_3d(F3);
      for (int j = 0; j < dim; ++j)
        for (int i = 0; i < dim; ++i) P[dim * dim * q + i + dim * j] = P3(i, j);
    }
  }

  double wave_speed(int, double density) const override {
    return std::sqrt((lambda0() + 2 * mu0()) / density);
  }

  std::string description(int dim) const override {
    return fmt::format("rubber (000 eq 5.1) c1={:g} c2={:g} lambda={:g}{}", c1_, c2_, lambda_,
                       dim == 1 ? " uniaxial strain" : dim == 2 ? " plane strain" : "");
  }

 private:
  double mu0() const { return c1_ + c2_; }
  double lambda0() const { return 2 * lambda_ - 2.0 / 3.0 * (c1_ + c2_); }

  Eigen::Matrix3d first_piola_3d(const Eigen::Matrix3d& F) const {
    const Eigen::Matrix3d B = F * F.transpose();
    const double I1 = B.trace(), J = F.determinant(), I3 = J * J;
    const Eigen::Matrix3d sigma =
        ((c1_ + c2_ * I1) * B - c2_ * B * B -
         (c1_ * std::cbrt(I3) + 2 * c2_ * std::pow(I3, 2.0 / 3.0) - lambda_ * std::log(I3)) *
             Eigen::Matrix3d::Identity()) /
        J;
    return J * sigma * F.inverse().transpose();
  }

  double c1_, c2_, lambda_;
};

}  // namespace

void register_hyperelastic(MaterialRegistry& r) {
  r.add("rubber",
        "compressible hyperelastic sigma = I3^-1/2[(c1+c2 I1)B - c2 B^2 - (c1 I3^1/3 + 2c2 I3^2/3 "
        "- lambda ln I3)I] (000 eq 5.1, 001 eq 18; paper density 125.4 kg/m^3)",
        {ParamSpec::positive("c1", 1.265e5, "N/m^2"), ParamSpec::positive("c2", 1.012e4, "N/m^2"),
         ParamSpec::positive("lambda", 1.012e7, "N/m^2 (small-strain Lame constant is 2 lambda "
                                                "- 2(c1+c2)/3)")},
        [](const Params& p) -> std::unique_ptr<Material> {
          return std::make_unique<Rubber>(p.number("c1"), p.number("c2"), p.number("lambda"));
        });
}

}  // namespace mfv
