/// Plugins that must be refused, one per compile definition (tests/CMakeLists.txt builds each
/// as its own library; tests/plugin_test.py runs mfv on them):
///   MFV_BAD_STALE      built for another mfv: its MFV_PLUGIN_ABI differs
///   MFV_BAD_CLASH      registers a kernel under a built-in name
///   MFV_BAD_UNDEFINED  needs a symbol no mfv defines
///   MFV_BAD_NO_ENTRY   a shared library without MFV_PLUGIN
///   MFV_BAD_THROWS     its entry point throws
///   MFV_BAD_THROWS_INT its entry point throws an int (not a std::exception)
///   MFV_BAD_HOOK_INT   its kernel hook throws an int
///   MFV_BAD_FACTORY_INT a kernel whose factory throws an int when a method creates it
///   MFV_BAD_EXITS      its entry point calls exit(0)
///   MFV_BAD_FACTORY_EXITS a kernel whose factory calls _exit(0) when a method creates it
///                      (while a case runs: no handler can catch it in-process)
///   MFV_BAD_FACTORY_CRASH a kernel whose factory dies of SIGSEGV when a method creates it
///   MFV_BAD_HOOK_EXITS its kernel hook calls _exit(0) (while the catalogue is built)
///   MFV_BAD_NAME       registers a kernel named "a,b=c"
///   MFV_BAD_EXTERNAL   registers a kernel named "external:pysph"
#include <unistd.h>

#include <csignal>
#include <cstdlib>

#include "apps/plugin.hpp"

#if defined(MFV_BAD_STALE)
extern "C" __attribute__((visibility("default"))) const char* mfv_plugin_abi() {
  return "mfv 0.0.1, gcc 9";
}
extern "C" __attribute__((visibility("default"))) void mfv_plugin_register(mfv::Extensions&) {}
#elif defined(MFV_BAD_CLASH)
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back([](mfv::KernelRegistry& r) {
    r.add("gaussian", "a second gaussian", {}, [](const mfv::Params&) {
      return std::unique_ptr<mfv::Kernel>();
    });
  });
}
#elif defined(MFV_BAD_UNDEFINED)
namespace mfv {
void a_function_no_mfv_defines(KernelRegistry&);
}
MFV_PLUGIN(plugin) { plugin.kernels.push_back(mfv::a_function_no_mfv_defines); }
#elif defined(MFV_BAD_NO_ENTRY)
extern "C" int not_a_plugin() { return 1; }
#elif defined(MFV_BAD_THROWS)
MFV_PLUGIN(plugin) { throw std::runtime_error("cannot find my data file"); }
#elif defined(MFV_BAD_THROWS_INT)
MFV_PLUGIN(plugin) { throw 42; }
#elif defined(MFV_BAD_HOOK_INT)
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back([](mfv::KernelRegistry&) { throw 7; });
}
#elif defined(MFV_BAD_FACTORY_INT)
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back([](mfv::KernelRegistry& r) {
    r.add("throws-int", "a kernel whose factory throws an int", {},
          [](const mfv::Params&) -> std::unique_ptr<mfv::Kernel> { throw 42; });
  });
}
#elif defined(MFV_BAD_FACTORY_EXITS) || defined(MFV_BAD_FACTORY_CRASH)
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back([](mfv::KernelRegistry& r) {
    r.add("ends-the-process", "a kernel whose factory ends the process", {},
          [](const mfv::Params&) -> std::unique_ptr<mfv::Kernel> {
#if defined(MFV_BAD_FACTORY_EXITS)
            _exit(0);
#else
            std::raise(SIGSEGV);
            return nullptr;
#endif
          });
  });
}
#elif defined(MFV_BAD_HOOK_EXITS)
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back([](mfv::KernelRegistry&) { _exit(0); });
}
#elif defined(MFV_BAD_EXITS)
MFV_PLUGIN(plugin) { std::exit(0); }
#elif defined(MFV_BAD_NAME) || defined(MFV_BAD_EXTERNAL)
MFV_PLUGIN(plugin) {
  plugin.kernels.push_back([](mfv::KernelRegistry& r) {
#if defined(MFV_BAD_NAME)
    const char* name = "a,b=c";
#else
    const char* name = "external:pysph";
#endif
    r.add(name, "a kernel with a name mfv cannot parse", {}, [](const mfv::Params&) {
      return std::unique_ptr<mfv::Kernel>();
    });
  });
}
#endif
