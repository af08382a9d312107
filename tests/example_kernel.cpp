/// Worked example of docs/architecture.md: a new kernel in one file. Wendland-type C2 weight
/// W(s) = (1 - s)³ (1 + 3s) for s <= 1. In-tree, add `register_wendland(r);` to
/// register_all_kernels (methods/kernels/register.hpp); this test passes it as an extension.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class Wendland final : public KernelFormula<Wendland> {
 public:
  void formula(double s, double& w, double& dw, double& d2w) const {
    const double t = 1 - s;
    w = t * t * t * (1 + 3 * s);
    dw = -12 * s * t * t;
    d2w = -12 * t * (1 - 3 * s);
  }
  double support() const override { return 1.0; }
  // ∫ W over R^d: 1D 4/5; 2D 2π∫ s W ds = π/5; 3D 4π∫ s² W ds = 16π/105 (Beta integrals).
  double integral(int dim) const override {
    return dim == 1 ? 0.8 : dim == 2 ? M_PI / 5 : 16 * M_PI / 105;
  }
};

}  // namespace

void register_wendland(KernelRegistry& r) {
  r.add("wendland", "Wendland-type C2 weight (1-s)^3 (1+3s), support s<=1 (example plugin)", {},
        [](const Params&) { return std::make_unique<Wendland>(); });
}

}  // namespace mfv
