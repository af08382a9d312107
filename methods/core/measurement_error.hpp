/// A run that ended but whose measurement could not be taken: the oscillating plate's period
/// from fewer than two zero crossings of its tip. The case fails with the reason (never a
/// blank or zero number) and, in `mfv compare` and `mfv verify`, the other cases still run;
/// `mfv run` exits 1 with it. (Apart from methods/core/errors.hpp, which ~all of mfv includes,
/// so that the problems that throw it and the commands that catch it are all a new error
/// type recompiles.)
#pragma once
#include <stdexcept>

namespace mfv {

class MeasurementError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mfv
