/// Size checks before allocating: particle counts in 64-bit, and a lower-bound estimate of the
/// memory a case needs against what the machine has, so an impossible case is refused with
/// its estimate instead of exhausting memory or overflowing an int.
#pragma once
#include <cstdint>
#include <string_view>

namespace mfv {

/// Lower bounds of the resident memory per particle of a whole static case (particles, shape
/// tables, quadrature, sparse system, error rules), measured with the cheapest method (fem:
/// 1D 3.3 KB, 2D 13 KB per particle; efg, sph and rkpm need 1.5-10 times more).
inline constexpr double kBytesPerParticle1D = 3.0e3;
inline constexpr double kBytesPerParticle2D = 12.0e3;

/// Memory the process can still get: /proc/meminfo MemAvailable (or sysconf when that is
/// unreadable), and under an address-space limit (ulimit -v, RLIMIT_AS) at most what the limit
/// leaves over the present VmSize; 0 when nothing tells.
std::uint64_t available_memory_bytes();

/// nx · ny in 64-bit; throws InputError naming `what` when the product exceeds the int
/// indices every table uses (2^31 - 1) or a factor is negative.
std::int64_t checked_particle_count(std::int64_t nx, std::int64_t ny, std::string_view what);

/// Throws InputError when `particles` particles of dimension `dim` need more memory than is
/// available: the message names `what`, the estimate and the available memory.
void check_case_memory(std::int64_t particles, int dim, std::string_view what);

}  // namespace mfv
