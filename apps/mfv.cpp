/// mfv: meshfree verification suite command line (CLI11).
#include <algorithm>
#include <filesystem>
#include <cmath>
#include <new>
#include <iostream>
#include <limits>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "dynamics/external_solver.hpp"
#include "apps/commands.hpp"
#include "apps/plugins.hpp"
#include "apps/supervise.hpp"
#include "reports/atomic.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/names.hpp"
#include "methods/core/petsc_session.hpp"
#include "verify/manifest.hpp"
#include "verify/provenance.hpp"

namespace {

/// A finite number in [lo, hi) (hi_open) or [lo, hi]: CLI::Range lets NaN through, since
/// every comparison with NaN is false.
CLI::Validator finite_in(double lo, double hi, bool hi_open, const std::string& meaning) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        std::size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || used == 0) return fmt::format("'{}' is not a number", text);
        if (!std::isfinite(v) || v < lo || (hi_open ? v >= hi : v > hi))
          return fmt::format("{} must be {} in [{}, {}{}, got {}", meaning,
                             "a finite number", lo, hi, hi_open ? ")" : "]", text);
        return {};
      },
      fmt::format("in [{}, {}{}", lo, hi, hi_open ? ")" : "]"));
}

/// A report directory named on the command line: `-r ''` is a mistake, not "no report".
CLI::Validator non_empty_path(const std::string& option) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        return text.empty() ? fmt::format("{} '' names no directory; name one, or leave the "
                                          "option out (--no-report writes none)",
                                          option)
                            : std::string();
      },
      "DIR");
}

/// `--vtk=none|finest|all` and its older spelling `--no-vtk`, setting a command's two VTK
/// switches; `fallback` names the command's default in the help.
void add_vtk_policy(CLI::App* c, bool& vtk, bool& finest_only, const std::string& fallback) {
  c->add_option_function<std::string>(
       "--vtk",
       [&vtk, &finest_only](const std::string& v) {
         vtk = v != "none";
         finest_only = v == "finest";
       },
       fmt::format("VTK fields in the report: none, finest (each study's finest resolution) or "
                   "all (default: {})",
                   fallback))
      ->check(CLI::IsMember({"none", "finest", "all"}));
  c->add_flag("!--no-vtk", vtk, "leave VTK files out of the report (= --vtk=none)");
}

}  // namespace

