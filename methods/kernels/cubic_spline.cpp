/// Normalized cubic B-spline, support 2 (001 eqs 14-15):
/// W = C(1 - 1.5q² + 0.75q³) for q < 1, C/4 (2 - q)³ for 1 <= q < 2, C = 2/3, 10/(7π), 1/π.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class CubicSpline final : public KernelFormula<CubicSpline> {
 public:
  explicit CubicSpline(int dim) : c_(dim == 1 ? 2.0 / 3 : dim == 2 ? 10 / (7 * M_PI) : 1 / M_PI), dim_(dim) {}
  void formula(double q, double& w, double& dw, double& d2w) const {
    if (q < 1) {
      w = c_ * (1 - 1.5 * q * q + 0.75 * q * q * q);
      dw = c_ * (-3 * q + 2.25 * q * q);
      d2w = c_ * (-3 + 4.5 * q);
    } else {
      const double t = 2 - q;
      w = c_ * 0.25 * t * t * t;
      dw = -c_ * 0.75 * t * t;
      d2w = c_ * 1.5 * t;
    }
  }
  double support() const override { return 2.0; }
  double integral(int dim) const override {
    // The constant normalizes the kernel in its own dimension; elsewhere scale accordingly.
    const double raw1 = 1.5, raw2 = 0.7 * M_PI, raw3 = M_PI;  // ∫ of the bracket, C = 1
    const double raw = dim == 1 ? raw1 : dim == 2 ? raw2 : raw3;
    return c_ * raw;
  }
  int dim() const { return dim_; }

 private:
  double c_;
  int dim_;
};

}  // namespace

void register_cubic_spline(KernelRegistry& r) {
  r.add("cubic-spline", "normalized cubic B-spline, support q<2 (001 eqs 14-15)",
        {ParamSpec::count("dim", 1, 1, "dimension whose constant C is used (2/3, 10/7pi, 1/pi)")},
        [](const Params& p) {
          if (p.integer("dim") > 3)
            throw InputError("parameter 'dim' of kernel 'cubic-spline' must be 1, 2 or 3");
          return std::make_unique<CubicSpline>(p.integer("dim"));
        });
}

}  // namespace mfv
