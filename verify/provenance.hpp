/// Provenance of a run: what binary produced the numbers and on what machine, for
/// `mfv --version` and the "provenance" member of every results.json (issue 28): a number
/// without the commit, compiler, build type, thread count and machine behind it cannot be
/// compared with another run's.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace mfv {

struct Provenance {
  std::string version;     ///< the project's (CMake project VERSION)
  std::string commit;      ///< git commit the binary was built from; "unknown" outside git
  bool dirty = false;      ///< tracked files differed from that commit at build time
  std::string build_type;  ///< CMAKE_BUILD_TYPE (Release, Debug, …)
  std::string compiler;    ///< compiler and version
  std::vector<std::pair<std::string, std::string>> libraries;  ///< name → version
  // The run's machine and threading: what makes CPU seconds comparable or not.
  int threads = 1;                   ///< OpenMP threads a parallel region gets (omp_get_max_threads)
  std::string omp_wait_policy;       ///< OMP_WAIT_POLICY as set ("" unset: the runtime's default)
  std::string hostname, cpu;         ///< host name; CPU model (/proc/cpuinfo)
  unsigned cores = 1;                ///< hardware threads
  double load_average = -1;          ///< 1-minute load average now; -1 when unknown
};

/// The provenance now (build facts are fixed; threads, load and host are read at the call).
Provenance provenance();

/// `mfv --version`: "mfv 0.1.0 (commit abc1234…, Release, GCC 12.2.0)" then one line per
/// library and the machine.
std::string version_text(const Provenance& p);

/// The "provenance" object of results.json (docs/schemas/results.schema.json).
nlohmann::json provenance_json(const Provenance& p);

}  // namespace mfv
