/// Shared helpers of the numerical tests: the catalogue with the example kernel, the registered
/// methods as test parameters, and a method's discretization where it runs.
#pragma once
#include <cctype>
#include <optional>
#include <string>
#include <vector>

#include "apps/catalogue.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

void register_wendland(KernelRegistry& r);

/// The built-in catalogue plus the example kernel of docs/architecture.md.
inline const Catalogue& test_catalogue() {
  static const Catalogue c(Extensions{{register_wendland}, {}, {}, {}, {}});
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
