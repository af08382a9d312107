/// One published number against ours: the ratio, the difference and a verdict computed from a
/// stated tolerance (the ledger and the problem pages share it, so they never disagree).
#pragma once
#include <string>

namespace mfv {

/// How a row compares ours with the paper's value.
enum class CompareBy {
  ratio,       ///< reproduced when |ours / published − 1| ≤ tolerance
  difference,  ///< reproduced when |ours − published| ≤ tolerance (absolute, in the quantity's units)
};

/// Verdict words, in the order the ledger counts them.
inline constexpr const char* kReproduced = "reproduced";
inline constexpr const char* kReproducedReading = "reproduced under a stated reading";
inline constexpr const char* kPartly = "partly";
inline constexpr const char* kNotReproduced = "not reproduced";
inline constexpr const char* kNotReached = "not reached";  ///< ours is missing or non-finite
inline constexpr const char* kNotYetBuilt = "not yet built";

struct Comparison {
  double ratio = 0;       ///< ours / published (NaN when either is missing or published is 0)
  double difference = 0;  ///< ours − published
  /// kReproduced, kPartly (within 3× the tolerance), kNotReproduced, or kNotReached.
  std::string verdict;
};

/// Compares `ours` with `published` under `tolerance` (> 0, finite; std::invalid_argument
/// otherwise). A non-finite `ours` is kNotReached, never a match.
Comparison compare_value(double ours, double published, double tolerance,
                         CompareBy by = CompareBy::ratio);

}  // namespace mfv
