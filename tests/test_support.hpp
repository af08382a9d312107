/// Shared helpers of the numerical tests: the catalogue with the example kernel, the registered
/// methods as test parameters, and a method's discretization where it runs.
#pragma once
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "apps/catalogue.hpp"
#include "apps/plugins.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

void register_example_lucy(KernelRegistry& r);

/// The plugin libraries named by the environment variable MFV_PLUGINS (':'-separated), so an
/// out-of-tree kernel or method runs through every conformance test here:
/// `MFV_PLUGINS=libmine.so test_core --gtest_filter='*Conformance*:*Patch*'`.
inline std::vector<std::filesystem::path> plugins_from_environment() {
  std::vector<std::filesystem::path> out;
  const char* env = std::getenv("MFV_PLUGINS");
  for (std::string rest = env ? env : ""; !rest.empty();) {
    const auto colon = rest.find(':');
    if (colon != 0) out.emplace_back(rest.substr(0, colon));
    rest = colon == std::string::npos ? "" : rest.substr(colon + 1);
  }
  return out;
}

/// The tests' extensions: the example kernel of docs/architecture.md, then the plugins of
/// MFV_PLUGINS (loaded once).
inline Extensions test_extensions() {
  static const Plugins plugins(plugins_from_environment());
  Extensions e = plugins.extensions();
  e.kernels.insert(e.kernels.begin(), register_example_lucy);
  return e;
}

/// The built-in catalogue plus test_extensions().
inline const Catalogue& test_catalogue() {
  static const Catalogue c(test_extensions());
  return c;
}

/// Every registered method, so a parameterized test covers a method the moment it is
/// registered.
inline std::vector<std::string> registered_methods() { return test_catalogue().methods.keys(); }

/// The registered methods whose schema declares parameter `name` (e.g. vci).
inline std::vector<std::string> methods_with_parameter(const std::string& name) {
  std::vector<std::string> out;
  for (const std::string& m : registered_methods())
    for (const ParamSpec& s : test_catalogue().methods.entry(m).schema)
      if (s.name == name) out.push_back(m);
  return out;
}

/// A method name as part of a test name: "kbm-si" → "kbm_si".
inline std::string test_name(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

/// `method` discretized on `particles`, or nothing when the method refuses the domain with
/// InputError (an approximation implemented in 1D only refuses a 2D domain): then `refusal`
/// holds its reason, which the test reports as it skips.
inline std::optional<Discretization> discretize_if_supported(const std::string& method,
                                                             const Params& params,
                                                             const Domain& domain,
                                                             const ParticleSet& particles,
                                                             std::string& refusal) {
  try {
    return test_catalogue().methods.create(method, params)->discretize(domain, particles, 1);
  } catch (const InputError& e) {
    refusal = method + " does not run here: " + e.what();
    return std::nullopt;
  }
}

}  // namespace mfv
