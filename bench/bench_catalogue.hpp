/// The one Catalogue (every registry filled) the benchmark programs share: built on first use,
/// once per process, whichever benchmark asks first.
#pragma once
#include "apps/catalogue.hpp"

namespace mfv::bench {

inline const Catalogue& catalogue() {
  static const Catalogue c;
  return c;
}

}  // namespace mfv::bench
