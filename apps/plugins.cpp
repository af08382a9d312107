/// dlopen-based plugin loading (apps/plugins.hpp).
#include "apps/plugins.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <system_error>

#include <fmt/format.h>

#include "apps/plugin.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

namespace {

constexpr const char* kHowToBuild =
    "build the plugin against this mfv's installation (find_package(mfv CONFIG) with "
    "CMAKE_PREFIX_PATH set to its prefix; examples/plugin/ shows how)";

/// `hook` with every exception turned into an InputError that names the plugin: what a
/// plugin registers is the user's input, and a clash ("kernel 'gaussian' registered twice")
/// is fixed in the plugin.
template <class... Args>
std::function<void(Args...)> naming(const std::string& plugin, std::function<void(Args...)> hook) {
  return [plugin, hook = std::move(hook)](Args... args) {
    try {
      hook(args...);
    } catch (const std::exception& e) {
      throw InputError(fmt::format("plugin '{}': {}; fix the plugin's registration (a name "
                                   "must be new: `mfv list` names the registered ones)",
                                   plugin, e.what()));
    }
  };
}

template <class Hook>
void append(std::vector<Hook>& to, const std::vector<Hook>& from, const std::string& plugin) {
  for (const auto& h : from) to.push_back(naming(plugin, h));
}

}  // namespace

Plugins::Plugins(const std::vector<std::filesystem::path>& paths) {
  for (const auto& path : paths) {
    const std::string given = path.string();
    std::error_code ec;
    if (given.empty())
      throw InputError("--plugin '' names no file; give the path of a plugin library (.so)");
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
      throw InputError(fmt::format("plugin '{}': no such file; give the path of a plugin "
                                   "library (.so) built with MFV_PLUGIN (examples/plugin/)",
                                   given));
    if (!std::filesystem::is_regular_file(status))
      throw InputError(fmt::format("plugin '{}' is not a regular file (a {}); give the path of "
                                   "a plugin library (.so)",
                                   given,
                                   std::filesystem::is_directory(status) ? "directory"
                                                                         : "special file"));
    const std::string resolved = std::filesystem::canonical(path).string();
    if (std::find(loaded_.begin(), loaded_.end(), resolved) != loaded_.end()) continue;

    // RTLD_NOW: a symbol the plugin needs and this mfv lacks fails here, with its name, not
    // at the first call. RTLD_LOCAL: two plugins' own symbols stay apart.
    void* handle = dlopen(resolved.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      throw InputError(fmt::format("plugin '{}' cannot be loaded: {}; {}", given,
                                   why ? why : "unknown reason", kHowToBuild));
    }
    // Never dlclose'd: the registries' factories and the objects they make are its code.
    using AbiFn = const char* (*)();
    using RegisterFn = void (*)(Extensions&);
    auto abi = reinterpret_cast<AbiFn>(dlsym(handle, "mfv_plugin_abi"));
    auto enter = reinterpret_cast<RegisterFn>(dlsym(handle, "mfv_plugin_register"));
    if (!abi || !enter)
      throw InputError(fmt::format("'{}' is not an mfv plugin: it defines no {}; a plugin "
                                   "defines its entry point with MFV_PLUGIN (apps/plugin.hpp)",
                                   given, !abi ? "mfv_plugin_abi" : "mfv_plugin_register"));
    const char* theirs = abi();
    if (!theirs || std::strcmp(theirs, MFV_PLUGIN_ABI) != 0)
      throw InputError(fmt::format("plugin '{}' was built for {}, this program is {}; {}", given,
                                   theirs ? theirs : "(null)", MFV_PLUGIN_ABI, kHowToBuild));
    Extensions mine;
    try {
      enter(mine);
    } catch (const std::exception& e) {
      throw InputError(fmt::format("plugin '{}' failed in mfv_plugin_register: {}", given,
                                   e.what()));
    }
    const std::string name = path.filename().string();
    append(extensions_.kernels, mine.kernels, name);
    append(extensions_.approximations, mine.approximations, name);
    append(extensions_.methods, mine.methods, name);
    append(extensions_.problems, mine.problems, name);
    append(extensions_.analyses, mine.analyses, name);
    loaded_.push_back(resolved);
    extensions_.sources.push_back(resolved);
  }
}

}  // namespace mfv
