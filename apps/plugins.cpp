/// dlopen-based plugin loading (apps/plugins.hpp).
#include "apps/plugins.hpp"

#include <dlfcn.h>
#include <elf.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <set>
#include <system_error>

#include <fmt/format.h>

#include "apps/plugin.hpp"
#include "apps/supervise.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

namespace {

constexpr const char* kHowToBuild =
    "build the plugin against this mfv's installation (find_package(mfv CONFIG) with "
    "CMAKE_PREFIX_PATH set to its prefix; examples/plugin/ shows how)";

/// A name a plugin may register: letters, digits and - _ . + (at most 64), beginning with a
/// letter or digit. ',' '=' and spaces are the syntax of `-p key=value,...`; ':' is reserved
/// for `external:<solver>`.
bool valid_registered_name(const std::string& n) {
  if (n.empty() || n.size() > 64 || !std::isalnum(static_cast<unsigned char>(n[0]))) return false;
  return std::all_of(n.begin(), n.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ||
           c == '+';
  });
}

template <class First, class... Rest>
First& first_of(First& f, Rest&...) {
  return f;
}

/// `hook` with every exception turned into an InputError that names the plugin: what a
/// plugin registers is the user's input, and a clash ("kernel 'gaussian' registered twice")
/// is fixed in the plugin. Anything thrown that is not a std::exception is named too (it
/// would otherwise end mfv through std::terminate), and every name the hook added to its
/// registry (the hook's first argument) must be a valid one.
std::string& plugin_being_loaded();

template <class... Args>
std::function<void(Args...)> naming(const std::string& plugin, std::function<void(Args...)> hook) {
  return [plugin, hook = std::move(hook)](Args... args) {
    auto& registry = first_of(args...);
    const auto before = registry.keys();
    // A hook is the plugin's registration too: exit() in it is refused as in loading (rc 2).
    struct Registering {
      explicit Registering(const std::string& p) { plugin_being_loaded() = p; }
      ~Registering() { plugin_being_loaded().clear(); }
    } registering(plugin);
    try {
      hook(args...);
    } catch (const std::exception& e) {
      throw InputError(fmt::format("plugin '{}': {}; fix the plugin's registration (a name "
                                   "must be new: `mfv list` names the registered ones)",
                                   plugin, e.what()));
    } catch (...) {
      throw InputError(fmt::format("plugin '{}': its {} registration threw something that is "
                                   "not a std::exception; fix the plugin (throw "
                                   "std::runtime_error with a message)",
                                   plugin, registry.kind()));
    }
    const std::set<std::string> old(before.begin(), before.end());
    for (const auto& k : registry.keys())
      if (!old.count(k) && !valid_registered_name(k))
        throw InputError(fmt::format(
            "plugin '{}': the {} name '{}' is not a valid name; use letters, digits and - _ . + "
            "(at most 64, beginning with a letter or digit: ',', '=' and spaces are the syntax "
            "of -p key=value,..., ':' is reserved for external:<solver>)",
            plugin, registry.kind(), k));
  };
}

/// The library being loaded, for refuse_plugin_exit: process-wide because exit
/// handlers take no argument; written only while Plugins' constructor loads a library.
std::string& plugin_being_loaded() {
  static std::string name;
  return name;
}

/// The plugins loaded while a command runs ("" outside one): process-wide for the same
/// reason as plugin_being_loaded.
std::string& plugins_of_running_command() {
  static std::string names;
  return names;
}

/// exit() called by a plugin ends mfv naming it, not with the plugin's own status: exit(0)
/// would make a verify that ran nothing pass. While mfv loads a plugin (its static
/// initializers or mfv_plugin_register): rc 2 naming that library; while a command runs
/// (mfv's commands return, so the call came from a plugin's code): rc 1 naming the plugins.
void refuse_plugin_exit() {
  if (const std::string& p = plugin_being_loaded(); !p.empty()) {
    std::fprintf(stderr,
                 "mfv: input error: plugin '%s' called exit() while it was being loaded (in "
                 "its static initializers, mfv_plugin_register or a registration hook); a "
                 "plugin's registration "
                 "must return, and report a failure by throwing std::runtime_error\n",
                 p.c_str());
    std::fflush(stderr);
    report_finished(2);  // mfv's own verdict on the plugin: the supervisor ends with it
    std::_Exit(2);
  }
  if (const std::string& p = plugins_of_running_command(); !p.empty()) {
    std::fprintf(stderr,
                 "mfv: error: something called exit() while the command ran; mfv's commands "
                 "return, so it was a plugin's code (loaded: %s); the command did not finish\n",
                 p.c_str());
    std::fflush(stderr);
    report_finished(1);
    std::_Exit(1);
  }
}

