/// Wendland's compactly supported kernels C2, C4 and C6 (H. Wendland, Adv. Comput. Math. 4,
/// 389–396, 1995; as SPH kernels: W. Dehnen & H. Aly, MNRAS 425, 1068–1082, 2012, Table 1),
/// the functions positive definite in up to three dimensions (so in 1D and 2D too):
///   C2: f(r) = (1 − r)⁴ (1 + 4r)
///   C4: f(r) = (1 − r)⁶ (1 + 6r + 35/3 r²)
///   C6: f(r) = (1 − r)⁸ (1 + 8r + 25r² + 32r³),     r = s/2 < 1,
/// W(s) = C f(s/2) with support s < 2 like the cubic spline, and C normalizing W in the
/// dimension `dim`: C = 1/raw(dim) with raw = ∫ f(|x|/2) dx over R^dim,
///   C2: 4/3, 4π/7, 16π/21;  C4: 32/27, 4π/9, 256π/495;  C6: 16/15, 14π/39, 512π/1365,
/// i.e. Dehnen & Aly's 7/π, 21/(2π), 9/π, 495/(32π), 78/(7π), 1365/(64π) for H = 2 in 2D/3D.
/// Not the tests' example kernel `example-lucy` (tests/example_kernel.cpp), Lucy's
/// (1 − s)³(1 + 3s) = Wendland's ψ₂,₁, which is positive definite in 1D only.
#include <array>

#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

enum class Smoothness { c2, c4, c6 };

/// raw(dim) of the header, dim = 1, 2, 3.
std::array<double, 3> raw_integrals(Smoothness k) {
  switch (k) {
    case Smoothness::c2: return {4.0 / 3, 4 * M_PI / 7, 16 * M_PI / 21};
    case Smoothness::c4: return {32.0 / 27, 4 * M_PI / 9, 256 * M_PI / 495};
    case Smoothness::c6: return {16.0 / 15, 14 * M_PI / 39, 512 * M_PI / 1365};
  }
  return {};
}

class Wendland final : public KernelFormula<Wendland> {
 public:
  Wendland(Smoothness k, int dim) : k_(k), raw_(raw_integrals(k)), c_(1 / raw_[dim - 1]) {}
  void formula(double s, double& w, double& dw, double& d2w) const {
    // f, f' and f'' at r = s/2; the chain rule gives dW/ds = C f'/2, d²W/ds² = C f''/4.
    const double r = 0.5 * s, u = 1 - r, u2 = u * u, u4 = u2 * u2;
    double f = 0, d = 0, d2 = 0;
    switch (k_) {
      case Smoothness::c2:
        f = u4 * (1 + 4 * r);
        d = -20 * r * u2 * u;
        d2 = 20 * u2 * (4 * r - 1);
        break;
      case Smoothness::c4:
        f = u4 * u2 * (1 + 6 * r + 35.0 / 3 * r * r);
        d = -56.0 / 3 * r * (1 + 5 * r) * u4 * u;
        d2 = 56.0 / 3 * u4 * (35 * r * r - 4 * r - 1);
        break;
      case Smoothness::c6:
        f = u4 * u4 * (1 + 8 * r + 25 * r * r + 32 * r * r * r);
        d = -22 * r * (1 + 7 * r + 16 * r * r) * u4 * u2 * u;
        d2 = 22 * u4 * u2 * (160 * r * r * r + 15 * r * r - 6 * r - 1);
        break;
    }
    w = c_ * f;
    dw = 0.5 * c_ * d;
    d2w = 0.25 * c_ * d2;
  }
  double support() const override { return 2.0; }
  double integral(int dim) const override { return c_ * raw_[dim - 1]; }

 private:
  Smoothness k_;
  std::array<double, 3> raw_;
  double c_;
};

void add(KernelRegistry& r, const char* name, Smoothness k, const char* what) {
  r.add(name, what,
        {ParamSpec::count("dim", 1, 1, "dimension whose constant C normalizes the kernel (1, 2, 3)")},
        [name, k](const Params& p) {
          if (p.integer("dim") > 3)
            throw InputError(fmt::format("parameter 'dim' of kernel '{}' must be 1, 2 or 3", name));
          return std::make_unique<Wendland>(k, static_cast<int>(p.integer("dim")));
        });
}

}  // namespace

void register_wendland_kernels(KernelRegistry& r) {
  add(r, "wendland-c2", Smoothness::c2,
      "Wendland C2 (1-r)^4(1+4r), r = s/2 < 1, positive definite up to 3D (Dehnen & Aly 2012)");
  add(r, "wendland-c4", Smoothness::c4,
      "Wendland C4 (1-r)^6(1+6r+35r^2/3), r = s/2 < 1 (Dehnen & Aly 2012)");
  add(r, "wendland-c6", Smoothness::c6,
      "Wendland C6 (1-r)^8(1+8r+25r^2+32r^3), r = s/2 < 1 (Dehnen & Aly 2012)");
}

}  // namespace mfv
