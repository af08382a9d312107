#include "dynamics/external_solver.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "methods/core/errors.hpp"
#include "methods/core/signal_cleanup.hpp"

extern char** environ;

namespace mfv {

namespace fs = std::filesystem;

std::string file_tail(const fs::path& file, std::size_t bytes) {
  // Only the tail is read (a solver that printed 1 GiB costs `bytes`), and only from a
  // regular file: a FIFO or a device put in its place would block or never end.
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return ec ? "" : "(not a regular file)";
  const auto size = fs::file_size(file, ec);
  if (ec) return "";
  std::ifstream in(file, std::ios::binary);
  const bool cut = size > bytes;
  if (cut) in.seekg(static_cast<std::streamoff>(size - bytes));
  std::string s(cut ? bytes : static_cast<std::size_t>(size), '\0');
  in.read(s.data(), static_cast<std::streamsize>(s.size()));
  s.resize(static_cast<std::size_t>(std::max<std::streamsize>(0, in.gcount())));
  return cut ? "…" + s : s;
}

bool SolverSpec::supports(const std::string& problem) const {
  return std::find(problems.begin(), problems.end(), problem) != problems.end();
}

namespace {

std::vector<std::string> string_array(const toml::table& t, const std::string& key,
                                      const fs::path& file, bool required) {
  const toml::node* n = t.get(key);
  if (!n) {
    if (required)
      throw InputError(fmt::format("solver file '{}': [solver] {} is missing; give it as an "
                                   "array of strings, e.g. {} = [\"python3\", \"adapter.py\"]",
                                   file.string(), key, key));
    return {};
  }
  const toml::array* a = n->as_array();
  if (!a)
    throw InputError(fmt::format("solver file '{}': [solver] {} must be an array of strings",
                                 file.string(), key));
  std::vector<std::string> out;
  for (const auto& e : *a) {
    const auto s = e.value<std::string>();
    if (!s)
      throw InputError(fmt::format("solver file '{}': [solver] {} must be an array of "
                                   "strings; element {} is not one",
                                   file.string(), key, out.size() + 1));
    out.push_back(*s);
  }
  return out;
}

std::string substitute_dir(std::string s, const fs::path& dir) {
  const std::string key = "{solver_dir}";
  for (auto p = s.find(key); p != std::string::npos; p = s.find(key, p))
    s.replace(p, key.size(), dir.string());
  return s;
}

std::string tail_of(const fs::path& file, std::size_t bytes = 1500) {
  std::string s = file_tail(file, bytes);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

std::string shown_command(const std::vector<std::string>& argv) {
  return fmt::format("{}", fmt::join(argv, " "));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The processes whose parent is `parent` (from /proc/<pid>/stat's fourth field).
std::set<pid_t> children_of(pid_t parent) {
  std::set<pid_t> out;
  std::error_code ec;
  for (fs::directory_iterator it("/proc", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    std::ifstream stat(it->path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    // "pid (comm) state ppid …": comm may hold spaces and parentheses, so from the last ')'.
    const auto close = line.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 1));
    std::string state;
    long ppid = 0;
    if (rest >> state >> ppid && ppid == parent) out.insert(static_cast<pid_t>(std::stol(name)));
  }
  return out;
}

/// Kills and reaps every child of mfv that was not one before the solver started: with mfv a
/// child subreaper (PR_SET_CHILD_SUBREAPER), a solver's descendant that left its process
/// group (setsid) becomes mfv's child when its parent exits, and goes with the case. Rounds,
/// because killing one hands its own children to mfv. Cases run one at a time, so a new
/// child is this solver's.
void reap_descendants(const std::set<pid_t>& before) {
  for (int round = 0; round < 50; ++round) {
    std::vector<pid_t> stray;
    for (pid_t p : children_of(::getpid()))
      if (!before.count(p)) stray.push_back(p);
    if (stray.empty()) return;
    for (pid_t p : stray) ::kill(p, SIGKILL);
    for (pid_t p : stray) {
      int status = 0;
      while (::waitpid(p, &status, 0) < 0 && errno == EINTR) {
      }
    }
  }
}

/// Spawns argv in `dir` (own process group, stdin from /dev/null, stdout/stderr to the
/// files), waits up to `timeout` s; returns the exit status, or -1 on timeout (the group
/// then got SIGTERM and, 5 s later, SIGKILL). errno-style failure to start: the error code
/// in `spawn_error`.
int spawn_and_wait(const std::vector<std::string>& argv, const fs::path& dir,
                   const fs::path& out, const fs::path& err, double timeout, int& spawn_error,
                   double& wall, double* cpu = nullptr) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addchdir_np(&fa, dir.c_str());
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK |
                                      POSIX_SPAWN_SETSIGDEF);
  posix_spawnattr_setpgroup(&attr, 0);
  // mfv blocks SIGINT/SIGTERM/SIGHUP for its clean-up thread; the solver gets them back.
  sigset_t none, deflt;
  sigemptyset(&none);
  sigemptyset(&deflt);
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&deflt, s);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &deflt);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // Orphaned descendants of the solver come to mfv, not to init (reap_descendants).
  ::prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
  const std::set<pid_t> children_before = children_of(::getpid());
  pid_t pid = 0;
  const auto t0 = std::chrono::steady_clock::now();
  spawn_error = posix_spawnp(&pid, args[0], &fa, &attr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (spawn_error != 0) return -2;
  // Killed by SIGKILL (no handler runs), mfv still takes the solver's group with it: a
  // watchdog shell holds the read end of a pipe whose write end only mfv has (close-on-exec);
  // when mfv dies, any way, the pipe ends and the watchdog kills the group (issue 45: a solver
  // outlived a SIGKILLed mfv). At the case's end mfv kills and reaps the watchdog first, so
  // its kill never runs once the group is gone (its pid may then be another's).
  int watch[2] = {-1, -1};
  pid_t watchdog = 0;
  if (::pipe2(watch, O_CLOEXEC) == 0) {
    posix_spawn_file_actions_t wa;
    posix_spawn_file_actions_init(&wa);
    posix_spawn_file_actions_adddup2(&wa, watch[0], 0);
    posix_spawn_file_actions_addopen(&wa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&wa, 2, "/dev/null", O_WRONLY, 0);
    posix_spawnattr_t wattr;
    posix_spawnattr_init(&wattr);
    posix_spawnattr_setflags(&wattr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    sigset_t ignored_none;
    sigemptyset(&ignored_none);
    posix_spawnattr_setsigmask(&wattr, &ignored_none);
    posix_spawnattr_setsigdefault(&wattr, &deflt);
    // dash, /bin/sh on Debian, takes no "--": "kill -KILL -PGID" names the group.
    const std::string script = fmt::format("read x; kill -KILL -{}", pid);
    const char* wargv[] = {"/bin/sh", "-c", script.c_str(), nullptr};
    if (posix_spawn(&watchdog, "/bin/sh", &wa, &wattr, const_cast<char**>(wargv), environ) != 0)
      watchdog = 0;
    posix_spawn_file_actions_destroy(&wa);
    posix_spawnattr_destroy(&wattr);
    ::close(watch[0]);  // the write end stays open in mfv until it exits
  }
  // Ends the watchdog (its kill not run), then closes mfv's end of its pipe.
  auto end_watchdog = [watchdog, fd = watch[1]] {
    if (watchdog > 0) {
      ::kill(watchdog, SIGKILL);
      int ignored = 0;
      while (::waitpid(watchdog, &ignored, 0) < 0 && errno == EINTR) {
      }
    }
    if (fd >= 0) ::close(fd);
  };
  // Killed itself (SIGINT, SIGTERM, SIGHUP), mfv takes the solver's group with it: the group
  // is the solver's own, so the signal does not reach it, and it would run on, orphaned.
  const OnSignal kill_group([pid, &children_before, &end_watchdog] {
    ::kill(-pid, SIGKILL);
    end_watchdog();
    reap_descendants(children_before);
  });
  int status = 0;
  bool timed_out = false;
  double killed_at = 0;
  for (;;) {
    struct rusage usage {};
    const pid_t w = ::wait4(pid, &status, WNOHANG, &usage);
    if (w == pid) {
      if (cpu)
        *cpu = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec +
               1e-6 * usage.ru_stime.tv_usec;
      break;
    }
    if (w < 0 && errno != EINTR) break;
    const double t = seconds_since(t0);
    if (!timed_out && t > timeout) {
      timed_out = true;
      killed_at = t;
      ::kill(-pid, SIGTERM);
    } else if (timed_out && t > killed_at + 5) {
      ::kill(-pid, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(t < 1 ? 5 : 50));
  }
  wall = seconds_since(t0);
  // Whatever the solver left running goes with it: its group, and what left the group.
  ::kill(-pid, SIGKILL);
  end_watchdog();
  reap_descendants(children_before);
  if (timed_out) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 255;
}

}  // namespace

SolverSpec read_solver_spec(const fs::path& file) {
  toml::table doc;
  try {
    doc = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("solver file '{}': not TOML: {} (line {})", file.string(),
                                 e.description(), e.source().begin.line));
  }
  const toml::table* t = doc["solver"].as_table();
  if (!t)
    throw InputError(fmt::format("solver file '{}': no [solver] table; see "
                                 "docs/external-solvers.md for the keys",
                                 file.string()));
  static const std::set<std::string> known = {"command", "problems", "timeout", "description",
                                              "install_hint", "check", "params"};
  for (const auto& [k, v] : *t)
    if (!known.count(std::string(k.str())))
      throw InputError(fmt::format("solver file '{}': unknown key [solver] {}; valid keys: {}",
                                   file.string(), k.str(), fmt::join(known, ", ")));
  SolverSpec s;
  s.file = fs::absolute(file);
  s.name = file.stem().string();
  const fs::path dir = s.file.parent_path();
  s.command = string_array(*t, "command", file, true);
  if (s.command.empty() || s.command.front().empty())
    throw InputError(fmt::format("solver file '{}': [solver] command is empty; give the "
                                 "program and its arguments",
                                 file.string()));
  for (auto& a : s.command) a = substitute_dir(a, dir);
  s.check = string_array(*t, "check", file, false);
  for (auto& a : s.check) a = substitute_dir(a, dir);
  s.problems = string_array(*t, "problems", file, true);
  if (s.problems.empty())
    throw InputError(fmt::format("solver file '{}': [solver] problems is empty; name the "
                                 "problems the solver supports",
                                 file.string()));
  if (const toml::node* n = t->get("timeout")) {
    const auto v = n->value<double>();
    if (!v || !(*v > 0) || !std::isfinite(*v))
      throw InputError(fmt::format("solver file '{}': [solver] timeout must be a positive "
                                   "number of seconds",
                                   file.string()));
    s.timeout = *v;
  }
  for (const char* key : {"description", "install_hint"})
    if (const toml::node* n = t->get(key)) {
      const auto v = n->value<std::string>();
      if (!v)
        throw InputError(
            fmt::format("solver file '{}': [solver] {} must be a string", file.string(), key));
      (std::string(key) == "description" ? s.description : s.install_hint) = *v;
    }
  if (const toml::node* n = t->get("params")) {
    const toml::table* pt = n->as_table();
    if (!pt)
      throw InputError(fmt::format("solver file '{}': [solver.params] must be a table of "
                                   "name = default",
                                   file.string()));
    for (const auto& [k, v] : *pt) {
      const std::string key(k.str());
      if (key == "keep")
        throw InputError(fmt::format("solver file '{}': [solver.params] keep is mfv's own "
                                     "parameter; rename the solver's",
                                     file.string()));
      if (const auto x = v.value<double>(); x && !v.is_string()) {
        s.params.set(key, *x);
      } else if (const auto text = v.value<std::string>()) {
        s.params.set(key, ParamValue{*text});
      } else {
        throw InputError(fmt::format("solver file '{}': [solver.params] {} must be a number or "
                                     "a string",
                                     file.string(), key));
      }
    }
  }
  return s;
}

std::vector<SolverSpec> read_solver_specs(const fs::path& dir) {
  std::vector<SolverSpec> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".toml" && e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    try {
      out.push_back(read_solver_spec(f));
    } catch (const InputError& e) {
      SolverSpec broken;
      broken.name = f.stem().string();
      broken.file = fs::absolute(f);
      broken.broken = e.what();
      out.push_back(std::move(broken));
    }
  }
  return out;
}

void write_case_input(const fs::path& dir, const ExternalCase& c) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec))
    throw std::runtime_error(fmt::format("the external case directory '{}' must exist and be "
                                         "empty",
                                         dir.string()));
  const int n = static_cast<int>(c.x.cols());
  if (c.x.rows() != c.dim || c.volume.size() != n || c.mass.size() != n ||
      static_cast<int>(c.sides.size()) != n ||
      (c.initial_velocity.size() > 0 &&
       (c.initial_velocity.rows() != c.dim || c.initial_velocity.cols() != n)))
    throw std::logic_error("write_case_input: particle arrays of different sizes");
  if (c.output_times.empty() || !std::is_sorted(c.output_times.begin(), c.output_times.end()))
    throw std::logic_error("write_case_input: output times must be given, increasing");
  auto params_json = [](const Params& p) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [k, v] : p.values())
      std::visit([&](const auto& x) { j[k] = x; }, v);
    return j;
  };
  nlohmann::json j;
  j["protocol"] = kExternalProtocol;
  j["problem"] = c.problem;
  j["problem_params"] = params_json(c.problem_params);
  j["solver_params"] = params_json(c.solver_params);
  j["nodes"] = c.nodes;
  j["dim"] = c.dim;
  j["units"] = {{"system", c.unit_system}, {"time", c.time_unit}};
  j["particles"] = {{"count", n}, {"file", "particles.csv"}};
  j["material"] = {{"model", c.material}, {"params", params_json(c.material_params)},
                   {"density", c.density}};
  nlohmann::json pv = nlohmann::json::array();
  for (const auto& p : c.prescribed)
    pv.push_back({{"particle", p.particle}, {"component", p.component}, {"value", p.value},
                  {"until", p.until}});
  j["prescribed_velocity"] = pv;
  j["end_time"] = c.end_time;
  j["checkpoints"] = c.checkpoints;
  j["output_times"] = c.output_times;
  j["output"] = {{"index", "frames/index.csv"}, {"frame", "frames/frame-<k>.csv"}};
  std::ofstream(dir / "input.json") << j.dump(2) << "\n";

  std::ofstream p(dir / "particles.csv");
  const char* axes[] = {"x", "y", "z"};
  p << "id";
  for (int a = 0; a < c.dim; ++a) p << "," << axes[a];
  p << ",volume,mass";
  for (int a = 0; a < c.dim; ++a) p << ",v" << axes[a] << "0";
  p << ",sides\n";
  for (int I = 0; I < n; ++I) {
    p << I;
    for (int a = 0; a < c.dim; ++a) p << fmt::format(",{:.17g}", c.x(a, I));
    p << fmt::format(",{:.17g},{:.17g}", c.volume(I), c.mass(I));
    for (int a = 0; a < c.dim; ++a)
      p << fmt::format(",{:.17g}", c.initial_velocity.size() ? c.initial_velocity(a, I) : 0.0);
    p << "," << c.sides[I] << "\n";
  }
  if (!p) throw std::runtime_error(fmt::format("cannot write '{}'", (dir / "particles.csv").string()));
}

