/// The list of built-in kernels: each registered in this order, which `mfv list` shows.
/// Adding one: its file in methods/kernels/ (CMake picks up every .cpp there) and one line in
/// MFV_KERNELS below; that recompiles the new file and this unit only (docs/architecture.md).
#include "methods/kernels/register.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(KernelRegistry&)`.
#define MFV_KERNELS(X) \
  X(quartic_spline)      \
  X(exponential)         \
  X(cubic_spline)        \
  X(cubic_window)        \
  X(gaussian)            \
  X(wendland_kernels)    \
  X(quintic_spline)

#define MFV_DECLARE(name) void register_##name(KernelRegistry&);
MFV_KERNELS(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_kernels(KernelRegistry& r) {
#define MFV_REGISTER(name) register_##name(r);
  MFV_KERNELS(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
