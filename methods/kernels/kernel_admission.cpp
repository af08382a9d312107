/// Admission of a kernel by the methods (methods/kernels/kernel_admission.hpp).
#include "methods/kernels/kernel_admission.hpp"

#include <cmath>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

std::string kernel_property_failure(const Kernel& W) {
  const double rs = W.support();
  if (!std::isfinite(rs) || rs <= 0)
    return fmt::format("support() = {:g}: not finite and positive", rs);
  const double w0 = W.value(0);
  if (!std::isfinite(w0) || w0 <= 0)
    return fmt::format("W(0) = {:g}: not finite and positive", w0);
  constexpr int kSamples = 64;
  for (int i = 0; i < kSamples; ++i) {
    const double s = rs * i / kSamples;
    const double w = W.value(s);
    if (!std::isfinite(w)) return fmt::format("W({:g}) = {:g}: not finite", s, w);
    if (w < 0)
      return fmt::format("W({:g}) = {:g} < 0: not positive inside its support (moment matrices "
                         "and SPH densities need W ≥ 0)",
                         s, w);
  }
  const double beyond = W.value(1.01 * rs);
  if (beyond != 0)
    return fmt::format("W({:g}) = {:g} beyond its support {:g}: the neighbour search would "
                       "miss it",
                       1.01 * rs, beyond, rs);
  const double scale = w0 / rs;
  for (double f : {0.07, 0.23, 0.31, 0.47, 0.61, 0.77, 0.89}) {
    const double s = f * rs, e = 1e-6 * rs;
    double w = 0, dw = 0;
    W.evaluate({&s, 1}, {&w, 1}, {&dw, 1}, {});
    const double fd = (W.value(s + e) - W.value(s - e)) / (2 * e);
    if (!std::isfinite(dw) || std::abs(dw - fd) > 1e-4 * (scale + std::abs(dw)))
      return fmt::format("dW/ds({:g}) = {:g} but the central difference of W gives {:g}: the "
                         "derivative is not W's",
                         s, dw, fd);
  }
  return "";
}

void admit_kernel(const Kernel& W, const std::string& name) {
  const std::string why = kernel_property_failure(W);
  if (!why.empty())
    throw InputError(fmt::format(
        "kernel '{}' is refused: {}; fix the kernel (its conformance tests: ctest -R "
        "KernelConformance) or choose another (mfv list kernels)",
        name, why));
}

}  // namespace mfv
