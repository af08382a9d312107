/// Approximation registry type and the entry point of the built-in approximations (the list is in
/// register_all.cpp).
#pragma once
#include "methods/approximations/approximation.hpp"
#include "methods/kernels/register.hpp"

namespace mfv {

using ApproximationRegistry = Registry<Approximation>;

/// Registers every built-in approximation (the list: methods/approximations/register_all.cpp).
void register_all_approximations(ApproximationRegistry& r, const KernelRegistry& k);

}  // namespace mfv
