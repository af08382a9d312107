/// Approximation registry and its one-line-per-plugin registration list.
#pragma once
#include "methods/approximations/approximation.hpp"
#include "methods/kernels/register.hpp"

namespace mfv {

using ApproximationRegistry = Registry<Approximation>;

void register_shepard(ApproximationRegistry&, const KernelRegistry&);
void register_mls(ApproximationRegistry&, const KernelRegistry&);
void register_rkpm_approximation(ApproximationRegistry&, const KernelRegistry&);
void register_sph_approximation(ApproximationRegistry&, const KernelRegistry&);
void register_linear_elements(ApproximationRegistry&, const KernelRegistry&);
void register_wavelet_approximation(ApproximationRegistry&, const KernelRegistry&);

/// Registers every approximation: add one line here for a new one.
inline void register_all_approximations(ApproximationRegistry& r, const KernelRegistry& k) {
  register_shepard(r, k);
  register_mls(r, k);
  register_rkpm_approximation(r, k);
  register_sph_approximation(r, k);
  register_linear_elements(r, k);
  register_wavelet_approximation(r, k);
}

}  // namespace mfv
