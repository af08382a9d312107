/// The list of built-in approximations: each registered in this order, which `mfv list` shows.
/// Adding one: its file in methods/approximations/ (CMake picks up every .cpp there) and one line in
/// MFV_APPROXIMATIONS below; that recompiles the new file and this unit only (docs/architecture.md).
#include "methods/approximations/register.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(ApproximationRegistry&, const KernelRegistry&)`.
#define MFV_APPROXIMATIONS(X) \
  X(shepard)                  \
  X(mls)                      \
  X(rkpm_approximation)       \
  X(sph_approximation)        \
  X(linear_elements)          \
  X(wavelet_approximation)

#define MFV_DECLARE(name) void register_##name(ApproximationRegistry&, const KernelRegistry&);
MFV_APPROXIMATIONS(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_approximations(ApproximationRegistry& r, const KernelRegistry& k) {
#define MFV_REGISTER(name) register_##name(r, k);
  MFV_APPROXIMATIONS(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