int main(int argc, char** argv) {
  // A supervised child (apps/supervise.hpp) takes its channel out of the environment first.
  mfv::adopt_supervision();
  // Then, before any thread exists: an interrupted run removes its staging directory.
  mfv::install_staging_cleanup();
  // Under mpirun every rank runs the whole command (set-up and assembly are replicated; the
  // PETSc solves are distributed), so MPI starts first and rank 0 alone prints to stdout and
  // writes files; every rank reports its errors on stderr, naming itself.
  const bool mpi = mfv::petsc::launched_by_mpirun();
  if (mpi) {
    try {
      mfv::petsc::ensure_initialized();
    } catch (const std::exception& e) {
      std::cerr << "mfv: error: " << e.what() << "\n";
      return 1;
    }
  }
  const int rank = mfv::petsc::rank();
  std::ostream quiet(nullptr);
  std::ostream& out = rank == 0 ? std::cout : quiet;
  std::ostream& err_progress = rank == 0 ? std::cerr : quiet;
  const std::string who = mpi ? fmt::format("mfv (rank {})", rank) : std::string("mfv");
  CLI::App app{"mfv: verification suite for meshfree particle methods"};
  app.require_subcommand(1);

  // Provenance is read only when asked for: /proc/cpuinfo is no business of every run.
  app.set_version_flag("--version", [] { return mfv::version_text(mfv::provenance()); },
                       "version, commit, compiler, build type, libraries and machine");
  // Plugins (apps/plugin.hpp): loaded before the catalogue is built, so their kernels,
  // methods, problems and analyses are in every registry; a manifest's [suite] plugins too.
  std::vector<std::string> plugin_paths;
  app.add_option("--plugin", plugin_paths,
                 "load a plugin library (.so) built against this mfv before the command "
                 "(repeatable; examples/plugin/)")
      ->type_name("LIB");
  std::string list_what;
  auto* list = app.add_subcommand("list", "name the kernels, approximations, integration rules, "
                                          "methods, problems and analyses");
  list->add_option("what", list_what,
                   "a kind (kernels, methods, problems, analyses, ...) to list with every "
                   "parameter, or one name to show");

  mfv::RunOptions run;
  auto* cmd_run = app.add_subcommand("run", "run one case and print its errors");
  cmd_run->add_option("problem", run.problem, "problem name (see mfv list)")->required();
  cmd_run->add_option("--method,-m", run.method, "method name")->required();
  cmd_run->add_option("--params,-p", run.method_params, "method parameters key=value,...");
  cmd_run->add_option("--problem-params", run.problem_params, "problem parameters key=value,...");
  cmd_run->add_option("--nodes,-n", run.nodes,
                      "the resolution: particles on the line in 1D; in 2D what the problem "
                      "counts (`mfv list <problem>` says what: the cantilever's particles across "
                      "the depth, the rod's along its length)")
      ->required()
      ->check(CLI::Range(1, std::numeric_limits<int>::max()));
  cmd_run->add_option("--perturb", run.perturbation, "random particle offsets, fraction of dx")
      ->check(finite_in(0, 0.5, true, "--perturb"));
  cmd_run->add_option("--vtk", run.vtk, "also write the particles and fields to this .vtp file")
      ->check(non_empty_path("--vtk"));
  cmd_run->add_option("--analysis", run.analysis,
                      "the analysis to run (default: the problem's first; see mfv list)");

  // `study` is `compare` with one method; both share the options.
  mfv::CompareOptions cmp;
  std::string study_params;
  auto add_study_options = [&](CLI::App* c) {
    c->add_option("problem", cmp.problem, "problem name (see mfv list)")->required();
    c->add_option("--problem-params", cmp.problem_params, "problem parameters key=value,...");
    c->add_option("--analysis", cmp.analysis,
                  "the analysis to run (default: the problem's first; see mfv list)");
    auto* nodes = c->add_option("--nodes,-n", cmp.nodes,
                                "resolutions (each as --nodes of `mfv run`: particles on the "
                                "line, or what the 2D problem counts), repeatable or "
                                "comma-separated; run coarse to fine "
                                "in sorted order, each at most once (default: the problem's "
                                "standard refinement study)")
                      ->delimiter(',')
                      ->check(CLI::Range(2, std::numeric_limits<int>::max()));
    c->add_flag("--full", cmp.full, "the paper-size resolutions")->excludes(nodes);
    c->add_option("--perturb", cmp.perturbation, "random particle offsets, fraction of dx")
        ->check(finite_in(0, 0.5, true, "--perturb"));
    c->add_option("--report,-r", cmp.report, "write a report into this directory")
        ->check(non_empty_path("--report"));
    add_vtk_policy(c, cmp.vtk, cmp.vtk_finest_only, "all");
    c->add_flag("--force", cmp.force,
                "replace an earlier mfv report even if files were added to it (never anything "
                "that is not an mfv report)");
  };
  auto* cmd_study = app.add_subcommand("study", "refinement study of one method: errors, rates");
  add_study_options(cmd_study);
  std::string study_method;
  cmd_study->add_option("--method,-m", study_method, "method name")->required();
  cmd_study->add_option("--params,-p", study_params, "method parameters key=value,...");

  auto* cmd_compare = app.add_subcommand(
      "compare", "refinement studies of several methods on one problem, with a report");
  add_study_options(cmd_compare);
  cmd_compare
      ->add_option("--method,-m", cmp.methods,
                   "method, repeatable: name or name:key=value,... (e.g. rkpm:j=1)")
      ->required();

  mfv::AnalyseOptions ana;
  auto* cmd_analyse = app.add_subcommand(
      "analyse", "one case of a problem's analysis (e.g. dispersion, time-step, stretch-map, "
                 "crack-sweep) with any method: verdict, measured values, plots, CSV");
  cmd_analyse->add_option("problem", ana.problem,
                          "problem name, e.g. dispersion, time-step, enriched-bar, stretch-map")
      ->required();
  cmd_analyse->add_option("--method,-m", ana.method, "method name")->required();
  cmd_analyse->add_option("--params,-p", ana.method_params, "method parameters key=value,...");
  cmd_analyse->add_option("--problem-params", ana.problem_params, "problem parameters key=value,...");
  cmd_analyse->add_option("--analysis", ana.analysis,
                          "the analysis to run (default: the problem's first; see mfv list)");
  cmd_analyse->add_option("--nodes,-n", ana.nodes, "resolution (default: the problem's own)")
      ->check(CLI::Range(1, std::numeric_limits<int>::max()));
  auto* ana_report = cmd_analyse->add_option("--report,-r", ana.report,
                                             "write a report into this directory (default: "
                                             "print only)")
                         ->check(non_empty_path("--report"));
  cmd_analyse->add_flag("--no-report", ana.no_report, "print only (the default without -r)")
      ->excludes(ana_report);
  cmd_analyse->add_flag("--force", ana.force, "replace an earlier mfv report even if files were "
                                              "added to it");

  // `dispersion` is `analyse dispersion` with the analysis parameters as named options.
  mfv::AnalyseOptions dis;
  std::string lattice = "line", frame = "lagrangian", angles, mass = "lumped", stress;
  double sigma = 0;
  bool map = false;
  auto* cmd_dispersion = app.add_subcommand(
      "dispersion", "von Neumann dispersion of any method on a lattice: omega(kappa), verdict, plots");
  cmd_dispersion->add_option("--method,-m", dis.method, "method name")->required();
  cmd_dispersion->add_option("--params,-p", dis.method_params, "method parameters key=value,...");
  cmd_dispersion->add_option("--lattice", lattice, "line, rectangular or hexagonal");
  cmd_dispersion->add_option("--frame", frame, "lagrangian or eulerian kernel");
  cmd_dispersion->add_option("--sigma", sigma, "prestress sigma/E (1D) or sigma/mu (2D)")
      ->check(finite_in(-1e6, 1e6, false, "--sigma"));
  cmd_dispersion->add_option("--stress", stress, "2D prestress: biaxial or uniaxial");
  cmd_dispersion->add_option("--angles", angles, "2D wave directions in degrees, e.g. 0,30,45");
  cmd_dispersion->add_option("--points", dis.nodes,
                             "wave numbers per direction, from 0 to the zone boundary (at least "
                             "3; default: the analysis's own)")
      ->check(CLI::Range(3, 1000000));
  cmd_dispersion->add_option("--mass", mass, "lumped or consistent");
  cmd_dispersion->add_flag("--map", map, "also the (sigma, kappa) stable domain");
  auto* dis_report = cmd_dispersion->add_option("--report,-r", dis.report, "report directory")
                         ->check(non_empty_path("--report"));
  cmd_dispersion->add_flag("--no-report", dis.no_report, "print only")->excludes(dis_report);
  cmd_dispersion->add_flag("--force", dis.force, "replace an earlier mfv report even if files "
                                                 "were added to it");

  mfv::VerifyOptions ver;
  auto* cmd_verify = app.add_subcommand(
      "verify", "run a suite manifest; exit 1 if a case leaves its band or worsens the baseline");
  cmd_verify->add_option("manifest", ver.manifest, "suite manifest (TOML), e.g. suites/default.toml")
      ->required();
  cmd_verify->add_flag("--full", ver.full, "the paper-size resolutions (full_nodes)");
  cmd_verify->add_option("--case", ver.cases,
                         "run only this case: an id or a glob such as 'rod-pulse/*' (repeatable)");
  cmd_verify->add_flag("--list", ver.list, "print the cases that would run, and run none");
  auto* ver_history = cmd_verify->add_option(
      "--history", ver.history,
      "append this run to this SQLite history (default: <report dir>.history.sqlite beside "
      "the report; none with --no-report)")->check(non_empty_path("--history"));
  cmd_verify->add_flag("--no-history", ver.no_history, "append to no history")
      ->excludes(ver_history);
  cmd_verify->add_option("--junit", ver.junit,
                         "also write the verdicts as JUnit XML to this file (for CI test views)")
      ->check(non_empty_path("--junit"));
  auto* ver_update = cmd_verify->add_flag("--update-baseline", ver.update_baseline,
                                          "record this run's numbers as the baseline");
  cmd_verify->add_flag("--require-baseline", ver.require_baseline,
                       "fail a case that is not in the baseline (default: it is 'new', "
                       "recorded by --update-baseline)")
      ->excludes(ver_update);
  cmd_verify->add_flag("--timing-gate", ver.timing_gate,
                       "fail the run on a timing regression: a case more than 3x slower than "
                       "the baseline scaled by this run's machine factor (default: reported "
                       "only; also [suite] timing_gate = true)");
  auto* ver_report =
      cmd_verify->add_option("--report,-r", ver.report, "report directory (default runs/<suite>)")
          ->check(non_empty_path("--report"));
  cmd_verify->add_flag("--no-report", ver.no_report, "write no report")->excludes(ver_report);
  // The nightly writes no fields by default: every resolution's were 94 % of a report (210
  // of 223 MB), and the finest resolution's alone still 177 of 206 MB (the transient time
  // series); the report says how to get them.
  ver.vtk = false;
  add_vtk_policy(cmd_verify, ver.vtk, ver.vtk_finest_only, "none");
  cmd_verify->add_flag("--force", ver.force, "replace an earlier mfv report even if files were "
                                             "added to it");

  mfv::DiffCommandOptions diff;
  auto* cmd_diff = app.add_subcommand(
      "diff", "what changed between two verification runs: numbers beyond a tolerance, "
              "verdicts flipped, cases added or removed; exit 1 when something got worse");
  cmd_diff->add_option("before", diff.before, "the earlier run: a report directory, its "
                                              "results.json, or a run id of --history")
      ->required();
  cmd_diff->add_option("after", diff.after, "the later run")->required();
  cmd_diff->add_option("--history", diff.history, "the history file that run ids refer to");
  cmd_diff->add_option("--tolerance", diff.tolerance,
                       "relative change that counts (default 0.05)")
      ->check(finite_in(1e-15, 1e6, false, "--tolerance"));

  mfv::HistoryCommandOptions hist;
  hist.history = "runs/default.history.sqlite";
  auto* cmd_history = app.add_subcommand(
      "history", "a verification history: the runs; a case's quantities with their trend; one "
                 "quantity over the runs");
  cmd_history->add_option("subject", hist.subject,
                          "CASE or CASE/QUANTITY (e.g. 'rod-pulse/sph/L2 rate (least squares)'); "
                          "none: the runs");
  cmd_history->add_option("quantity", hist.quantity, "the quantity, when not in CASE/QUANTITY");
  cmd_history->add_option("--history", hist.history,
                          "the SQLite history (default runs/default.history.sqlite, the "
                          "nightly's)")
      ->check(non_empty_path("--history"));
  cmd_history->add_option("--last", hist.last, "how many runs (default 20)")
      ->check(CLI::Range(1, 1000000));

  std::vector<std::string> docs_files;
  bool docs_write = false;
  auto* cmd_docs = app.add_subcommand(
      "docs", "check (or rewrite) the blocks of README.md and docs/ generated from a manifest: "
              "the counts and the methods x problems table; exit 1 when one is out of date");
  cmd_docs->add_option("files", docs_files, "Markdown files holding '<!-- mfv:begin KIND "
                                            "MANIFEST -->' blocks")
      ->required();
  bool docs_check_flag = false;
  auto* docs_check = cmd_docs->add_flag("--check", docs_check_flag, "check only (the default)");
  cmd_docs->add_flag("--write", docs_write, "rewrite the blocks that are out of date")
      ->excludes(docs_check);

  std::string ctest_manifest, ctest_output, ctest_mfv;
  auto* cmd_ctest = app.add_subcommand(
      "manifest-ctest", "write a CTest script with one regression test per manifest case");
  cmd_ctest->add_option("manifest", ctest_manifest, "suite manifest (TOML)")->required();
  cmd_ctest->add_option("--output,-o", ctest_output, "the CTest script to write")
      ->required()
      ->check(non_empty_path("--output"));
  cmd_ctest->add_option("--mfv", ctest_mfv, "path of the mfv executable the tests run")
      ->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Every other parse error is bad input: exit 2 as documented (CLI11's own codes are
    // 101-120). An unexpected first word is an unknown subcommand: name it.
    std::vector<std::string> names;
    for (const auto* sub : app.get_subcommands([](CLI::App*) { return true; }))
      names.push_back(sub->get_name());
    if (argc > 1 && argv[1][0] != '-' &&
        std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      std::cerr << fmt::format("mfv: input error: unknown subcommand '{}'; {}subcommands: {} "
                               "(see mfv --help)\n",
                               mfv::shown_name(argv[1]), mfv::did_you_mean(argv[1], names),
                               fmt::join(names, ", "));
      return 2;
    }
    // CLI11's own message, in mfv's voice, with where to read the choices.
    std::string where = "mfv";
    for (const auto* sub : app.get_subcommands())
      where += " " + sub->get_name();
    std::string what = e.what();
    if (!what.empty() && what.back() == '\n') what.pop_back();
    std::cerr << fmt::format("mfv: input error: {}; see `{} --help`\n", what, where);
    return 2;
  }
  if (rank > 0) {
    // Rank 0 alone writes; the other ranks learn of its refusals at checks_done().
    run.vtk.clear();
    ana.no_report = dis.no_report = ver.no_report = true;
    ana.report.clear();
    dis.report.clear();
    ver.report.clear();
    ver.update_baseline = false;
    ver.junit.clear();
    ver.no_history = true;
    cmp.report.clear();
  }
  // What the command printed must reach its reader: a full disk or a closed pipe behind
  // stdout is a failure (exit 1), never a silent success.
  auto flushed = [&](int status) {
    out.flush();
    if (out.rdbuf() != nullptr && !out) {  // the other ranks' `out` is a null sink
      std::cerr << who << ": error: cannot write to standard output (disk full or the reader "
                          "is gone)\n";
      return status == 0 ? 1 : status;
    }
    return status;
  };
  // Under mpirun every rank ends through the same agreement (methods/core/petsc_session.hpp):
  // all exit with the largest code, and one message is printed — rank 0's, or a failing
  // rank's when rank 0 did not fail.
  int status = 0;
  std::string message;
  bool other_rank = false;
  try {
    std::vector<std::filesystem::path> plugin_files(plugin_paths.begin(), plugin_paths.end());
    if (*cmd_verify)
      for (const auto& p : mfv::load_manifest(ver.manifest).plugins) plugin_files.push_back(p);
    // Plugins' code runs in a supervised child: a plugin's _exit() cannot make the command
    // look finished.
    if (!mpi) {
      std::vector<std::string> names;
      for (const auto& f : plugin_files) names.push_back(f.filename().string());
      if (const auto code = mfv::supervise(argv, names)) return *code;
    }
    const mfv::Plugins plugins(plugin_files);
    const mfv::CommandExitGuard exit_guard(plugins);
    // External solvers (issue 30): `external:<name>` for each solvers/<name>.toml found
    // (dynamics/external_solver.hpp: $MFV_SOLVERS, the installed share/mfv/solvers or the
    // source tree's).
    mfv::Extensions extensions = plugins.extensions();
    extensions.methods.push_back(
        [specs = mfv::find_solver_specs()](mfv::MethodRegistry& r, const mfv::MethodParts&) {
          mfv::register_external_solvers(r, specs);
        });
    const mfv::Catalogue catalogue(extensions);
    mfv::report_registered();
    if (*list) {
      mfv::command_list(catalogue, list_what, out);
      status = flushed(0);
    } else if (*cmd_docs) {
      if (rank == 0) status = flushed(mfv::command_docs(catalogue, docs_files, docs_write, out));
    } else if (*cmd_ctest) {
      if (rank == 0) mfv::command_manifest_ctest(ctest_manifest, ctest_mfv, ctest_output);
    } else if (*cmd_run) {
      status = flushed(mfv::command_run(catalogue, run, out));
    } else if (*cmd_analyse) {
      status = flushed(mfv::command_analyse(catalogue, ana, out));
    } else if (*cmd_dispersion) {
      dis.problem = "dispersion";
      std::string colon_angles = angles;
      std::replace(colon_angles.begin(), colon_angles.end(), ',', ':');
      dis.problem_params = fmt::format("lattice={},frame={},sigma={},mass={}", lattice, frame,
                                       sigma, mass);
      if (!colon_angles.empty()) dis.problem_params += ",angles=" + colon_angles;
      if (!stress.empty()) dis.problem_params += ",stress=" + stress;
      if (map) dis.problem_params += ",map=sigma-kappa";
      status = flushed(mfv::command_analyse(catalogue, dis, out));
    } else if (*cmd_study) {
      cmp.methods = {study_params.empty() ? study_method : study_method + ":" + study_params};
      status = flushed(mfv::command_compare(catalogue, cmp, out, err_progress));
    } else if (*cmd_compare) {
      status = flushed(mfv::command_compare(catalogue, cmp, out, err_progress));
    } else if (*cmd_history) {
      status = flushed(mfv::command_history(hist, out));
    } else if (*cmd_diff) {
      status = flushed(mfv::command_diff(diff, out));
    } else if (*cmd_verify) {
      status = flushed(mfv::command_verify(catalogue, ver, out, err_progress));
    }
  } catch (const mfv::petsc::OtherRankFailed& e) {
    status = e.code;
    other_rank = true;
  } catch (const mfv::InputError& e) {
    status = 2;
    message = fmt::format("{}: input error: {}", who, e.what());
  } catch (const std::bad_alloc&) {
    status = 1;
    message = fmt::format("{}: error: out of memory; lower --nodes (or the problem parameter "
                          "that sets the size) or free memory",
                          who);
  } catch (const mfv::SingularError& e) {
    status = 3;
    message = fmt::format("{}: singular: {}", who, e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    // A path no file system can hold is the user's input; anything else is a failure.
    const auto c = e.code();
    const bool input = c == std::errc::filename_too_long || c == std::errc::invalid_argument;
    status = input ? 2 : 1;
    message = fmt::format("{}{}{}{}", who, input ? ": input error: " : ": error: ", e.what(),
                          input ? "; give a shorter or valid path" : "");
  } catch (const std::exception& e) {
    status = 1;
    message = fmt::format("{}: error: {}", who, e.what());
  } catch (...) {
    // mfv throws only std::exceptions: this came from a plugin's code (a factory, a kernel, a
    // method), which would otherwise end mfv through std::terminate.
    status = 1;
    message = fmt::format("{}: error: something that is not a std::exception was thrown (by a "
                          "plugin's code: mfv's own throws std::exception); fix the plugin",
                          who);
  }
  if (!mpi) {
    if (!message.empty()) std::cerr << message << "\n";
    mfv::report_finished(status);
    return status;
  }
  const mfv::petsc::Agreement agreed = mfv::petsc::finish(status);
  if (!message.empty() && !other_rank && (rank == 0 || agreed.rank0_code == 0))
    std::cerr << message << "\n";
  return agreed.code;
}
