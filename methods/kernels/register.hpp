/// Kernel registry type and the one-line-per-kernel registration list.
#pragma once
#include "methods/core/registry.hpp"
#include "methods/kernels/kernel.hpp"

namespace mfv {

using KernelRegistry = Registry<Kernel>;

void register_quartic_spline(KernelRegistry&);
void register_exponential(KernelRegistry&);
void register_cubic_spline(KernelRegistry&);
void register_cubic_window(KernelRegistry&);
void register_gaussian(KernelRegistry&);
void register_wendland_kernels(KernelRegistry&);  // wendland-c2, -c4, -c6
void register_quintic_spline(KernelRegistry&);

/// Registers every kernel: add one line here for a new kernel.
inline void register_all_kernels(KernelRegistry& r) {
  register_quartic_spline(r);
  register_exponential(r);
  register_cubic_spline(r);
  register_cubic_window(r);
  register_gaussian(r);
  register_wendland_kernels(r);
  register_quintic_spline(r);
}

}  // namespace mfv
