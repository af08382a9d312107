#include "problems/comparison.hpp"

#include <cmath>
#include <stdexcept>

namespace mfv {

Comparison compare_value(double ours, double published, double tolerance, CompareBy by) {
  if (!(tolerance > 0) || !std::isfinite(tolerance))
    throw std::invalid_argument("a comparison tolerance must be positive and finite");
  Comparison c;
  c.difference = ours - published;
  c.ratio = (std::isfinite(ours) && std::isfinite(published) && published != 0)
                ? ours / published
                : NAN;
  if (!std::isfinite(ours) || !std::isfinite(published)) {
    c.verdict = kNotReached;
    return c;
  }
  const double gap = by == CompareBy::ratio
                         ? (published != 0 ? std::abs(c.ratio - 1) : std::abs(c.difference))
                         : std::abs(c.difference);
  c.verdict = gap <= tolerance ? kReproduced : gap <= 3 * tolerance ? kPartly : kNotReproduced;
  return c;
}

}  // namespace mfv
