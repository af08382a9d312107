#include "verify/provenance.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include <Eigen/Core>
#include <fmt/format.h>
#include <omp.h>
#include <petscversion.h>
#include <toml++/toml.h>

namespace mfv {

namespace detail {
// build_info.cpp, written at build time by cmake/BuildInfo.cmake.
const char* build_commit();
bool build_dirty();
}  // namespace detail

namespace {

std::string compiler_text() {
#if defined(__clang__)
  return fmt::format("Clang {}.{}.{}", __clang_major__, __clang_minor__, __clang_patchlevel__);
#elif defined(__GNUC__)
  return fmt::format("GCC {}.{}.{}", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__);
#else
  return "unknown compiler";
#endif
}

/// The first "model name" of /proc/cpuinfo; "" where there is none.
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon == std::string::npos) break;
      const auto start = line.find_first_not_of(" \t", colon + 1);
      return start == std::string::npos ? "" : line.substr(start);
    }
  return "";
}

double load_average_now() {
  double load[1] = {-1};
  return ::getloadavg(load, 1) == 1 ? load[0] : -1;
}

}  // namespace

Provenance provenance() {
  Provenance p;
  p.version = MFV_VERSION;
  p.commit = detail::build_commit();
  p.dirty = detail::build_dirty();
  p.build_type = MFV_BUILD_TYPE[0] ? MFV_BUILD_TYPE : "unspecified";
  p.compiler = compiler_text();
  p.libraries = {
      {"Eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION,
                            EIGEN_MINOR_VERSION)},
      {"fmt", fmt::format("{}.{}.{}", FMT_VERSION / 10000, FMT_VERSION / 100 % 100,
                          FMT_VERSION % 100)},
      {"nlohmann_json", fmt::format("{}.{}.{}", NLOHMANN_JSON_VERSION_MAJOR,
                                    NLOHMANN_JSON_VERSION_MINOR, NLOHMANN_JSON_VERSION_PATCH)},
      {"toml++", fmt::format("{}.{}.{}", TOML_LIB_MAJOR, TOML_LIB_MINOR, TOML_LIB_PATCH)},
      {"PETSc", fmt::format("{}.{}.{}", PETSC_VERSION_MAJOR, PETSC_VERSION_MINOR,
                            PETSC_VERSION_SUBMINOR)},
      {"OpenMP", fmt::format("{}", _OPENMP)},  // the specification date, e.g. 201511 = 4.5
  };
  p.threads = omp_get_max_threads();
  if (const char* w = std::getenv("OMP_WAIT_POLICY")) p.omp_wait_policy = w;
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) == 0) p.hostname = host;
  p.cpu = cpu_model();
  const unsigned n = std::thread::hardware_concurrency();
  p.cores = n == 0 ? 1 : n;
  p.load_average = load_average_now();
  return p;
}

std::string version_text(const Provenance& p) {
  std::string out = fmt::format("mfv {} (commit {}{}, {} build, {})\n", p.version, p.commit,
                                p.dirty ? " with uncommitted changes" : "", p.build_type,
                                p.compiler);
  for (const auto& [name, version] : p.libraries) out += fmt::format("  {:<14} {}\n", name, version);
  out += fmt::format("  machine        {} cores{}{}\n", p.cores,
                     p.cpu.empty() ? "" : ", " + p.cpu,
                     p.hostname.empty() ? "" : ", host " + p.hostname);
  out += fmt::format("  threads        {} (OpenMP; OMP_WAIT_POLICY {})\n", p.threads,
                     p.omp_wait_policy.empty() ? "unset" : p.omp_wait_policy);
  return out;
}

nlohmann::json provenance_json(const Provenance& p) {
  nlohmann::json libs = nlohmann::json::object();
  for (const auto& [name, version] : p.libraries) libs[name] = version;
  nlohmann::json out = {
      {"version", p.version},
      {"commit", p.commit},
      {"dirty", p.dirty},
      {"build_type", p.build_type},
      {"compiler", p.compiler},
      {"libraries", libs},
      {"threads", p.threads},
      {"omp_wait_policy", p.omp_wait_policy.empty() ? nlohmann::json(nullptr)
                                                    : nlohmann::json(p.omp_wait_policy)},
      {"hostname", p.hostname},
      {"cpu", p.cpu},
      {"cores", p.cores},
      {"load_average", p.load_average >= 0 ? nlohmann::json(p.load_average)
                                           : nlohmann::json(nullptr)},
  };
  return out;
}

}  // namespace mfv