std::optional<std::string> solver_missing(const SolverSpec& spec) {
  const std::vector<std::string>& probe = spec.check.empty() ? spec.command : spec.check;
  if (spec.check.empty()) {
    // Without a check: the program must be found (a path, or a name on PATH).
    const std::string& prog = probe.front();
    if (prog.find('/') != std::string::npos) {
      if (::access(prog.c_str(), X_OK) != 0)
        return fmt::format("{}: not an executable file", prog);
      return std::nullopt;
    }
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "/usr/bin:/bin");
    for (std::string d; std::getline(dirs, d, ':');)
      if (!d.empty() && ::access((fs::path(d) / prog).c_str(), X_OK) == 0) return std::nullopt;
    return fmt::format("{}: no such program on PATH", prog);
  }
  // The check's output goes into a private directory of its own (mkdtemp), never into a
  // name under $TMPDIR a user's file may have.
  std::error_code tmp_ec;
  fs::path tmp = fs::temp_directory_path(tmp_ec);
  if (tmp_ec) tmp = "/tmp";
  std::string dir_template = (tmp / "mfv-check-XXXXXX").string();
  if (!::mkdtemp(dir_template.data()))
    throw ExternalSolverError(fmt::format(
        "cannot create a private directory for the check of external solver '{}' under '{}' "
        "({}); set TMPDIR to a writable directory",
        spec.name, tmp.string(), std::strerror(errno)));
  const fs::path private_dir = dir_template;
  const fs::path out = private_dir / "out";
  const fs::path err = private_dir / "err";
  int spawn_error = 0;
  double wall = 0;
  const int rc = spawn_and_wait(probe, private_dir, out, err, 60, spawn_error, wall);
  const std::string why = tail_of(err, 300);
  std::error_code ignored;
  fs::remove_all(private_dir, ignored);
  if (rc == -2)
    return fmt::format("{}: cannot start ({})", probe.front(), std::strerror(spawn_error));
  if (rc != 0)
    return fmt::format("check '{}' {}{}", shown_command(probe),
                       rc == -1 ? "did not finish in 60 s" : fmt::format("exited {}", rc),
                       why.empty() ? "" : ": " + why);
  return std::nullopt;
}

