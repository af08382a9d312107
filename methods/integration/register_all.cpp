/// The list of built-in integration schemes: each registered in this order, which `mfv list` shows.
/// Adding one: its file in methods/integration/ (CMake picks up every .cpp there) and one line in
/// MFV_INTEGRATIONS below; that recompiles the new file and this unit only (docs/architecture.md).
#include "methods/integration/integration.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(IntegrationRegistry&)`.
#define MFV_INTEGRATIONS(X) \
  X(nodal)            \
  X(gauss_cells)      \
  X(stress_points)

#define MFV_DECLARE(name) void register_##name(IntegrationRegistry&);
MFV_INTEGRATIONS(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_integrations(IntegrationRegistry& r) {
#define MFV_REGISTER(name) register_##name(r);
  MFV_INTEGRATIONS(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
