/// Weight functions (kernels) W(s) of the normalized distance s = |x - x_J| / a, with
/// dW/ds and d²W/ds², evaluated per batch of points (one virtual call per batch).
#pragma once
#include <cmath>
#include <memory>
#include <span>
#include <string>

namespace mfv {

class Kernel {
 public:
  virtual ~Kernel() = default;
  /// W, dW/ds, d²W/ds² at every s (s >= 0). Any output span may be empty to skip it.
  virtual void evaluate(std::span<const double> s, std::span<double> w, std::span<double> dw,
                        std::span<double> d2w) const = 0;
  /// W(s) = 0 for s >= support(); for the Gaussian the truncation radius.
  virtual double support() const = 0;
  /// ∫ W(|x|) dx over R^dim (dim = 1, 2, 3): 1 for normalized SPH kernels.
  virtual double integral(int dim) const = 0;

  double value(double s) const {
    double w = 0;
    evaluate({&s, 1}, {&w, 1}, {}, {});
    return w;
  }
};

/// The dilation a whose support reaches `radius`: W vanishes for s = r/a >= support(), so
/// a = radius / support(). With the radius over the spacing (dmax) it is a over Δx; the one
/// place where "dmax over the kernel's support" is written.
inline double dilation_for_radius(const Kernel& W, double radius) { return radius / W.support(); }

/// Helper that turns a scalar formula into a batch kernel. Derived supplies
/// `static void formula(double s, double& w, double& dw, double& d2w)` for s < support.
template <class Derived>
class KernelFormula : public Kernel {
 public:
  void evaluate(std::span<const double> s, std::span<double> w, std::span<double> dw,
                std::span<double> d2w) const final {
    const auto& self = static_cast<const Derived&>(*this);
    const double rs = self.support();
    for (std::size_t i = 0; i < s.size(); ++i) {
      double a = 0, b = 0, c = 0;
      if (s[i] < rs) self.formula(s[i], a, b, c);
      if (!w.empty()) w[i] = a;
      if (!dw.empty()) dw[i] = b;
      if (!d2w.empty()) d2w[i] = c;
    }
  }
};

}  // namespace mfv
