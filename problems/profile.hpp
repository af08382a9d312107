/// Curves over space at one time that a problem measures (σθθ around a ring, a stress
/// profile through a wall against a reference); the reports overlay the curves of one title
/// across studies in one plot.
#pragma once
#include <string>
#include <vector>

namespace mfv {

struct Profile {
  std::string title, xlabel, ylabel;
  std::vector<std::string> labels;
  std::vector<std::vector<double>> x, y;  ///< one curve per label
};

}  // namespace mfv
