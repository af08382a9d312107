/// Bad input everywhere (issue 12 item 2): every input that used to crash, overflow or run
/// silently wrong is refused with an InputError naming the input, through the commands and
/// through the mfv executable (exit 2 for every parse error, 0 for --help).
#include <array>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "apps/commands.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/params.hpp"
#include "methods/core/resources.hpp"
#include "methods/particles.hpp"

namespace mfv {
namespace {

const Catalogue& catalogue() {
  static const Catalogue c;
  return c;
}

/// Runs `f`, expects an InputError whose message contains every one of `words`.
void expect_input_error(const std::function<void()>& f, const std::vector<std::string>& words) {
  try {
    f();
    ADD_FAILURE() << "expected InputError mentioning " << words.front();
  } catch (const InputError& e) {
    for (const auto& w : words)
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos)
          << "message lacks '" << w << "': " << e.what();
  }
}

// --- The crashes of issue 12, each now an InputError ---------------------------------------

struct RunCase {
  const char* name;
  RunOptions options;
  std::vector<std::string> words;  ///< the message must name these
};

class BadRun : public ::testing::TestWithParam<RunCase> {};

TEST_P(BadRun, IsRefusedNamingTheInput) {
  const RunCase& c = GetParam();
  std::ostringstream out;
  expect_input_error([&] { command_run(catalogue(), c.options, out); }, c.words);
}

RunOptions run(std::string problem, std::string method, int nodes, std::string method_params = "",
               std::string problem_params = "", double perturb = 0) {
  RunOptions o;
  o.problem = std::move(problem);
  o.method = std::move(method);
  o.nodes = nodes;
  o.method_params = std::move(method_params);
  o.problem_params = std::move(problem_params);
  o.perturbation = perturb;
  return o;
}

INSTANTIATE_TEST_SUITE_P(
    Issue12, BadRun,
    ::testing::Values(
        // A null second-derivative table used to segfault in the stabilized form.
        RunCase{"advection_sph", run("advection-diffusion", "sph", 31, "", "a=1"),
                {"second derivatives", "a=0"}},
        RunCase{"advection_rlm", run("advection-diffusion", "rlm", 31, "", "a=1000"),
                {"second derivatives"}},
        RunCase{"advection_kbm", run("advection-diffusion", "kbm-ni", 31, "", "a=1"),
                {"second derivatives"}},
        // Enrichment unknowns overflowed the explicit engine's force tables.
        RunCase{"dispersion_xefg",
                run("dispersion", "xefg", 5, "crack=through,crack_x=0.31"),
                {"crack enrichment", "crack=none"}},
        RunCase{"time_step_xefg", run("time-step", "xefg", 11, "crack=through,crack_x=0.31"),
                {"crack enrichment", "crack=none"}},
        RunCase{"stretch_map_xefg",
                run("stretch-map", "xefg", 5, "crack=through,crack_x=0.31", "grid=2"),
                {"crack enrichment"}},
        // 46,341² overflows int: counted in 64 bits and refused.
        RunCase{"lattice_overflow", run("elastic-patch", "fem", 46341), {"46341", "lower --nodes"}},
        RunCase{"cantilever_overflow", run("cantilever", "fem", 600000000), {"--nodes"}},
        // 1e9 particles on a line would take terabytes: refused with the estimate.
        RunCase{"line_memory", run("laplace-tanh", "fem", 1000000000), {"GB", "available"}},
        // A time step so small that the step count overflows used to become one huge step.
        // (1e-90: values below 1e-100 in magnitude are refused earlier, by the parameter check.)
        RunCase{"dt_tiny", run("prestressed-rod", "fem", 11, "", "dt=1e-90"), {"dt", "steps"}},
        // Found by scripts/fuzz_cases.py: a step past L/c put grk-bar's checkpoints so far
        // out that the exact solution's reflection sum never ended.
        RunCase{"grk_bar_dt_huge", run("grk-bar", "fem", 11, "", "dt=1e9"), {"dt", "L/c"}},
        // Found by scripts/fuzz_cases.py: bands=1e9 wavelet dilations ran for ever.
        RunCase{"wavelet_bands_huge", run("laplace-tanh", "wavelet", 21, "bands=1e9"),
                {"bands", "16"}},
        // Found by scripts/fuzz_cases.py: a support of 1e300 overflowed the patch width.
        RunCase{"dispersion_support_huge", run("dispersion", "sph", 5, "radius=1e90"),
                {"supports reach", "smaller support"}},
        RunCase{"enriched_bar_positions_huge",
                run("enriched-bar", "xefg", 5, "", "positions=1000000000"), {"positions"}},
        // Found by scripts/fuzz_cases.py: a window 2^j that underflows to zero.
        RunCase{"rkpm_window_underflow", run("laplace-tanh", "rkpm", 21, "j=-1e90"), {"2^j"}},
        RunCase{"dt_negative", run("prestressed-rod", "fem", 11, "", "dt=-1"), {"dt"}},
        RunCase{"perturb_nan", run("laplace-tanh", "fem", 21, "", "", std::nan("")),
                {"--perturb"}},
        RunCase{"perturb_negative", run("laplace-tanh", "fem", 21, "", "", -0.1), {"--perturb"}},
        RunCase{"nodes_zero", run("laplace-tanh", "fem", 0), {"--nodes"}},
        RunCase{"param_nan", run("laplace-tanh", "rkpm", 21, "j=nan"), {"'j'", "finite"}},
        RunCase{"param_duplicate", run("laplace-tanh", "efg", 21, "dmax=2,dmax=3"),
                {"dmax", "twice"}}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(BadInput, AdvectionWithGalerkinMethodsStillRuns) {
  // The refusal is specific: methods with second derivatives keep solving a != 0.
  std::ostringstream out;
  command_run(catalogue(), run("advection-diffusion", "fem", 31, "", "a=1"), out);
  EXPECT_NE(out.str().find("L2 error"), std::string::npos) << out.str();
}

TEST(BadInput, AnalyseRefusesReportWithNoReportAndNegativeNodes) {
  std::ostringstream out;
  AnalyseOptions o;
  o.problem = "time-step";
  o.method = "fem";
  o.report = "somewhere";
  o.no_report = true;
  expect_input_error([&] { command_analyse(catalogue(), o, out); }, {"--no-report"});
  o.report.clear();
  o.nodes = -5;
  expect_input_error([&] { command_analyse(catalogue(), o, out); }, {"-5"});
}

TEST(BadInput, StudyRefusesDuplicateResolutionsAndFullWithNodes) {
  std::ostringstream out, progress;
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"fem"};
  o.nodes = {21, 41, 21};
  expect_input_error([&] { command_compare(catalogue(), o, out, progress); }, {"21", "twice"});
  o.nodes = {21};
  o.full = true;
  expect_input_error([&] { command_compare(catalogue(), o, out, progress); }, {"--full"});
  EXPECT_TRUE(progress.str().empty()) << "nothing may run before the input is checked";
}

TEST(BadInput, StudySortsResolutionsCoarseToFine) {
  std::ostringstream out, progress;
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"fem"};
  o.nodes = {81, 21, 41};
  ASSERT_EQ(command_compare(catalogue(), o, out, progress), 0);
  const std::string p = progress.str();
  EXPECT_LT(p.find("21 nodes"), p.find("41 nodes")) << p;
  EXPECT_LT(p.find("41 nodes"), p.find("81 nodes")) << p;
}

// --- The size checks and the parameter parser ----------------------------------------------

TEST(BadInput, ParticleCountsAreCheckedIn64Bits) {
  EXPECT_EQ(checked_particle_count(46340, 46340, "t"), std::int64_t{46340} * 46340);
  expect_input_error([] { checked_particle_count(46341, 46341, "t"); }, {"2^31"});
  expect_input_error([] { checked_particle_count(-1, 5, "t"); }, {"negative"});
  expect_input_error(
      [] { rectangle_lattice(Domain::rectangle(0, 0, 1, 1), 50000, 50000, Placement::boundary); },
      {"50000"});
}

TEST(BadInput, MemoryEstimateRefusesWhatTheMachineCannotHold) {
  const std::uint64_t have = available_memory_bytes();
  ASSERT_GT(have, 0u) << "neither /proc/meminfo nor sysconf reports available memory";
  // Twice what is available by the 1D estimate is refused; a small case passes.
  const auto too_many = static_cast<std::int64_t>(2.0 * have / kBytesPerParticle1D);
  expect_input_error([&] { check_case_memory(too_many, 1, "probe"); }, {"probe", "GB"});
  EXPECT_NO_THROW(check_case_memory(1000, 1, "probe"));
  EXPECT_NO_THROW(check_case_memory(1000, 2, "probe"));
}

TEST(BadInput, ParamsRefuseDuplicateKeysAndHugeIntegers) {
  expect_input_error([] { Params::parse("dmax=2,dmax=3"); }, {"dmax", "twice"});
  expect_input_error([] { Params::parse("kernel=gaussian, kernel=gaussian"); }, {"kernel"});
  EXPECT_NO_THROW(Params::parse("dmax=2,kernel=gaussian"));
  Params p;
  p.set("j", 1e300);
  expect_input_error([&] { p.integer("j"); }, {"'j'"});
  p.set("j", std::nan(""));
  expect_input_error([&] { p.integer("j"); }, {"'j'"});
}

// --- The executable: parse errors exit 2, help 0, unknown subcommands named ----------------

struct CliCase {
  const char* name;
  std::string args;
  int exit_code;
  const char* message;  ///< must appear in stdout + stderr
};

class Cli : public ::testing::TestWithParam<CliCase> {};

TEST_P(Cli, ExitCodeAndMessage) {
  const CliCase& c = GetParam();
  const std::string cmd = std::string(MFV_EXECUTABLE) + " " + c.args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  std::array<char, 4096> buf{};
  while (const std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) text.append(buf.data(), n);
  const int status = ::pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << c.args << " ended by a signal:\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), c.exit_code) << c.args << "\n" << text;
  EXPECT_NE(text.find(c.message), std::string::npos) << c.args << "\n" << text;
}

INSTANTIATE_TEST_SUITE_P(
    Issue12, Cli,
    ::testing::Values(
        CliCase{"help", "--help", 0, "Subcommands"},
        CliCase{"run_help", "run --help", 0, "--nodes"},
        CliCase{"no_subcommand", "", 2, "subcommand"},
        CliCase{"unknown_subcommand", "frobnicate", 2, "unknown subcommand 'frobnicate'"},
        CliCase{"unknown_option", "run laplace-tanh -m fem -n 21 --frob", 2, "--frob"},
        CliCase{"missing_required", "run laplace-tanh -n 21", 2, "--method"},
        CliCase{"nodes_not_a_number", "run laplace-tanh -m fem -n many", 2, "many"},
        CliCase{"nodes_negative", "run laplace-tanh -m fem -n -4", 2, "-4"},
        CliCase{"nodes_huge", "run laplace-tanh -m fem -n 99999999999", 2, "99999999999"},
        CliCase{"perturb_nan", "run laplace-tanh -m fem -n 21 --perturb nan", 2, "--perturb"},
        CliCase{"perturb_too_big", "run laplace-tanh -m fem -n 21 --perturb 0.7", 2, "--perturb"},
        CliCase{"sigma_inf", "dispersion -m fem --sigma inf --no-report", 2, "--sigma"},
        CliCase{"points_too_few", "dispersion -m fem --points 1 --no-report", 2, "--points"},
        CliCase{"full_with_nodes", "study laplace-tanh -m fem --full -n 21,41", 2, "--full"},
        CliCase{"report_with_no_report", "verify suites/default.toml -r x --no-report", 2,
                "--no-report"},
        CliCase{"analyse_report_with_no_report", "analyse time-step -m fem -r x --no-report", 2,
                "--no-report"},
        CliCase{"duplicate_param", "run laplace-tanh -m efg -n 21 -p dmax=2,dmax=3", 2, "twice"},
        CliCase{"duplicate_resolution", "study laplace-tanh -m fem -n 21,41,21", 2, "twice"},
        CliCase{"advection_sph", "run advection-diffusion -m sph -n 31 --problem-params a=1", 2,
                "second derivatives"},
        CliCase{"dt_tiny", "run grk-bar -m fem -n 11 --problem-params dt=1e-90", 2, "steps"},
        CliCase{"dt_denormal", "run grk-bar -m fem -n 11 --problem-params dt=1e-300", 2,
                "rescale it"},
        CliCase{"dispersion_points", "dispersion -m fem --points 5 --no-report", 0, "verdict"}),
    [](const auto& info) { return std::string(info.param.name); });

// Issue 26's smaller ones: each refused before any computation with exit 2, or a failure to
// write what was asked reported as one (exit 1), never a silent success.
INSTANTIATE_TEST_SUITE_P(
    Issue26, Cli,
    ::testing::Values(
        CliCase{"empty_report", "study laplace-tanh -m fem -n 21,41 -r ''", 2,
                "names no directory"},
        CliCase{"empty_verify_report", "verify suites/default.toml -r ''", 2,
                "names no directory"},
        CliCase{"vtk_in_missing_directory",
                "run laplace-tanh -m fem -n 21 --vtk /nonexistent-mfv/dir/x.vtp", 2,
                "does not exist"},
        CliCase{"ctest_output_in_missing_directory",
                "manifest-ctest suites/default.toml -o /nonexistent-mfv/x.cmake --mfv x", 2,
                "does not exist"},
        CliCase{"manifest_is_a_directory", "verify suites --no-report", 2,
                "a directory, not a regular file"},
        CliCase{"manifest_is_a_device", "verify /dev/zero --no-report", 2,
                "a character device, not a regular file"},
        // A support over the whole body is a dense system: refused with the estimate, in a
        // second (it used to run 206 s at 2.7 GB, and 7.6 GB for the patch).
        CliCase{"support_over_the_whole_body", "run cantilever -m efg-ni -n 21 -p radius=100", 2,
                "the system would be dense"},
        CliCase{"sph_galerkin_window_over_the_whole_patch",
                "run elastic-patch -m sph-galerkin -n 61 -p h=100", 2, "would be dense"},
        CliCase{"manifest_name_too_long",
                "verify " + std::string(5000, 'x') + ".toml --no-report", 2, "too long"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(Cli, OutputToAFullDiskIsAFailure) {
  const std::string err = ::testing::TempDir() + "mfv-full-disk.txt";
  const std::string cmd = std::string(MFV_EXECUTABLE) + " list > /dev/full 2> " + err;
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::string text;
  if (FILE* f = std::fopen(err.c_str(), "r")) {
    std::array<char, 4096> buf{};
    while (const std::size_t n = std::fread(buf.data(), 1, buf.size(), f)) text.append(buf.data(), n);
    std::fclose(f);
  }
  EXPECT_NE(text.find("cannot write to standard output"), std::string::npos) << text;
  std::remove(err.c_str());
}

}  // namespace
}  // namespace mfv
