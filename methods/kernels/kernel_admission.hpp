/// The properties every method of mfv needs of a weight function, checked when a method takes a
/// kernel (issue 46): a kernel that fails the conformance checks is refused with the failed check
/// named, instead of running to H1 rates of −1.31 with exit 0.
///
/// Every method weights by W: MLS/RK moment matrices M = Σ W_J p p^T are positive definite only
/// for W ≥ 0 (with W(0) > 0), SPH densities ρ_I = Σ m_J W_IJ are positive only for it, and
/// every method differentiates W, so dW/ds must be dW/ds. The checks are those of
/// tests/test_kernels.cpp (KernelConformance), at a looser tolerance and on fewer points:
///   1. support() finite and > 0;
///   2. W(0) finite and > 0; W finite and ≥ 0 on [0, support);
///   3. W = 0 beyond the support (at 1.01 support);
///   4. dW/ds against a central difference of W at seven interior points,
///      |dW − ΔW/Δs| ≤ 1e-4 (W(0)/support + |dW|).
#pragma once
#include <string>

#include "methods/kernels/kernel.hpp"

namespace mfv {

/// Empty when W passes, otherwise the first failed check with its value ("W(0.42) = −0.013 <
/// 0: not positive inside its support").
std::string kernel_property_failure(const Kernel& W);

/// InputError naming kernel `name` and the failed check when W fails one.
void admit_kernel(const Kernel& W, const std::string& name);

}  // namespace mfv
