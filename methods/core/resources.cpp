#include "methods/core/resources.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

/// A "<key>: <n> kB" line of a /proc file, in bytes; 0 when absent.
std::uint64_t proc_kb(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) != 0) continue;
    std::istringstream s(line.substr(key.size()));
    std::uint64_t kb = 0;
    if (s >> kb) return kb * 1024;
  }
  return 0;
}

}  // namespace

std::uint64_t available_memory_bytes() {
  std::uint64_t have = proc_kb("/proc/meminfo", "MemAvailable:");
  if (have == 0) {
    const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) have = static_cast<std::uint64_t>(pages) * page;
  }
  // Under `ulimit -v` (RLIMIT_AS) the process can map only what its limit leaves over its
  // present address space, whatever the machine has free.
  rlimit lim{};
  if (::getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    const std::uint64_t used = proc_kb("/proc/self/status", "VmSize:");
    const std::uint64_t left = lim.rlim_cur > used ? lim.rlim_cur - used : 1;
    have = have == 0 ? left : std::min(have, left);
  }
  return have;
}

std::int64_t checked_particle_count(std::int64_t nx, std::int64_t ny, std::string_view what) {
  constexpr std::int64_t limit = std::numeric_limits<int>::max();
  if (nx < 0 || ny < 0)
    throw InputError(fmt::format("{}: negative particle count {} × {}; give a positive --nodes",
                                 what, nx, ny));
  // The product is formed only when both factors are below 2^31, so it fits in 64 bits.
  if (nx > limit || ny > limit || nx * ny > limit)
    throw InputError(fmt::format("{}: {} × {} = {} particles exceed the 2^31 - 1 the shape tables "
                                 "can index; lower --nodes (or the parameter that sets the "
                                 "particle count)",
                                 what, nx, ny, static_cast<double>(nx) * static_cast<double>(ny)));
  return nx * ny;
}

void check_case_memory(std::int64_t particles, int dim, std::string_view what) {
  const double per = dim == 1 ? kBytesPerParticle1D : kBytesPerParticle2D;
  const double need = static_cast<double>(particles) * per;
  const std::uint64_t have = available_memory_bytes();
  if (have == 0 || need <= static_cast<double>(have)) return;
  throw InputError(fmt::format(
      "{}: {} particles need at least {:.3g} GB (about {:.0f} KB per particle in {}D with the "
      "cheapest method), but only {:.3g} GB of memory is available; lower --nodes (or the "
      "parameter that sets the particle count)",
      what, particles, need / 1e9, per / 1e3, dim, static_cast<double>(have) / 1e9));
}

}  // namespace mfv
