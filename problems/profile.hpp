/// Curves over space at one time that a problem measures (σθθ around a ring, a stress
/// profile through a wall against a reference); the reports overlay the curves of one title
/// across studies in one plot.
#pragma once
#include <string>
#include <vector>

#include "reports/plot.hpp"

namespace mfv {

struct Profile {
  std::string title, xlabel, ylabel;  ///< axis labels carry their units
  std::vector<std::string> labels;
  std::vector<std::vector<double>> x, y;  ///< one curve per label
  /// What each curve is (reports/plot.hpp SeriesRole); curves past its end are computed.
  /// A reference, data or band curve is the problem's, not the method's: the report draws it
  /// once per plot however many studies carry it. Two consecutive `band` curves on the same x
  /// are the edges of one shaded band, named by the first's label.
  std::vector<SeriesRole> roles = {};

  SeriesRole role(std::size_t curve) const {
    return curve < roles.size() ? roles[curve] : SeriesRole::computed;
  }
};

}  // namespace mfv
