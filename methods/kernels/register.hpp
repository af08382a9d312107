/// Kernel registry type and the entry point of the built-in kernels (the list is in register_all.cpp).
#pragma once
#include "methods/core/registry.hpp"
#include "methods/kernels/kernel.hpp"

namespace mfv {

using KernelRegistry = Registry<Kernel>;

/// Registers every built-in kernel, in the order of the list in methods/kernels/register_all.cpp.
void register_all_kernels(KernelRegistry& r);

}  // namespace mfv
