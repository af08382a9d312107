/// The list of built-in materials: each registered in this order, which `mfv list` shows.
/// Adding one: its file in methods/materials/ (CMake picks up every .cpp there) and one line in
/// MFV_MATERIALS below; that recompiles the new file and this unit only (docs/architecture.md).
#include "methods/materials/material.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(MaterialRegistry&)`.
#define MFV_MATERIALS(X) \
  X(svk)                \
  X(plastic_1d)         \
  X(hyperelastic)       \
  X(j2_jaumann)         \
  X(j2_viscoplastic)    \
  X(tait)

#define MFV_DECLARE(name) void register_##name(MaterialRegistry&);
MFV_MATERIALS(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_materials(MaterialRegistry& r) {
#define MFV_REGISTER(name) register_##name(r);
  MFV_MATERIALS(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
