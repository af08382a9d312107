/// The benchmark programs' memory counters: this process's resident memory now (VmRSS) and
/// at its peak (VmHWM) from /proc/self/status, and the reset of the peak, so each case can
/// report its own.
#pragma once
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

namespace mfv::bench {

/// A "Key:  <n> kB" line of /proc/self/status in bytes; 0 when it is unreadable (not Linux).
inline std::uint64_t status_bytes(const char* key) {
  std::ifstream in("/proc/self/status");
  const std::string prefix = std::string(key) + ":";
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0)
      return std::strtoull(line.c_str() + prefix.size(), nullptr, 10) * 1024;
  return 0;
}

inline double resident_gb() { return status_bytes("VmRSS") / (1024.0 * 1024.0 * 1024.0); }
inline double peak_resident_gb() { return status_bytes("VmHWM") / (1024.0 * 1024.0 * 1024.0); }
inline std::uint64_t peak_resident_bytes() { return status_bytes("VmHWM"); }

/// Starts a new peak: writing 5 to clear_refs sets VmHWM to the current resident size
/// (Linux >= 4.0), so each benchmark's peak is its own, not the run's so far.
inline void reset_peak_resident() { std::ofstream("/proc/self/clear_refs") << "5"; }

}  // namespace mfv::bench
