/// Exponential weight W(s) = exp(-(s/c)²) for s <= 1, c = 0.4 (000 eq 2.9), not shifted to 0.
#include "methods/kernels/register.hpp"

#include <gsl/gsl_sf_erf.h>

namespace mfv {
namespace {

class Exponential final : public KernelFormula<Exponential> {
 public:
  explicit Exponential(double c) : c_(c) {}
  void formula(double s, double& w, double& dw, double& d2w) const {
    const double q = s / c_;
    w = std::exp(-q * q);
    dw = -2 * q / c_ * w;
    d2w = (4 * q * q - 2) / (c_ * c_) * w;
  }
  double support() const override { return 1.0; }
  double integral(int dim) const override {
    // 1D: c√π erf(1/c); 2D: π c² (1 - e^{-1/c²}); 3D by the closed form of ∫ 4π s² e^{-s²/c²}.
    const double e = std::exp(-1 / (c_ * c_));
    if (dim == 1) return c_ * std::sqrt(M_PI) * gsl_sf_erf(1 / c_);
    if (dim == 2) return M_PI * c_ * c_ * (1 - e);
    return 4 * M_PI * (c_ * c_ * c_ * std::sqrt(M_PI) / 4 * gsl_sf_erf(1 / c_) - c_ * c_ / 2 * e);
  }

 private:
  double c_;
};

}  // namespace

void register_exponential(KernelRegistry& r) {
  r.add("exponential", "exp(-(s/c)^2), support s<=1, c=0.4 (000 eq 2.9)",
        {ParamSpec::positive("c", 0.4, "width relative to the support")},
        [](const Params& p) { return std::make_unique<Exponential>(p.number("c")); });
}

}  // namespace mfv
