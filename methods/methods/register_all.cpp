/// The list of built-in methods: each registered in this order, which `mfv list` shows.
/// Adding one: its file in methods/methods/ (CMake picks up every .cpp there) and one line in
/// MFV_METHODS below; that recompiles the new file and this unit only (docs/architecture.md).
#include "methods/methods/register.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(MethodRegistry&, const MethodParts&)`.
#define MFV_METHODS(X) \
  X(fem)        \
  X(efg)        \
  X(rkpm)       \
  X(sph)        \
  X(wavelet)    \
  X(rlm)        \
  X(kbm)        \
  X(efg_ni)     \
  X(efg_ci)     \
  X(xefg)

#define MFV_DECLARE(name) void register_##name(MethodRegistry&, const MethodParts&);
MFV_METHODS(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_methods(MethodRegistry& r, const MethodParts& parts) {
#define MFV_REGISTER(name) register_##name(r, parts);
  MFV_METHODS(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
