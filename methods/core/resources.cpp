#include "methods/core/resources.hpp"

#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <unistd.h>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

std::uint64_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("MemAvailable:", 0) != 0) continue;
    std::istringstream s(line.substr(13));
    std::uint64_t kb = 0;
    if (s >> kb) return kb * 1024;
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) return static_cast<std::uint64_t>(pages) * page;
  return 0;
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
