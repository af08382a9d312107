// placeholder: filled in by issue #5 work (xefg, 003)
#include "methods/methods/register.hpp"
namespace mfv {
void register_xefg(MethodRegistry&, const MethodParts&) {}
}  // namespace mfv