/// Registers refuse_plugin_exit once, after the names' storage (statics are destroyed in the
/// reverse order of their registration, so they outlive the handler's run at exit).
void refuse_plugin_exit_from_now_on() {
  static const bool registered = [] {
    plugin_being_loaded();
    plugins_of_running_command();
    std::atexit(refuse_plugin_exit);
    std::at_quick_exit(refuse_plugin_exit);
    return true;
  }();
  (void)registered;
}

/// Clears plugin_being_loaded however the load ends.
struct LoadingPlugin {
  explicit LoadingPlugin(const std::string& name) {
    refuse_plugin_exit_from_now_on();
    plugin_being_loaded() = name;
  }
  ~LoadingPlugin() { plugin_being_loaded().clear(); }
  LoadingPlugin(const LoadingPlugin&) = delete;
  LoadingPlugin& operator=(const LoadingPlugin&) = delete;
};

/// An ELF library whose headers reach past the end of the file: dlopen would map the missing
/// pages and the first touch of one kills mfv with SIGBUS. "" when the file is whole (or is
/// no 64-bit ELF file: dlopen then says what it is).
std::string truncated_elf(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return {};
  std::ifstream in(path, std::ios::binary);
  Elf64_Ehdr eh{};
  in.read(reinterpret_cast<char*>(&eh), sizeof eh);
  if (in.gcount() < SELFMAG || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0) return {};
  if (in.gcount() < static_cast<std::streamsize>(sizeof eh))
    return fmt::format("{} bytes, shorter than an ELF header", size);
  if (eh.e_ident[EI_CLASS] != ELFCLASS64) return {};
  const auto need = [&](std::uint64_t end, const char* what) -> std::string {
    if (end <= size) return {};
    return fmt::format("its {} reach byte {}, the file has {}", what, end, size);
  };
  if (auto w = need(eh.e_phoff + std::uint64_t(eh.e_phnum) * eh.e_phentsize, "program headers");
      !w.empty())
    return w;
  if (auto w = need(eh.e_shoff + std::uint64_t(eh.e_shnum) * eh.e_shentsize, "section headers");
      !w.empty())
    return w;
  if (eh.e_phentsize != sizeof(Elf64_Phdr)) return "its program headers are not of this size";
  in.seekg(static_cast<std::streamoff>(eh.e_phoff));
  for (int i = 0; i < eh.e_phnum; ++i) {
    Elf64_Phdr ph{};
    if (!in.read(reinterpret_cast<char*>(&ph), sizeof ph)) return "its program headers are cut";
    if (ph.p_type == PT_LOAD)
      if (auto w = need(ph.p_offset + ph.p_filesz, "loadable segments"); !w.empty()) return w;
  }
  return {};
}

