/// The list of built-in problems: each registered in this order, which `mfv list` shows.
/// Adding one: its file in problems/ (CMake picks up every .cpp there) and one line in
/// MFV_PROBLEMS below; that recompiles the new file and this unit only (docs/architecture.md).
#include "problems/register.hpp"

namespace mfv {

// One line per plugin file: the <name> of its `void register_<name>(ProblemRegistry&)`.
#define MFV_PROBLEMS(X) \
  X(laplace_tanh)           \
  X(advection_diffusion)    \
  X(cantilever)             \
  X(elastic_patch)          \
  X(rod_pulse)              \
  X(prestressed_rod)        \
  X(grk_bar)                \
  X(dispersion)             \
  X(time_step)              \
  X(enriched_bar)           \
  X(stretch_map)            \
  X(rings)                  \
  X(funnel)                 \
  X(plate)                  \
  X(notched_beam)           \
  X(hydrostatic_column)     \
  X(dam_break)              \
  X(oscillating_plate)      \
  X(manufactured)

#define MFV_DECLARE(name) void register_##name(ProblemRegistry&);
MFV_PROBLEMS(MFV_DECLARE)
#undef MFV_DECLARE

void register_all_problems(ProblemRegistry& r) {
#define MFV_REGISTER(name) register_##name(r);
  MFV_PROBLEMS(MFV_REGISTER)
#undef MFV_REGISTER
}

}  // namespace mfv
