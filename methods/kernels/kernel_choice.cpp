/// The kernel choice forwarded by declaration (methods/kernels/kernel_choice.hpp).
#include "methods/kernels/kernel_choice.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/kernels/kernel_admission.hpp"

namespace mfv {

namespace {

constexpr std::string_view kPrefix = "kernel-";

}  // namespace

ParamSchema kernel_choice(const KernelRegistry& kernels, std::string def, std::string description,
                          std::vector<std::string> choices) {
  if (choices.empty()) choices = kernels.keys();
  ParamSchema out{ParamSpec::choice("kernel", std::move(def), choices, std::move(description))};
  // One `kernel-<name>` per parameter name, whichever kernels declare it: its kind and range
  // from the first such kernel; the chosen kernel's own schema checks the value again.
  std::map<std::string, std::vector<std::string>> owners;
  for (const std::string& k : choices)
    for (const ParamSpec& s : kernels.entry(k).schema) owners[s.name].push_back(k);
  for (const auto& [name, ks] : owners) {
    ParamSpec spec = *std::find_if(kernels.entry(ks.front()).schema.begin(),
                                   kernels.entry(ks.front()).schema.end(),
                                   [&](const ParamSpec& s) { return s.name == name; });
    spec.description = fmt::format("the kernel's `{}` ({}): {}; unset, the kernel's default",
                                   name, fmt::join(ks, ", "), spec.description);
    spec.name = std::string(kPrefix) + name;
    spec.aliases.clear();
    spec.optional = true;
    out.push_back(std::move(spec));
  }
  return out;
}

std::unique_ptr<Kernel> make_kernel(const KernelRegistry& kernels, const Params& p) {
  const std::string& name = p.text("kernel");
  const ParamSchema& schema = kernels.entry(name).schema;
  Params own;
  for (const auto& [key, value] : p.values()) {
    if (!key.starts_with(kPrefix)) continue;
    const std::string param = key.substr(kPrefix.size());
    if (std::none_of(schema.begin(), schema.end(),
                     [&](const ParamSpec& s) { return s.name == param; })) {
      std::vector<std::string> theirs;
      for (const ParamSpec& s : schema) theirs.push_back(std::string(kPrefix) + s.name);
      throw InputError(fmt::format(
          "'{}' is not a parameter of kernel '{}' ({}); drop it, or choose a kernel that "
          "declares `{}` (mfv list kernels)",
          key, name,
          theirs.empty() ? std::string("it takes none")
                         : fmt::format("its parameters: {}", fmt::join(theirs, ", ")),
          param));
    }
    own.set(param, value);
  }
  // A method takes only a kernel with the properties every method needs (issue 46).
  std::unique_ptr<Kernel> W = kernels.create(name, own);
  if (!W) throw InputError(fmt::format("kernel '{}' built no kernel (its factory returned null)", name));
  admit_kernel(*W, name);
  return W;
}

Params with_kernel(Params child, const Params& parent) {
  for (const auto& [key, value] : parent.values())
    if (key == "kernel" || key.starts_with(kPrefix)) child.set(key, value);
  return child;
}

}  // namespace mfv
