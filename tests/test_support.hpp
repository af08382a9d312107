/// Shared helpers of the numerical tests: the catalogue with the example kernel, particle sets.
#pragma once
#include "apps/catalogue.hpp"

namespace mfv {

void register_wendland(KernelRegistry& r);

/// The built-in catalogue plus the example kernel of docs/architecture.md.
inline const Catalogue& test_catalogue() {
  static const Catalogue c(Extensions{{register_wendland}, {}, {}, {}});
  return c;
}

}  // namespace mfv
