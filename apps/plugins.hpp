/// Loading plugins: shared libraries built against an installed mfv with MFV_PLUGIN
/// (apps/plugin.hpp), named by `mfv --plugin lib.so` or a manifest's `[suite] plugins`.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "apps/catalogue.hpp"

namespace mfv {

/// The plugins of one run, loaded in order: their registration functions as one Extensions
/// for the Catalogue. A library is loaded once however often it is named. Libraries stay
/// loaded for the life of the process (the registries' factories are their code).
class Plugins {
 public:
  Plugins() = default;
  /// Loads every library of `paths`. InputError, naming the file and the fix, when one is not
  /// a readable regular file, cannot be loaded (a missing symbol: built against another mfv),
  /// is not an mfv plugin (no mfv_plugin_abi), or was built for another MFV_PLUGIN_ABI.
  explicit Plugins(const std::vector<std::filesystem::path>& paths);

  /// The hooks of every plugin; each names its plugin when registration throws
  /// ("plugin 'libx.so': kernel 'gaussian' registered twice").
  const Extensions& extensions() const { return extensions_; }
  /// The loaded libraries, as resolved absolute paths, in load order (for provenance).
  const std::vector<std::string>& loaded() const { return loaded_; }

 private:
  Extensions extensions_;
  std::vector<std::string> loaded_;
};

/// While alive, and when plugins are loaded, an exit() called during the command ends mfv
/// with exit 1 naming the plugins, not with the caller's status: mfv's commands return, so
/// the call came from a plugin's code (a factory, a kernel, a method), and exit(0) in a case
/// would make a verify that ran nothing pass. (_exit cannot be caught in-process.)
class CommandExitGuard {
 public:
  explicit CommandExitGuard(const Plugins& plugins);
  ~CommandExitGuard();
  CommandExitGuard(const CommandExitGuard&) = delete;
  CommandExitGuard& operator=(const CommandExitGuard&) = delete;
};

}  // namespace mfv
