/// Gaussian window W(s) = exp(-s²)/√π (004 II eq 6.8a, normalized in 1D), truncated at s = cutoff.
#include "methods/kernels/register.hpp"

namespace mfv {
namespace {

class Gaussian final : public KernelFormula<Gaussian> {
 public:
  explicit Gaussian(double cutoff) : cutoff_(cutoff) {}
  void formula(double s, double& w, double& dw, double& d2w) const {
    w = std::exp(-s * s) / std::sqrt(M_PI);
    dw = -2 * s * w;
    d2w = (4 * s * s - 2) * w;
  }
  double support() const override { return cutoff_; }
  // Untruncated integrals (the tail beyond the cutoff is below e^{-cutoff²}).
  double integral(int dim) const override { return std::pow(std::sqrt(M_PI), dim - 1); }

 private:
  double cutoff_;
};

}  // namespace

void register_gaussian(KernelRegistry& r) {
  r.add("gaussian", "exp(-s^2)/sqrt(pi) (004 II eq 6.8a), truncated at s = cutoff",
        {ParamSpec::positive("cutoff", 6.0, "truncation radius in units of the dilation")},
        [](const Params& p) { return std::make_unique<Gaussian>(p.number("cutoff")); });
}

}  // namespace mfv
