// placeholder: filled in by issue #5 work (critical time step analyses)
#include "problems/problem.hpp"
namespace mfv {
void register_time_step(ProblemRegistry&) {}
}  // namespace mfv
