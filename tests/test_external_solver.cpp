// External solvers (issue 30): the solver file's checks, the protocol's input, the run
// without a shell under a timeout, and the output's checks: a broken solver (timeout, exit
// code, missing checkpoint, NaN field, wrong particle count) is a failure naming the cause,
// and solvers/fem-rod (the protocol's one-page example) runs a rod pulse close to d'Alembert.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "dynamics/external_solver.hpp"
#include "methods/core/errors.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "mfv-external-XXXXXX").string();
    path = ::mkdtemp(t.data());
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

/// The rod pulse of 001 §9.2 (mm, ms, kg, GPa) on `nx` × 2 particles, Gaussian velocity.
ExternalCase rod_case(int nx, std::vector<double> times) {
  ExternalCase c;
  c.problem = "rod-pulse";
  c.nodes = nx;
  c.dim = 2;
  c.unit_system = "mm, ms, kg, GPa";
  c.time_unit = "ms";
  const int n = 2 * nx;
  c.x.resize(2, n);
  c.initial_velocity.resize(2, n);
  c.volume.resize(n);
  c.mass.resize(n);
  c.sides.assign(n, 0);
  const double L = 60, dx = L / (nx - 1);
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < nx; ++i) {
      const int I = j * nx + i;
      c.x(0, I) = i * dx;
      c.x(1, I) = 5.0 * j;
      c.volume(I) = dx * 2.5;
      c.mass(I) = 7.8e-6 * c.volume(I);
      c.initial_velocity(0, I) = std::exp(-0.25 * (i * dx - 30) * (i * dx - 30));
      c.initial_velocity(1, I) = 0;
    }
  c.material = "svk";
  c.material_params.set("E", 210.0);
  c.material_params.set("nu", 0.0);
  c.density = 7.8e-6;
  c.output_times = std::move(times);
  c.end_time = c.output_times.back();
  c.checkpoints = {c.output_times.back()};
  return c;
}

/// A solver in Python that writes correct frames of zeros, broken as `mode` says.
SolverSpec fake_solver(const fs::path& dir, const std::string& mode, double timeout = 30) {
  write(dir / "fake.py", R"(import json, os, sys, time
mode = sys.argv[1]; case = sys.argv[2]
inp = json.load(open(os.path.join(case, "input.json")))
n = inp["particles"]["count"]
if mode == "sleep": time.sleep(60)
if mode == "exit": sys.stderr.write("solver blew up at step 7\n"); sys.exit(3)
os.makedirs(os.path.join(case, "frames"))
ix = open(os.path.join(case, "frames", "index.csv"), "w")
ix.write("mfv-external-1\n" if mode != "protocol" else "mfv-external-0\n")
for k, t in enumerate(inp["output_times"]):
    if mode == "missing" and k == len(inp["output_times"]) - 1: break
    with open(os.path.join(case, "frames", f"frame-{k}.csv"), "w") as f:
        f.write("id,ux,uy,vx,vy\n")
        for i in range(n - (1 if mode == "count" else 0)):
            vx = "nan" if mode == "nan" and i == 17 else "0"
            f.write(f"{i},0,0,{vx},0\n")
    ix.write(f"{k},{t + (1e-3 if mode == 'time' else 0)!r}\n")
)");
  write(dir / "fake.toml", fmt::format("[solver]\ncommand = [\"python3\", \"{{solver_dir}}/fake.py\", "
                                       "\"{}\"]\nproblems = [\"rod-pulse\"]\ntimeout = {}\n",
                                       mode, timeout));
  return read_solver_spec(dir / "fake.toml");
}

/// Runs the fake in a fresh case directory and reads its output.
std::string run_fake(const std::string& mode, double timeout = 30) {
  TempDir t;
  const SolverSpec s = fake_solver(t.path, mode, timeout);
  const ExternalCase c = rod_case(13, {0.005, 0.01});
  fs::create_directory(t.path / "case");
  write_case_input(t.path / "case", c);
  return message_of([&] {
    run_solver(s, t.path / "case");
    read_case_output(t.path / "case", c);
  });
}

