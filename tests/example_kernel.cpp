/// Worked example of docs/architecture.md: a new kernel in one file. Lucy's kernel (Lucy 1977,
/// the first SPH kernel), W(s) = (1 − s)³ (1 + 3s) for s ≤ 1: Wendland's ψ₂,₁, positive
/// definite in 1D only. Registered as `example-lucy`, a name no real kernel takes, by the
/// tests' catalogue (tests/test_support.hpp) as an extension; in the tree, a kernel file in
/// methods/kernels/ and its line in methods/kernels/register_all.cpp do the same.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class Lucy final : public KernelFormula<Lucy> {
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

void register_example_lucy(KernelRegistry& r) {
  r.add("example-lucy",
        "Lucy's kernel (1-s)^3 (1+3s), support s<=1 (Lucy 1977; docs/architecture.md's example)",
        {}, [](const Params&) { return std::make_unique<Lucy>(); });
}

}  // namespace mfv