SolverRun run_solver(const SolverSpec& spec, const fs::path& dir) {
  if (const auto why = solver_missing(spec))
    throw ExternalSolverMissing(fmt::format(
        "external solver '{}' is not installed here: {}{}", spec.name, *why,
        spec.install_hint.empty() ? "" : fmt::format(" (install: {})", spec.install_hint)));
  SolverRun r;
  r.stdout_file = dir / "stdout.txt";
  r.stderr_file = dir / "stderr.txt";
  std::vector<std::string> argv = spec.command;
  argv.push_back(fs::absolute(dir).string());
  int spawn_error = 0;
  const int rc = spawn_and_wait(argv, dir, r.stdout_file, r.stderr_file, spec.timeout,
                                spawn_error, r.wall_seconds, &r.cpu_seconds);
  if (rc == -2)
    throw ExternalSolverMissing(fmt::format("external solver '{}': cannot start '{}' ({}){}",
                                            spec.name, argv.front(), std::strerror(spawn_error),
                                            spec.install_hint.empty()
                                                ? ""
                                                : fmt::format(" (install: {})", spec.install_hint)));
  r.exit_code = rc;
  const std::string err = tail_of(r.stderr_file);
  if (rc == -1)
    throw ExternalSolverError(fmt::format(
        "external solver '{}' did not finish within its timeout of {:g} s (stopped; raise "
        "[solver] timeout in '{}' for larger cases){}",
        spec.name, spec.timeout, spec.file.string(), err.empty() ? "" : "; stderr: " + err));
  if (rc != 0)
    throw ExternalSolverError(fmt::format("external solver '{}' exited {} after {:.1f} s{}",
                                          spec.name, rc, r.wall_seconds,
                                          err.empty() ? " (stderr empty)" : "; stderr: " + err));
  return r;
}

