/// The quintic B-spline of support 3 (J. P. Morris, P. J. Fox & Y. Zhu, J. Comput. Phys. 136,
/// 214–226, 1997, eq 8; Morris's thesis 1996):
///   W(s) = C [(3 − s)⁵₊ − 6 (2 − s)⁵₊ + 15 (1 − s)⁵₊],   (x)₊ = max(x, 0),
/// C = 1/120, 7/(478π), 1/(120π) normalizing it in 1, 2, 3 dimensions (`dim`): the bracket
/// integrates to 120, 478π/7 and 120π.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class QuinticSpline final : public KernelFormula<QuinticSpline> {
 public:
  explicit QuinticSpline(int dim) : c_(1 / kRaw[dim - 1]) {}
  void formula(double s, double& w, double& dw, double& d2w) const {
    // Each term t⁵₊ with t = k − s contributes t⁵, −5t⁴, 20t³ (d/ds of t is −1).
    w = dw = d2w = 0;
    const double coefficient[3] = {1, -6, 15};
    for (int k = 3; k >= 1; --k) {
      const double t = k - s;
      if (t <= 0) continue;
      const double c = coefficient[3 - k], t2 = t * t, t3 = t2 * t;
      w += c * t3 * t2;
      dw -= 5 * c * t2 * t2;
      d2w += 20 * c * t3;
    }
    w *= c_;
    dw *= c_;
    d2w *= c_;
  }
  double support() const override { return 3.0; }
  double integral(int dim) const override { return c_ * kRaw[dim - 1]; }

 private:
  static constexpr double kRaw[3] = {120.0, 478 * M_PI / 7, 120 * M_PI};
  double c_;
};

}  // namespace

void register_quintic_spline(KernelRegistry& r) {
  r.add("quintic-spline", "quintic B-spline, support s<3 (Morris, Fox & Zhu 1997)",
        {ParamSpec::count("dim", 1, 1, "dimension whose constant C normalizes the kernel (1, 2, 3)")},
        [](const Params& p) {
          if (p.integer("dim") > 3)
            throw InputError("parameter 'dim' of kernel 'quintic-spline' must be 1, 2 or 3");
          return std::make_unique<QuinticSpline>(static_cast<int>(p.integer("dim")));
        });
}

}  // namespace mfv
