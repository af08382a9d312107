/// The list of built-in analyses: each registered in this order, which `mfv list` shows.
/// Adding one: its file in analyses/ (CMake picks up every .cpp there) and one line in
/// MFV_ANALYSES below; that recompiles the new file and this unit only (docs/architecture.md).
#include "analyses/analysis.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(AnalysisRegistry&)`.
#define MFV_ANALYSES(X) \
  X(static_solve)            \
  X(transient)               \
  X(dispersion_analysis)     \
  X(time_step_analysis)      \
  X(stretch_map_analysis)    \
  X(crack_sweep)

#define MFV_DECLARE(name) void register_##name(AnalysisRegistry&);
MFV_ANALYSES(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_analyses(AnalysisRegistry& r) {
#define MFV_REGISTER(name) register_##name(r);
  MFV_ANALYSES(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
