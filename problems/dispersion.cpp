// placeholder: filled in by issue #5 work (dispersion analyses, 000)
#include "problems/problem.hpp"
namespace mfv {
void register_dispersion(ProblemRegistry&) {}
}  // namespace mfv