TEST(ExternalSolver, SolverFilesAreChecked) {
  TempDir t;
  auto refused = [&](const std::string& text) {
    write(t.path / "s.toml", text);
    return message_of([&] { read_solver_spec(t.path / "s.toml"); });
  };
  EXPECT_NE(refused("[solver]\nproblems = [\"rod-pulse\"]\n").find("command is missing"),
            std::string::npos);
  EXPECT_NE(refused("[solver]\ncommand = []\nproblems = [\"rod-pulse\"]\n").find("empty"),
            std::string::npos);
  EXPECT_NE(refused("[solver]\ncommand = \"python3 x.py\"\nproblems = [\"rod-pulse\"]\n")
                .find("array of strings"),
            std::string::npos);
  EXPECT_NE(refused("[solver]\ncommand = [\"a\"]\nproblems = [\"rod-pulse\"]\ntimeout = -1\n")
                .find("timeout must be a positive"),
            std::string::npos);
  EXPECT_NE(refused("[solver]\ncommand = [\"a\"]\nproblems = [\"rod-pulse\"]\nshell = true\n")
                .find("unknown key [solver] shell"),
            std::string::npos);
  EXPECT_NE(refused("command = [\"a\"]\n").find("no [solver] table"), std::string::npos);
  EXPECT_NE(refused("[solver\n").find("not TOML"), std::string::npos);
  EXPECT_NE(refused("[solver]\ncommand = [\"a\"]\nproblems = []\n").find("problems is empty"),
            std::string::npos);
  // A good one: {solver_dir} is the file's directory, the name its stem.
  write(t.path / "good.toml", "[solver]\ncommand = [\"python3\", \"{solver_dir}/a.py\"]\n"
                              "problems = [\"rod-pulse\"]\n");
  const SolverSpec s = read_solver_spec(t.path / "good.toml");
  EXPECT_EQ(s.name, "good");
  EXPECT_EQ(s.command.at(1), (fs::absolute(t.path) / "a.py").string());
  EXPECT_TRUE(s.supports("rod-pulse"));
  EXPECT_FALSE(s.supports("cantilever"));
  // The solver's own parameters: numbers and strings; anything else, and mfv's `keep`, refused.
  write(t.path / "p.toml", "[solver]\ncommand = [\"a\"]\nproblems = [\"rod-pulse\"]\n"
                           "[solver.params]\nh_over_dx = 1.3\nclamp = \"held\"\nsteps = 4\n");
  const SolverSpec p = read_solver_spec(t.path / "p.toml");
  EXPECT_EQ(p.params.number("h_over_dx"), 1.3);
  EXPECT_EQ(p.params.number("steps"), 4.0);
  EXPECT_EQ(p.params.text("clamp"), "held");
  EXPECT_NE(refused("[solver]\ncommand = [\"a\"]\nproblems = [\"r\"]\n[solver.params]\nx = [1]\n")
                .find("must be a number or a string"),
            std::string::npos);
  EXPECT_NE(refused("[solver]\ncommand = [\"a\"]\nproblems = [\"r\"]\n[solver.params]\nkeep = 1\n")
                .find("keep is mfv's own"),
            std::string::npos);
}

TEST(ExternalSolver, TheRepositorysSolverFilesRead) {
  const auto specs = read_solver_specs(fs::path(MFV_SOURCE_DIR) / "solvers");
  ASSERT_FALSE(specs.empty());
  for (const auto& s : specs) EXPECT_FALSE(s.problems.empty()) << s.name;
}

TEST(ExternalSolver, InputGoesOnlyIntoAFreshDirectory) {
  TempDir t;
  write(t.path / "old.txt", "an earlier run's");
  EXPECT_THROW(write_case_input(t.path, rod_case(13, {0.01})), std::runtime_error);
  fs::create_directory(t.path / "case");
  write_case_input(t.path / "case", rod_case(13, {0.01}));
  std::ifstream in(t.path / "case" / "input.json");
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"protocol\": \"mfv-external-1\""), std::string::npos);
  EXPECT_NE(json.find("\"output_times\""), std::string::npos);
}