/// A plugin that ends the process while it loads (_exit, abort, a signal in its static
/// initializers, mfv_plugin_abi or mfv_plugin_register) is found in a child first: mfv cannot
/// outlive an _exit or a crash in the plugin's own code, and exit status 0 would make a verify
/// that ran nothing pass. "" when the child's load returned (or threw: the load in mfv then
/// names the exception); otherwise how the child ended. The plugin's static initializers
/// therefore run twice (docs/architecture.md says so).
std::string load_ends_the_process(const std::string& resolved) {
  int fd[2];
  if (pipe2(fd, O_CLOEXEC) != 0) return {};  // no probe possible: mfv loads it as before
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    close(fd[0]);
    close(fd[1]);
    return {};
  }
  if (pid == 0) {
    close(fd[0]);
    forget_supervision();  // the probe is not the command: it never reports its end
    // What the plugin prints while loading is shown once, by the load in mfv.
    if (const int null = open("/dev/null", O_WRONLY); null >= 0) {
      dup2(null, 1);
      dup2(null, 2);
    }
    if (void* h = dlopen(resolved.c_str(), RTLD_NOW | RTLD_LOCAL)) {
      using AbiFn = const char* (*)();
      using RegisterFn = void (*)(Extensions&);
      auto abi = reinterpret_cast<AbiFn>(dlsym(h, "mfv_plugin_abi"));
      auto enter = reinterpret_cast<RegisterFn>(dlsym(h, "mfv_plugin_register"));
      try {
        const char* theirs = abi ? abi() : nullptr;
        if (enter && theirs && std::strcmp(theirs, MFV_PLUGIN_ABI) == 0) {
          Extensions mine;
          enter(mine);
        }
      } catch (...) {
      }
    }
    const char returned = 1;
    [[maybe_unused]] const auto w = write(fd[1], &returned, 1);
    _exit(0);
  }
  close(fd[1]);
  char c = 0;
  ssize_t n;
  do n = read(fd[0], &c, 1);
  while (n < 0 && errno == EINTR);
  close(fd[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const char* where = "(in its static initializers, mfv_plugin_abi or mfv_plugin_register)";
  if (n == 1) return {};
  if (WIFSIGNALED(status))
    return fmt::format("was killed by signal {} ({}) while it was being loaded {}",
                       WTERMSIG(status), strsignal(WTERMSIG(status)), where);
  if (WIFEXITED(status))
    return fmt::format("called exit() while it was being loaded {} (or _exit: a load in a "
                       "child process ended with exit status {})",
                       where, WEXITSTATUS(status));
  return fmt::format("ended the process while it was being loaded {}", where);
}

template <class Hook>
void append(std::vector<Hook>& to, const std::vector<Hook>& from, const std::string& plugin) {
  for (const auto& h : from) to.push_back(naming(plugin, h));
}

}  // namespace

CommandExitGuard::CommandExitGuard(const Plugins& plugins) {
  if (plugins.loaded().empty()) return;
  refuse_plugin_exit_from_now_on();
  std::vector<std::string> names;
  for (const auto& l : plugins.loaded()) names.push_back(std::filesystem::path(l).filename());
  plugins_of_running_command() = fmt::format("{}", fmt::join(names, ", "));
}

CommandExitGuard::~CommandExitGuard() { plugins_of_running_command().clear(); }

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
    if (const std::string cut = truncated_elf(resolved); !cut.empty())
      throw InputError(fmt::format("plugin '{}' is a truncated or damaged library ({}); "
                                   "rebuild it or copy it again; {}",
                                   given, cut, kHowToBuild));
    if (const std::string ended = load_ends_the_process(resolved); !ended.empty())
      throw InputError(fmt::format("plugin '{}' {}; a plugin's registration must return, and "
                                   "report a failure by throwing std::runtime_error",
                                   given, ended));
    const LoadingPlugin loading(given);

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
    const char* theirs = nullptr;
    try {
      theirs = abi();
    } catch (...) {
      throw InputError(fmt::format("plugin '{}' failed in mfv_plugin_abi (it threw); a "
                                   "plugin defines its entry points with MFV_PLUGIN "
                                   "(apps/plugin.hpp); {}",
                                   given, kHowToBuild));
    }
    if (!theirs || std::strcmp(theirs, MFV_PLUGIN_ABI) != 0)
      throw InputError(fmt::format("plugin '{}' was built for {}, this program is {}; {}", given,
                                   theirs ? theirs : "(null)", MFV_PLUGIN_ABI, kHowToBuild));
    Extensions mine;
    try {
      enter(mine);
    } catch (const std::exception& e) {
      throw InputError(fmt::format("plugin '{}' failed in mfv_plugin_register: {}", given,
                                   e.what()));
    } catch (...) {
      throw InputError(fmt::format("plugin '{}' failed in mfv_plugin_register: it threw "
                                   "something that is not a std::exception; fix the plugin "
                                   "(throw std::runtime_error with a message)",
                                   given));
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
