// placeholder: filled in by issue #5 work (enriched-bar, 003)
#include "problems/problem.hpp"
namespace mfv {
void register_enriched_bar(ProblemRegistry&) {}
}  // namespace mfv