namespace {

/// The longest line mfv reads from a solver's file: a frame row or an energy row is well
/// under a kilobyte; a runaway solver's one endless line would otherwise be read whole.
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

/// Opens a file the solver wrote, refusing what is not a regular file (a FIFO would block
/// mfv for ever, /dev/zero would never end) with ExternalSolverError naming it.
std::ifstream open_solver_file(const fs::path& file, const std::string& name) {
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (!ec && fs::exists(st) && !fs::is_regular_file(st))
    throw ExternalSolverError(fmt::format("{} is not a regular file (a {}); the solver must "
                                          "write its output as ordinary files",
                                          name, fs::is_directory(st) ? "directory" : "special file"));
  return std::ifstream(file, std::ios::binary);
}

/// std::getline with a cap: false at the end of the file; a line longer than kMaxLineBytes
/// is an ExternalSolverError naming the file and the line.
bool capped_getline(std::istream& in, std::string& line, const std::string& name, int ln) {
  line.clear();
  std::streambuf* sb = in.rdbuf();
  if (!sb || !in) return false;
  for (;;) {
    const int ch = sb->sbumpc();
    if (ch == std::char_traits<char>::eof()) {
      if (line.empty()) {
        in.setstate(std::ios::eofbit | std::ios::failbit);
        return false;
      }
      in.setstate(std::ios::eofbit);
      return true;
    }
    if (ch == '\n') return true;
    if (line.size() >= kMaxLineBytes)
      throw ExternalSolverError(fmt::format("{} line {} is longer than {} bytes; a solver's "
                                            "rows are short: is it writing what the protocol "
                                            "asks?",
                                            name, ln, kMaxLineBytes));
    line.push_back(static_cast<char>(ch));
  }
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string f; std::getline(s, f, ',');) {
    while (!f.empty() && (f.back() == '\r' || f.back() == ' ')) f.pop_back();
    while (!f.empty() && f.front() == ' ') f.erase(f.begin());
    out.push_back(f);
  }
  return out;
}

