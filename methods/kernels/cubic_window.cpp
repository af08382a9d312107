/// Cubic-spline window of RKPM, 004 (second paper) eq 6.7, in r = |y - x| / a:
/// Φ = 2/3 - 4r² + 4r³ for r <= 1/2, 4/3 - 4r + 4r² - 4r³/3 for 1/2 <= r <= 1.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class CubicWindow final : public KernelFormula<CubicWindow> {
 public:
  void formula(double r, double& w, double& dw, double& d2w) const {
    if (r <= 0.5) {
      w = 2.0 / 3 - 4 * r * r + 4 * r * r * r;
      dw = -8 * r + 12 * r * r;
      d2w = -8 + 24 * r;
    } else {
      w = 4.0 / 3 - 4 * r + 4 * r * r - 4.0 / 3 * r * r * r;
      dw = -4 + 8 * r - 4 * r * r;
      d2w = 8 - 8 * r;
    }
  }
  double support() const override { return 1.0; }
  // The B-spline of 001 eq 14 with q = 2r: ∫ over R is 1/2 in 1D, (1/4)(7π/10)(2/3)... in 2D.
  double integral(int dim) const override {
    return dim == 1 ? 0.5 : dim == 2 ? (2.0 / 3) * 0.7 * M_PI / 4 : (2.0 / 3) * M_PI / 8;
  }
};

}  // namespace

void register_cubic_window(KernelRegistry& r) {
  r.add("cubic-window", "RKPM cubic-spline window, support r<=1 (004 II eq 6.7)", {},
        [](const Params&) { return std::make_unique<CubicWindow>(); });
}

}  // namespace mfv
