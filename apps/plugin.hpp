/// What a plugin built outside mfv's tree includes: the extension hooks of the catalogue
/// (apps/catalogue.hpp's Extensions) and MFV_PLUGIN, which defines the library's one entry
/// point. `mfv --plugin lib.so …` and a manifest's `[suite] plugins` load such a library
/// (apps/plugins.hpp); examples/plugin/ is a complete plugin repository.
///
///   void register_my_kernel(mfv::KernelRegistry& r) { r.add("my-kernel", …); }
///   MFV_PLUGIN(plugin) { plugin.kernels.push_back(register_my_kernel); }
///
/// A plugin is compiled against mfv's headers and resolves mfv's symbols from the program
/// that loads it, so it must be built against the same mfv by a compatible compiler: the
/// loader compares the plugin's MFV_PLUGIN_ABI with its own and refuses a mismatch.
#pragma once
#include "apps/catalogue.hpp"

/// mfv's version; cmake/CheckVersion.cmake refuses a configure where it differs from the
/// project(VERSION) of CMakeLists.txt.
#define MFV_API_VERSION "0.1.0"

#define MFV_STRINGIFY_(x) #x
#define MFV_STRINGIFY(x) MFV_STRINGIFY_(x)
#if defined(__clang__)
#define MFV_COMPILER "clang " MFV_STRINGIFY(__clang_major__)
#elif defined(__GNUC__)
#define MFV_COMPILER "gcc " MFV_STRINGIFY(__GNUC__)
#else
#define MFV_COMPILER "an unknown compiler"
#endif
#if defined(_GLIBCXX_USE_CXX11_ABI)
#define MFV_STDLIB_ABI ", libstdc++ cxx11 ABI " MFV_STRINGIFY(_GLIBCXX_USE_CXX11_ABI)
#else
#define MFV_STDLIB_ABI ""
#endif
/// What a plugin and the program loading it must share: mfv's version (its headers' classes),
/// the compiler's major version and the standard library's ABI, as text.
#define MFV_PLUGIN_ABI "mfv " MFV_API_VERSION ", " MFV_COMPILER MFV_STDLIB_ABI

/// Defines a plugin's entry point: `MFV_PLUGIN(e) { e.kernels.push_back(…); }`. It exports
/// mfv_plugin_abi (checked before anything else is called) and mfv_plugin_register, which
/// adds the plugin's registration functions to `e`; the catalogue calls them right after its
/// built-in lists, so a plugin kernel is a `kernel=` choice of every method that takes one.
#define MFV_PLUGIN(extensions)                                                        \
  extern "C" __attribute__((visibility("default"))) const char* mfv_plugin_abi() {    \
    return MFV_PLUGIN_ABI;                                                            \
  }                                                                                   \
  extern "C" __attribute__((visibility("default"))) void mfv_plugin_register(         \
      ::mfv::Extensions& extensions)