/// `line` without the trailing '\r' and spaces of a file written on another system.
void trim_end(std::string& line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
}

/// Each column name of a CSV header with its index.
std::map<std::string, int> column_index(const std::vector<std::string>& header) {
  std::map<std::string, int> col;
  for (int i = 0; i < static_cast<int>(header.size()); ++i) col[header[i]] = i;
  return col;
}

/// Reads the first line of the solver's file `name` (e.g. "frames/index.csv") and checks it
/// is the protocol's version.
void expect_protocol_line(std::istream& in, const std::string& name) {
  std::string line;
  capped_getline(in, line, name, 1);
  trim_end(line);
  if (line != kExternalProtocol)
    throw ExternalSolverError(fmt::format("{}: first line '{}', expected the protocol '{}'",
                                          name, line.substr(0, 60), kExternalProtocol));
}

/// Parses a CSV number; NaN for "nan" and for anything unparsable (reported as such).
bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

std::string time_name(const ExternalCase& c, std::size_t k) {
  const double t = c.output_times[k];
  const bool checkpoint =
      std::any_of(c.checkpoints.begin(), c.checkpoints.end(),
                  [&](double tc) { return std::abs(tc - t) <= 1e-9 * std::max(1.0, std::abs(t)); });
  return fmt::format("{} t = {:.6g} (frame {})", checkpoint ? "checkpoint" : "output time", t, k);
}

}  // namespace

