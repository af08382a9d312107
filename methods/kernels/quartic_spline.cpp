/// Quartic spline weight W(s) = 1 - 6s² + 8s³ - 3s⁴ for s <= 1, 000 eq 2.8.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class QuarticSpline final : public KernelFormula<QuarticSpline> {
 public:
  void formula(double s, double& w, double& dw, double& d2w) const {
    w = 1 - 6 * s * s + 8 * s * s * s - 3 * s * s * s * s;
    dw = -12 * s + 24 * s * s - 12 * s * s * s;
    d2w = -12 + 48 * s - 36 * s * s;
  }
  double support() const override { return 1.0; }
  // ∫_{-1}^{1} W = 2(1 - 2 + 2 - 3/5) = 4/5; 2D: 2π∫ W s ds = 2π(1/2 - 3/2 + 8/5 - 1/2) = π/5.
  double integral(int dim) const override { return dim == 1 ? 0.8 : dim == 2 ? M_PI / 5 : 4 * M_PI * (1.0 / 3 - 6.0 / 5 + 8.0 / 6 - 3.0 / 7); }
};

}  // namespace

void register_quartic_spline(KernelRegistry& r) {
  r.add("quartic-spline", "quartic spline 1-6s^2+8s^3-3s^4, support s<=1 (000 eq 2.8)", {},
        [](const Params&) { return std::make_unique<QuarticSpline>(); });
}

}  // namespace mfv
