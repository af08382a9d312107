/// Process CPU time, the clock every CPU figure of the reports is read from.
#pragma once
#include <ctime>

namespace mfv {

/// Process CPU time in seconds (all threads: OpenMP loops count in full).
inline double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace mfv