std::vector<ExternalFrame> read_case_output(const fs::path& dir, const ExternalCase& c) {
  const fs::path frames = dir / "frames";
  const fs::path index = frames / "index.csv";
  std::ifstream in = open_solver_file(index, "frames/index.csv");
  if (!in)
    throw ExternalSolverError(fmt::format("the solver wrote no frames/index.csv (expected the "
                                          "line '{}', then k,time for each of {} frames)",
                                          kExternalProtocol, c.output_times.size()));
  expect_protocol_line(in, "frames/index.csv");
  std::string line;
  // "k,time", or "k,time,steps" with the solver's steps from t = 0 to the frame (optional:
  // the report's particle-steps per second).
  std::map<std::size_t, std::pair<double, long>> written;
  bool with_steps = false;
  for (int ln = 2; capped_getline(in, line, "frames/index.csv", ln); ++ln) {
    trim_end(line);
    if (line.empty()) continue;
    // A row per output time (and a header): more is not the protocol, and unbounded.
    if (written.size() > c.output_times.size() + 16)
      throw ExternalSolverError(fmt::format("frames/index.csv has more than {} rows for {} "
                                            "output times",
                                            written.size(), c.output_times.size()));
    if (line == "k,time" || line == "k,time,steps") {
      with_steps = line == "k,time,steps";
      continue;
    }
    const auto f = split_csv(line);
    const std::string form = with_steps ? "k,time,steps" : "k,time";
    double k = 0, t = 0, steps = -1;
    if (f.size() != (with_steps ? 3u : 2u) || !parse_number(f[0], k) || !parse_number(f[1], t) ||
        k < 0 || k != std::floor(k) ||
        (with_steps && (!parse_number(f[2], steps) || steps < 0 || steps != std::floor(steps))))
      throw ExternalSolverError(fmt::format("frames/index.csv line {}: '{}' is not '{}'", ln,
                                            line.substr(0, 60), form));
    written[static_cast<std::size_t>(k)] = {t, static_cast<long>(steps)};
  }
  const int n = static_cast<int>(c.x.cols());
  const char* axes[] = {"x", "y", "z"};
  std::vector<std::string> need{"id"};
  for (int a = 0; a < c.dim; ++a) need.push_back(fmt::format("u{}", axes[a]));
  for (int a = 0; a < c.dim; ++a) need.push_back(fmt::format("v{}", axes[a]));
  const std::vector<std::string> stress_cols =
      c.dim == 1 ? std::vector<std::string>{"sxx"} : std::vector<std::string>{"sxx", "syy", "sxy"};

  std::vector<ExternalFrame> out;
  for (std::size_t k = 0; k < c.output_times.size(); ++k) {
    const std::string what = time_name(c, k);
    const auto w = written.find(k);
    const fs::path file = frames / fmt::format("frame-{}.csv", k);
    if (w == written.end() || !fs::is_regular_file(file))
      throw ExternalSolverError(fmt::format(
          "{} missing: {}", what,
          w == written.end() ? "not in frames/index.csv" : "no " + file.filename().string()));
    const double t = c.output_times[k];
    if (!(std::abs(w->second.first - t) <= 1e-9 * std::max(1.0, std::abs(t))))
      throw ExternalSolverError(fmt::format("{}: the solver wrote it at t = {:.9g}, not at the "
                                            "requested time",
                                            what, w->second.first));
    const std::string shown = "frames/" + file.filename().string();
    std::ifstream f = open_solver_file(file, shown);
    capped_getline(f, line, shown, 1);
    const auto header = split_csv(line);
    std::map<std::string, int> col = column_index(header);
    for (const auto& h : need)
      if (!col.count(h))
        throw ExternalSolverError(fmt::format("{}: {} has no column '{}' (header: {})", what,
                                              file.filename().string(), h, line.substr(0, 80)));
    const bool has_stress = std::all_of(stress_cols.begin(), stress_cols.end(),
                                        [&](const std::string& s) { return col.count(s) != 0; });
    ExternalFrame fr;
    fr.time = t;
    fr.steps = w->second.second;
    fr.u = Eigen::MatrixXd::Constant(c.dim, n, std::nan(""));
    fr.v = fr.u;
    if (has_stress)
      fr.stress = Eigen::MatrixXd::Constant(static_cast<int>(stress_cols.size()), n, std::nan(""));
    std::vector<char> seen(n, 0);
    int rows = 0;
    for (int ln = 2; capped_getline(f, line, shown, ln); ++ln) {
      if (line.empty()) continue;
      ++rows;
      const auto v = split_csv(line);
      if (v.size() != header.size())
        throw ExternalSolverError(fmt::format("{}: {} line {} has {} fields, the header {}", what,
                                              file.filename().string(), ln, v.size(),
                                              header.size()));
      double id = 0;
      if (!parse_number(v[col["id"]], id) || id < 0 || id >= n || id != std::floor(id))
        throw ExternalSolverError(fmt::format("{}: {} line {}: id '{}' is not a particle "
                                              "(0 … {})",
                                              what, file.filename().string(), ln, v[col["id"]],
                                              n - 1));
      const int I = static_cast<int>(id);
      if (seen[I])
        throw ExternalSolverError(
            fmt::format("{}: particle {} appears twice in {}", what, I, file.filename().string()));
      seen[I] = 1;
      auto field = [&](const std::string& name) {
        double x = 0;
        if (!parse_number(v[col[name]], x) || !std::isfinite(x))
          throw ExternalSolverError(fmt::format("{}: field {} is {} at particle {}", what, name,
                                                v[col[name]].empty() ? "empty" : v[col[name]], I));
        return x;
      };
      for (int a = 0; a < c.dim; ++a) {
        fr.u(a, I) = field(fmt::format("u{}", axes[a]));
        fr.v(a, I) = field(fmt::format("v{}", axes[a]));
      }
      if (has_stress)
        for (int s = 0; s < static_cast<int>(stress_cols.size()); ++s)
          fr.stress(s, I) = field(stress_cols[s]);
    }
    if (rows != n)
      throw ExternalSolverError(
          fmt::format("{}: {} particles in {}, expected {}", what, rows, file.filename().string(), n));
    fr.x = c.x + fr.u;
    out.push_back(std::move(fr));
  }
  return out;
}