TEST(ExternalSolver, ABrokenSolverFailsNamingTheCause) {
  EXPECT_EQ(run_fake("ok"), "(no exception)");
  EXPECT_NE(run_fake("sleep", 1).find("did not finish within its timeout of 1 s"),
            std::string::npos);
  const std::string exit = run_fake("exit");
  EXPECT_NE(exit.find("exited 3"), std::string::npos) << exit;
  EXPECT_NE(exit.find("solver blew up at step 7"), std::string::npos) << exit;
  EXPECT_NE(run_fake("missing").find("checkpoint t = 0.01 (frame 1) missing"), std::string::npos);
  EXPECT_NE(run_fake("nan").find("field vx is nan at particle 17"), std::string::npos);
  EXPECT_NE(run_fake("count").find("25 particles in frame-0.csv, expected 26"),
            std::string::npos);
  EXPECT_NE(run_fake("time").find("not at the requested time"), std::string::npos);
  EXPECT_NE(run_fake("protocol").find("expected the protocol 'mfv-external-1'"),
            std::string::npos);
}

TEST(ExternalSolver, ASolverThatIsNotInstalledSaysHowToInstallIt) {
  TempDir t;
  write(t.path / "absent.toml",
        "[solver]\ncommand = [\"mfv-no-such-solver\"]\nproblems = [\"rod-pulse\"]\n"
        "install_hint = \"apt install mfv-no-such-solver\"\n");
  const SolverSpec s = read_solver_spec(t.path / "absent.toml");
  ASSERT_TRUE(solver_missing(s).has_value());
  fs::create_directory(t.path / "case");
  try {
    run_solver(s, t.path / "case");
    FAIL() << "ran a solver that does not exist";
  } catch (const ExternalSolverMissing& e) {
    EXPECT_NE(std::string(e.what()).find("no such program on PATH"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("apt install mfv-no-such-solver"), std::string::npos);
  }
  // A check that fails is "not installed" too (a Python module that is missing).
  write(t.path / "check.toml",
        "[solver]\ncommand = [\"python3\"]\ncheck = [\"python3\", \"-c\", \"import "
        "mfv_no_such_module\"]\nproblems = [\"rod-pulse\"]\n");
  EXPECT_THROW(run_solver(read_solver_spec(t.path / "check.toml"), t.path / "case"),
               ExternalSolverMissing);
}

TEST(ExternalSolver, TheProtocolExampleRunsTheRodPulse) {
  // solvers/fem-rod: 1D linear elements on the particles' x. At t = L/(2c) the Gaussian has
  // split into two halves centred on the ends (d'Alembert with free-end reflections).
  const auto specs = read_solver_specs(fs::path(MFV_SOURCE_DIR) / "solvers");
  const auto it = std::find_if(specs.begin(), specs.end(),
                               [](const SolverSpec& s) { return s.name == "fem-rod"; });
  ASSERT_NE(it, specs.end());
  const double c = std::sqrt(210 / 7.8e-6), transit = 60 / c;
  const ExternalCase rod = rod_case(241, {0.25 * transit, 0.5 * transit, transit});
  TempDir t;
  fs::create_directory(t.path / "case");
  write_case_input(t.path / "case", rod);
  const SolverRun run = run_solver(*it, t.path / "case");
  EXPECT_EQ(run.exit_code, 0);
  const auto frames = read_case_output(t.path / "case", rod);
  ASSERT_EQ(frames.size(), 3u);
  // At t = L/c the pulse is whole again at the centre: v(x, L/c) = v(x, 0).
  double err = 0, norm = 0;
  for (int I = 0; I < rod.x.cols(); ++I) {
    err += std::pow(frames[2].v(0, I) - rod.initial_velocity(0, I), 2);
    norm += std::pow(rod.initial_velocity(0, I), 2);
  }
  EXPECT_LT(std::sqrt(err / norm), 0.05);
  EXPECT_TRUE(frames[2].stress.allFinite());
  // Its energy account: the kinetic energy and the elements' work, conserved by central
  // differences to well under a per cent (K + W_int against its t = 0 value).
  const auto energy = read_case_energy(t.path / "case", rod);
  ASSERT_TRUE(energy.has_value());
  ASSERT_EQ(energy->time.size(), 4u);
  const double e0 = energy->kinetic[0];
  EXPECT_GT(e0, 0);
  for (std::size_t i = 0; i < energy->time.size(); ++i)
    EXPECT_LT(std::abs(energy->kinetic[i] + energy->internal_work[i] - e0), 1e-3 * e0) << i;
  EXPECT_GT(energy->internal_work[1], 0.1 * e0);  // a quarter transit in: strain energy held
}

/// Reads `text` as frames/energy.csv of a case whose last output time is 1.
std::string energy_message(const std::string& text) {
  TempDir t;
  ExternalCase c;
  c.output_times = {0.5, 1.0};
  c.end_time = 1.0;
  write(t.path / "frames" / "energy.csv", text);
  return message_of([&] { read_case_energy(t.path, c); });
}

TEST(ExternalSolver, TheEnergyAccountIsOptionalAndChecked) {
  TempDir t;
  ExternalCase c;
  c.output_times = {0.5, 1.0};
  c.end_time = 1.0;
  EXPECT_FALSE(read_case_energy(t.path, c).has_value());  // none written: not measured
  const std::string head = "mfv-external-1\ntime,kinetic,internal_work\n";
  EXPECT_EQ(energy_message(head + "0,2,0\n1,1,1\n"), "(no exception)");
  EXPECT_NE(energy_message("mfv-external-0\n" + head.substr(15) + "0,2,0\n1,1,1\n")
                .find("expected the protocol"),
            std::string::npos);
  EXPECT_NE(energy_message("mfv-external-1\ntime,kinetic\n0,2\n1,1\n")
                .find("no column 'internal_work'"),
            std::string::npos);
  EXPECT_NE(energy_message(head + "0,2,0\n0.5,nan,1\n1,1,1\n")
                .find("line 4: field kinetic is nan"),
            std::string::npos);
  EXPECT_NE(energy_message(head + "0.1,2,0\n1,1,1\n").find("not at t = 0"), std::string::npos);
  EXPECT_NE(energy_message(head + "0,2,0\n0.5,1,1\n").find("before the last output time"),
            std::string::npos);
  EXPECT_NE(energy_message(head + "0,2,0\n0.5,1,1\n0.5,1,1\n1,1,1\n")
                .find("is not after the previous row's"),
            std::string::npos);
  EXPECT_NE(energy_message(head + "0,2\n1,1,1\n").find("line 3 has 2 fields"),
            std::string::npos);
  // Columns by name, in any order, external work optional; values linear between rows.
  write(t.path / "frames" / "energy.csv",
        "mfv-external-1\nexternal_work,internal_work,time,kinetic,extra\n0,0,0,2,x\n"
        "1,2,1,1,y\n");
  const auto e = read_case_energy(t.path, c);
  ASSERT_TRUE(e.has_value());
  const auto mid = e->at(0.25);
  EXPECT_DOUBLE_EQ(mid[0], 1.75);
  EXPECT_DOUBLE_EQ(mid[1], 0.5);
  EXPECT_DOUBLE_EQ(mid[2], 0.25);
  EXPECT_DOUBLE_EQ(e->at(7.0)[0], 1.0);  // clamped to the rows' range
}

/// A case directory whose frames/ holds index.csv as `index` says (or a FIFO, or a link).
std::string output_message(const std::function<void(const fs::path& frames)>& make) {
  TempDir t;
  const ExternalCase c = rod_case(13, {0.005, 0.01});
  fs::create_directories(t.path / "frames");
  make(t.path / "frames");
  return message_of([&] { read_case_output(t.path, c); });
}

TEST(ExternalSolver, SolverOutputIsReadLikeAnyOtherInput) {
  // Issue 45: a FIFO or a device in place of a solver file is refused before it is opened
  // (a FIFO blocked mfv for ever, /dev/zero read for ever); a line has a cap.
  EXPECT_NE(output_message([](const fs::path& f) {
              ASSERT_EQ(::mkfifo((f / "index.csv").c_str(), 0600), 0);
            }).find("frames/index.csv is not a regular file (a special file)"),
            std::string::npos);
  EXPECT_NE(output_message([](const fs::path& f) {
              fs::create_symlink("/dev/zero", f / "index.csv");
            }).find("not a regular file"),
            std::string::npos);
  EXPECT_NE(output_message([](const fs::path& f) {
              write(f / "index.csv", "mfv-external-1\nk,time\n" + std::string(3 << 20, '7'));
            }).find("frames/index.csv line 3 is longer than 1048576 bytes"),
            std::string::npos);
  EXPECT_NE(output_message([](const fs::path& f) {
              std::string rows = "mfv-external-1\nk,time\n";
              for (int k = 0; k < 100; ++k) rows += fmt::format("{},0.005\n", 1000 + k);
              write(f / "index.csv", rows);
            }).find("more than"),
            std::string::npos);
  {
    TempDir t;
    ExternalCase c;
    c.output_times = {0.5, 1.0};
    c.end_time = 1.0;
    fs::create_directories(t.path / "frames");
    ASSERT_EQ(::mkfifo((t.path / "frames" / "energy.csv").c_str(), 0600), 0);
    EXPECT_NE(message_of([&] { read_case_energy(t.path, c); })
                  .find("frames/energy.csv is not a regular file"),
              std::string::npos);
  }
  // stdout/stderr: only the tail is read, and a FIFO is not waited on.
  TempDir t;
  std::string big(5 << 20, 'a');
  big += "THE END";
  write(t.path / "stdout.txt", big);
  EXPECT_EQ(file_tail(t.path / "stdout.txt", 7), "…THE END");
  ASSERT_EQ(::mkfifo((t.path / "stderr.txt").c_str(), 0600), 0);
  EXPECT_EQ(file_tail(t.path / "stderr.txt"), "(not a regular file)");
}

TEST(ExternalSolver, TheChecksTemporaryFilesArePrivate) {
  // The check's output went to $TMPDIR/mfv-check-<pid>-{out,err}, truncating and deleting a
  // user's files of those names; it now has a private directory of its own.
  TempDir t;
  const fs::path mine_out = t.path / fmt::format("mfv-check-{}-out", ::getpid());
  const fs::path mine_err = t.path / fmt::format("mfv-check-{}-err", ::getpid());
  write(mine_out, "my notes\n");
  write(mine_err, "my other notes\n");
  write(t.path / "c.toml",
        "[solver]\ncommand = [\"python3\"]\ncheck = [\"python3\", \"-c\", \"print(1)\"]\n"
        "problems = [\"rod-pulse\"]\n");
  const char* old = std::getenv("TMPDIR");
  const std::string saved = old ? old : "";
  ::setenv("TMPDIR", t.path.c_str(), 1);
  const auto missing = solver_missing(read_solver_spec(t.path / "c.toml"));
  if (old) ::setenv("TMPDIR", saved.c_str(), 1); else ::unsetenv("TMPDIR");
  EXPECT_FALSE(missing.has_value()) << *missing;
  std::ifstream a(mine_out), b(mine_err);
  std::string la, lb;
  std::getline(a, la);
  std::getline(b, lb);
  EXPECT_EQ(la, "my notes");
  EXPECT_EQ(lb, "my other notes");
  for (const auto& e : fs::directory_iterator(t.path))
    EXPECT_EQ(e.path().filename().string().rfind("mfv-check-", 0) == 0 &&
                  fs::is_directory(e.path()),
              false)
        << "left behind: " << e.path();
}

}  // namespace
}  // namespace mfv