std::array<double, 3> ExternalEnergy::at(double t) const {
  const std::size_t n = time.size();
  if (n == 0) return {NAN, NAN, NAN};
  std::size_t hi = std::upper_bound(time.begin(), time.end(), t) - time.begin();
  if (hi == 0) return {kinetic.front(), internal_work.front(), external_work.front()};
  if (hi == n) return {kinetic.back(), internal_work.back(), external_work.back()};
  const std::size_t lo = hi - 1;
  const double w = (t - time[lo]) / (time[hi] - time[lo]);
  auto lerp = [&](const std::vector<double>& v) { return v[lo] + w * (v[hi] - v[lo]); };
  return {lerp(kinetic), lerp(internal_work), lerp(external_work)};
}

std::optional<ExternalEnergy> read_case_energy(const fs::path& dir, const ExternalCase& c) {
  const fs::path file = dir / "frames" / "energy.csv";
  std::error_code exists_ec;
  if (!fs::exists(fs::symlink_status(file, exists_ec))) return std::nullopt;
  std::ifstream in = open_solver_file(file, "frames/energy.csv");
  if (!in || in.peek() == std::ifstream::traits_type::eof())
    throw ExternalSolverError("frames/energy.csv cannot be read (or is empty)");
  expect_protocol_line(in, "frames/energy.csv");
  std::string line;
  capped_getline(in, line, "frames/energy.csv", 2);
  trim_end(line);
  const auto header = split_csv(line);
  std::map<std::string, int> col = column_index(header);
  for (const char* need : {"time", "kinetic", "internal_work"})
    if (!col.count(need))
      throw ExternalSolverError(fmt::format("frames/energy.csv: no column '{}' (header: '{}'; "
                                            "expected time,kinetic,internal_work[,external_work])",
                                            need, line.substr(0, 80)));
  const bool with_external = col.count("external_work") != 0;
  ExternalEnergy e;
  for (int ln = 3; capped_getline(in, line, "frames/energy.csv", ln); ++ln) {
    trim_end(line);
    if (line.empty()) continue;
    const auto v = split_csv(line);
    if (v.size() != header.size())
      throw ExternalSolverError(fmt::format("frames/energy.csv line {} has {} fields, the "
                                            "header {}",
                                            ln, v.size(), header.size()));
    auto field = [&](const char* name) {
      double x = 0;
      const std::string& text = v[col[name]];
      if (!parse_number(text, x) || !std::isfinite(x))
        throw ExternalSolverError(fmt::format("frames/energy.csv line {}: field {} is {}", ln,
                                              name, text.empty() ? "empty" : text));
      return x;
    };
    const double t = field("time");
    if (!e.time.empty() && !(t > e.time.back()))
      throw ExternalSolverError(fmt::format("frames/energy.csv line {}: time {:.9g} is not "
                                            "after the previous row's {:.9g}",
                                            ln, t, e.time.back()));
    e.time.push_back(t);
    e.kinetic.push_back(field("kinetic"));
    e.internal_work.push_back(field("internal_work"));
    e.external_work.push_back(with_external ? field("external_work") : 0.0);
  }
  const double tol = 1e-9 * std::max(1.0, c.end_time);
  if (e.time.empty())
    throw ExternalSolverError("frames/energy.csv has a header and no rows");
  if (std::abs(e.time.front()) > tol)
    throw ExternalSolverError(fmt::format("frames/energy.csv starts at t = {:.9g}, not at "
                                          "t = 0: the balance is measured from the start",
                                          e.time.front()));
  const double last = c.output_times.empty() ? 0.0 : c.output_times.back();
  if (e.time.back() < last - tol)
    throw ExternalSolverError(fmt::format("frames/energy.csv ends at t = {:.9g}, before the "
                                          "last output time {:.9g}",
                                          e.time.back(), last));
  return e;
}

Discretization ExternalSolverMethod::discretize(const Domain&, ParticleSet, int) const {
  throw InputError(fmt::format(
      "method 'external:{}' is an external solver: it runs through the transient analysis "
      "only, on the problems its file '{}' names ({}); choose one of those",
      spec_.name, spec_.file.string(), fmt::join(spec_.problems, ", ")));
}

void ExternalSolverMethod::retabulate(Discretization&, int) const {
  throw std::logic_error("an external solver has no tables to recompute");
}

void register_external_solvers(MethodRegistry& methods, const std::vector<SolverSpec>& specs) {
  for (const SolverSpec& spec : specs) {
    if (!spec.broken.empty()) {
      methods.add("external:" + spec.name,
                  fmt::format("external solver, NOT USABLE: {}", spec.broken), {},
                  [spec](const Params&) -> std::unique_ptr<Method> {
                    throw InputError(spec.broken);
                  });
      continue;
    }
    ParamSchema schema;
    ParamSpec keep = ParamSpec::count("keep", 0, 0,
                                      "1: keep the case directory (input, frames, stdout, "
                                      "stderr) and name it; 0: remove it after the run");
    keep.max = 1;
    schema.push_back(std::move(keep));
    for (const auto& [name, value] : spec.params.values()) {
      ParamSpec p;
      p.name = name;
      p.description = fmt::format("the solver's own parameter ({} [solver.params])",
                                  spec.file.filename().string());
      p.default_value = value;
      schema.push_back(std::move(p));
    }
    methods.add(
        "external:" + spec.name,
        fmt::format("external solver: {} ({}; supports {})",
                    spec.description.empty() ? shown_command(spec.command) : spec.description,
                    spec.file.string(), fmt::join(spec.problems, ", ")),
        std::move(schema), [&methods, spec](const Params& p) -> std::unique_ptr<Method> {
          return std::make_unique<ExternalSolverMethod>(spec, methods.create("sph"), p);
        });
  }
}

std::vector<fs::path> solver_dirs() {
  std::vector<fs::path> out;
  if (const char* env = std::getenv("MFV_SOLVERS")) {
    std::stringstream dirs(env);
    for (std::string d; std::getline(dirs, d, ':');)
      if (!d.empty()) out.emplace_back(d);
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path installed = exe.parent_path().parent_path() / "share" / "mfv" / "solvers";
  if (!ec && fs::is_directory(installed, ec)) {
    out.push_back(installed);
  } else {
#ifdef MFV_SOURCE_DIR
    out.emplace_back(fs::path(MFV_SOURCE_DIR) / "solvers");
#endif
  }
  // A directory named twice (MFV_SOLVERS holding the default one, or one of its entries
  // twice) is read once: its files are not two definitions of each solver.
  std::vector<fs::path> unique;
  std::set<fs::path> seen;
  for (const fs::path& d : out)
    if (seen.insert(fs::weakly_canonical(d, ec)).second) unique.push_back(d);
  return unique;
}

std::vector<SolverSpec> find_solver_specs() {
  std::vector<SolverSpec> out;
  std::map<std::string, fs::path> seen;
  for (const auto& dir : solver_dirs())
    for (SolverSpec& s : read_solver_specs(dir)) {
      if (const auto it = seen.find(s.name); it != seen.end())
        throw InputError(fmt::format("external solver '{}' is defined twice: '{}' and '{}'; "
                                     "rename one file (MFV_SOLVERS is searched first)",
                                     s.name, it->second.string(), s.file.string()));
      seen[s.name] = s.file;
      out.push_back(std::move(s));
    }
  return out;
}

}  // namespace mfv
