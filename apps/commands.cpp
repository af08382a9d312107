#include "apps/commands.hpp"
#include "apps/command_support.hpp"
#include "dynamics/external_solver.hpp"
#include "methods/core/petsc_session.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <optional>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <functional>
#include <iostream>
#include <set>
#include <thread>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "methods/core/errors.hpp"
#include "methods/core/measurement_error.hpp"
#include "methods/core/names.hpp"
#include "reports/atomic.hpp"
#include "reports/convergence_table.hpp"
#include "reports/uncertainty.hpp"
#include "analyses/order_of_accuracy.hpp"
#include "reports/markdown.hpp"
#include "analyses/report_section.hpp"
#include "analyses/external_comparison.hpp"
#include "analyses/kernel_comparison.hpp"
#include "analyses/case_vtk.hpp"
#include "methods/core/clock.hpp"
#include "verify/baseline.hpp"
#include "verify/diff.hpp"
#include "verify/history.hpp"
#include "verify/junit.hpp"
#include "verify/ledger.hpp"
#include "verify/manifest.hpp"
#include "verify/provenance.hpp"
#include "verify/results_json.hpp"
#include "verify/runner.hpp"

namespace mfv {

namespace {

/// "methods", "analyses": a registry kind's plural.
std::string plural(const std::string& kind) {
  return kind.ends_with("is") ? kind.substr(0, kind.size() - 2) + "es" : kind + "s";
}

/// One entry: its description and every parameter with default, range and meaning.
template <class R>
void list_entry(const R& r, const std::string& name, std::ostream& out) {
  const auto& e = r.entry(name);
  out << fmt::format("  {:<20} {}\n", name, e.description);
  for (const auto& p : e.schema) {
    std::string range;
    if (!p.choices.empty()) range = fmt::format(" {{{}}}", fmt::join(p.choices, "|"));
    else if (p.min) range = fmt::format(" ({} {})", p.min_exclusive ? ">" : ">=", *p.min);
    out << fmt::format("      {}={}{}  {}\n", p.name,
                       p.optional ? std::string("(unset)") : format_value(p.default_value), range,
                       p.description);
  }
}

/// The first sentence of a description, cut at 90 characters: the overview's one line.
std::string first_line(const std::string& d) {
  std::string s = d.substr(0, d.find(": "));
  if (const auto at = s.find(". "); at != std::string::npos) s = s.substr(0, at);
  return s.size() > 90 ? s.substr(0, 87) + "..." : s;
}

}  // namespace

using namespace cli;


std::string convergence_table(const Registries& plugins, const StudyResult& s) {
  if (s.cases.empty()) return fmt::format("{}: no resolution ran\n", s.label);
  // The norms the study measures (its analysis says which): the L2 error, and the energy
  // norm for vector fields (2D elasticity is judged in it), the H1 seminorm for scalar ones
  // (their energy); an analysis that measures none shows its headline values instead.
  const CaseResult& first = s.cases.front();
  const MeasuredErrors measured =
      plugins.analyses.create(analysis_of(plugins, first))->measured_errors();
  if (measured.relative.empty()) {
    // An analysis has no error to converge: its measured values per resolution instead.
    std::vector<std::string> header{"nodes [1]"};
    for (const auto& [k, v] : first.headline) header.push_back(k);
    header.push_back("CPU [s]");
    MarkdownTable t(header, std::vector<char>(header.size(), 'r'));
    for (const auto& r : s.cases) {
      std::vector<std::string> row{std::to_string(r.spec.nodes)};
      for (const auto& [k, v] : first.headline) {
        const auto it = r.headline.find(k);
        row.push_back(it == r.headline.end() ? "–" : fmt::format("{:.6g}", it->second));
      }
      row.push_back(fmt::format("{:.3f}", r.cpu.total()));
      t.add_row(std::move(row));
    }
    return fmt::format("{} (analysis: measured values, no error norms)\n\n{}", s.label, t.str());
  }
  struct Norm {
    std::string name;
    double ErrorNorms::*rel;
    const std::vector<double>* pairwise;
    double fit;
  };
  std::vector<Norm> norms;
  if (measured.has("l2"))
    norms.push_back({"L2 rel", &ErrorNorms::l2_rel, &s.rates.pairwise_of(kRateL2),
                     s.rates.rate(kRateL2)});
  if (first.components > 1 && measured.has("energy"))
    norms.push_back({"energy rel", &ErrorNorms::energy_rel, &s.rates.pairwise_of(kRateEnergy),
                     s.rates.rate(kRateEnergy)});
  if (first.components == 1 && measured.has("h1_seminorm"))
    norms.push_back({"H1-semi rel", &ErrorNorms::h1_semi_rel, &s.rates.pairwise_of(kRateH1Semi),
                     s.rates.rate(kRateH1Semi)});
  std::vector<std::string> header{"nodes [1]", "h [length]"};
  std::vector<char> align{'r', 'r'};
  for (const auto& n : norms) {
    header.push_back(n.name + " [1]");
    header.push_back(n.name.substr(0, n.name.size() - 4) + " rate [1]");
    align.insert(align.end(), {'r', 'r'});
  }
  header.push_back("CPU [s]");
  align.push_back('r');
  MarkdownTable t(header, align);
  double cpu = 0;
  for (std::size_t i = 0; i < s.cases.size(); ++i) {
    const CaseResult& r = s.cases[i];
    std::vector<std::string> row{std::to_string(r.particles), fmt_sci(r.h)};
    for (const auto& n : norms) {
      row.push_back(fmt_sci(r.errors.*n.rel));
      row.push_back(i == 0 || i > n.pairwise->size() ? "–" : fmt_rate((*n.pairwise)[i - 1]));
    }
    row.push_back(fmt::format("{:.3f}", r.cpu.total()));
    cpu += r.cpu.total();
    t.add_row(std::move(row));
  }
  std::vector<std::string> fit{"least squares", ""};
  for (const auto& n : norms) {
    fit.push_back("");
    fit.push_back(fmt_rate(n.fit));
  }
  fit.push_back(fmt::format("{:.3f}", cpu));
  t.add_row(std::move(fit));
  // Beside the rates, the grid convergence index of each finest error (Roache; Celik et al.
  // 2008; reports/uncertainty.hpp): how sure the finest error itself is.
  std::string gci;
  if (s.cases.size() >= 2) {
    std::vector<std::string> parts;
    std::vector<double> h;
    for (const auto& r : s.cases) h.push_back(r.h);
    for (const auto& n : norms) {
      std::vector<double> e;
      for (const auto& r : s.cases) e.push_back(r.errors.*n.rel);
      parts.push_back(fmt::format("{} {}", n.name, grid_uncertainty(h, e).text()));
    }
    gci = fmt::format("\nfinest errors' uncertainty (GCI of the last three resolutions): {}\n",
                      fmt::join(parts, "; "));
    // The observed order beside the one the method declares (issue 46), for the static
    // problems whose errors are L2 and H1 (a transient run's are not).
    if (measured.has("l2") && (measured.has("h1_seminorm") || measured.has("energy")))
      gci += "order of accuracy: " + judge_order(plugins, s).text() + "\n";
  }
  return fmt::format("{}\n\n{}{}", s.label, t.str(), gci);
}


void command_list(const Catalogue& c, const std::string& what, std::ostream& out) {
  // Each registry under its plural and singular ("methods", "method"), in layer order.
  struct Kind {
    std::string plural;
    std::function<void(bool full)> list;
    std::function<bool(const std::string&)> has;
    std::function<void(const std::string&)> one;
  };
  std::vector<Kind> kinds;
  auto add = [&](const auto& r) {
    // Matched by the plural of the kind's first word ("integrations" for "integration scheme").
    kinds.push_back(Kind{
        plural(r.kind().substr(0, r.kind().find(' '))),
        [&r, &out, &c](bool full) {
          out << fmt::format("{}:\n", plural(r.kind()));
          for (const auto& name : r.keys()) {
            if (full) {
              list_entry(r, name, out);
            } else {
              out << fmt::format("  {:<22} {}\n", name, first_line(r.entry(name).description));
            }
          }
        },
        [&r](const std::string& n) { return r.contains(n); },
        [&r, &out](const std::string& n) {
          out << fmt::format("{} '{}':\n", r.kind(), n);
          list_entry(r, n, out);
        }});
  };
  add(c.kernels);
  add(c.approximations);
  add(c.integrations);
  add(c.methods);
  add(c.materials);
  add(c.problems);
  add(c.analyses);
  auto problem_analyses = [&](const std::string& name) {
    const auto problem = c.problems.create(name);
    out << fmt::format("      analyses (the first is the default): {}\n",
                       fmt::join(problem->analyses(), ", "));
    out << fmt::format("      -n / nodes counts: {}\n", problem->resolution_name());
  };
  if (what.empty()) {
    for (const auto& k : kinds) k.list(false);
    out << "\n`mfv list <kind>` (kernels, approximations, integrations, methods, materials, "
           "problems, analyses) lists each with its parameters; `mfv list <name>` shows one.\n";
    return;
  }
  for (const auto& k : kinds) {
    if (what != k.plural && what + "s" != k.plural && plural(what) != k.plural) continue;
    k.list(true);
    if (k.plural == "problems")
      for (const auto& name : c.problems.keys()) {
        out << fmt::format("  {}:\n", name);
        problem_analyses(name);
      }
    return;
  }
  bool found = false;
  for (const auto& k : kinds)
    if (k.has(what)) {
      k.one(what);
      if (k.plural == "problems") problem_analyses(what);
      found = true;  // a name may be a method and an approximation both
    }
  if (found) return;
  std::vector<std::string> valid;
  for (const auto& k : kinds) valid.push_back(k.plural);
  std::vector<std::string> names;
  for (const auto& r : {c.kernels.keys(), c.approximations.keys(), c.integrations.keys(),
                        c.methods.keys(), c.materials.keys(), c.problems.keys(),
                        c.analyses.keys()})
    names.insert(names.end(), r.begin(), r.end());
  valid.insert(valid.end(), names.begin(), names.end());
  throw InputError(fmt::format("mfv list: '{}' is neither a kind nor a name; {}kinds: {}; "
                               "`mfv list` names everything",
                               what, did_you_mean(what, valid),
                               "kernels, approximations, integrations, methods, materials, "
                               "problems, analyses"));
}

/// A case that ran but did not pass (exit 1: an unstable transient run, a failed check)
/// says why on stderr too, where scripts and CI read the reason; the full verdict is on
/// stdout with the rest of the case.
void say_why_it_failed(int status, const CaseResult& r) {
  if (status == 0) return;
  const auto* t = r.find<TransientData>();
  std::cerr << "mfv: " << r.spec.problem << " with " << r.spec.method << ": "
            << (t && t->instability ? t->verdict() : std::string("the case did not pass; see "
                                                                 "its verdict above"))
            << "\n";
}


int command_analyse(const Catalogue& c, const AnalyseOptions& o, std::ostream& out) {
  const double wall0 = wall_seconds(), cpu0 = cpu_seconds();
  if (o.no_report && !o.report.empty())
    throw InputError(fmt::format("--report {} and --no-report contradict each other; give one",
                                 o.report));
  if (o.nodes < 0)
    throw InputError(fmt::format("--nodes {} is negative; give a positive resolution, or leave "
                                 "it out for the problem's own",
                                 o.nodes));
  CaseSpec spec;
  spec.problem = o.problem;
  spec.method = o.method;
  spec.method_params = Params::parse(o.method_params);
  spec.problem_params = Params::parse(o.problem_params);
  spec.analysis = o.analysis;
  const auto problem = create_problem(c, spec.problem, spec.problem_params);
  spec.nodes = o.nodes > 0 ? o.nodes : problem->resolutions(Level::standard).front();
  // A report only with -r, as run, study and compare (issue 28: it used to write
  // ./reports/<problem>-<method> unasked).
  const std::filesystem::path dir(o.report);
  std::unique_ptr<StagedDirectory> staged;
  if (!o.no_report && !o.report.empty()) staged = stage_report(dir, o.force, spec.problem);
  petsc::checks_done();  // under mpirun: every rank's checks passed before any collective work
  StudyResult study;
  study.label = study_label(spec);
  study.cases.push_back(run_case(c, spec));
  const CaseResult& r = study.cases.back();
  out << fmt::format("analysis  {} of {} {}\n", r.analysis, spec.problem,
                     spec.problem_params.to_string());
  out << fmt::format("method    {} ({})\n", spec.method, r.method_description);
  const int status = c.analyses.create(r.analysis)->print_case(r, out);
  say_why_it_failed(status, r);
  std::set<std::string> printed;
  for (const auto& p : compare_published(*problem, {study},
                                          resolved_case_params(c, spec.problem, Params{},
                                                               r.analysis))) {
    if (p.study.empty() || std::isnan(p.ours)) continue;
    const std::string line =
        fmt::format("published {} {} = {:.6g} ({}); ours {:.6g}\n", p.published.source,
                    p.published.quantity, p.published.value, p.published.note, p.ours);
    if (printed.insert(line).second) out << line;
  }
  if (!staged) return status;
  const double wall = wall_seconds() - wall0, cpu = cpu_seconds() - cpu0;
  const std::string results = results_json(c, run_info(c, "analysis", wall, cpu), {study}, {});
  std::vector<ReportSection> sections;
  add_to_sections(c, sections, std::move(study));
  write_report(c, *staged,
               fmt::format("# mfv analysis: {} with {}\n\n{}\n\nMachine-readable: "
                           "[results.json](results.json).\n\n",
                           spec.problem, spec.method, machine_line(wall, cpu)),
               std::move(sections), false, false, {{"results.json", results}});
  out << fmt::format("report    {}\n", (dir / "index.md").string());
  return status;
}

int command_run(const Catalogue& c, const RunOptions& o, std::ostream& out) {
  if (o.nodes < 1)
    throw InputError(fmt::format("--nodes {} must be positive", o.nodes));
  if (!(o.perturbation >= 0 && o.perturbation < 0.5))
    throw InputError(fmt::format("--perturb {} must be in [0, 0.5) of the particle spacing",
                                 o.perturbation));
  if (!o.vtk.empty()) {
    check_output_file(o.vtk, "VTK file", is_vtk_xml);
    std::filesystem::path q = o.vtk;
    q.replace_extension(".quadrature.vtp");
    check_output_file(q, "VTK file", is_vtk_xml);
  }
  CaseSpec spec;
  spec.problem = o.problem;
  spec.method = o.method;
  spec.method_params = Params::parse(o.method_params);
  spec.problem_params = Params::parse(o.problem_params);
  spec.nodes = o.nodes;
  spec.perturbation = o.perturbation;
  spec.analysis = o.analysis;
  petsc::checks_done();
  CaseResult r;
  try {
    r = run_case(c, spec);
  } catch (const std::bad_alloc&) {
    throw std::runtime_error(fmt::format("out of memory running {} with {} at --nodes {}; lower "
                                         "--nodes or free memory",
                                         spec.problem, spec.method, spec.nodes));
  }
  out << fmt::format("problem   {} {}\n", spec.problem, spec.problem_params.to_string());
  out << fmt::format("method    {} ({})\n", spec.method, r.method_description);
  out << fmt::format("nodes     {}  (dx = {:.6g}, {} quadrature points)\n", r.particles, r.h,
                     r.quadrature_points);
  const int status = c.analyses.create(r.analysis)->print_case(r, out);
  say_why_it_failed(status, r);
  if (r.find<StaticSolveData>() == nullptr) {
    if (!o.vtk.empty())
      out << "vtk       only static solves write --vtk; transient runs write time series "
             "through reports: use `mfv study ... -r <dir>`\n";
    return status;
  }
  if (!o.vtk.empty()) {
    // Checked again when written (issue 45): a file of the user's created there while the
    // case ran is kept and the refusal named, as for verify's JUnit file and baseline.
    check_output_file(o.vtk, "VTK file", is_vtk_xml);
    if (r.components > 1) {
      std::filesystem::path quad = o.vtk;
      quad.replace_extension(".quadrature.vtp");
      check_output_file(quad, "VTK file", is_vtk_xml);
      write_particles_vtp(o.vtk, r);
      std::filesystem::path q = o.vtk;
      q.replace_extension(".quadrature.vtp");
      write_quadrature_vtp(q, r);
      out << fmt::format("vtk       {} and {}\n", o.vtk, q.string());
    } else {
      write_case_vtp(o.vtk, r);
      out << fmt::format("vtk       {}\n", o.vtk);
    }
  }
  return status;
}

std::pair<std::string, std::string> split_method_spec(const std::string& spec) {
  // An external solver's name has a colon of its own: external:<name>[:key=value,...].
  const std::string external = "external:";
  const auto colon =
      spec.find(':', spec.rfind(external, 0) == 0 ? external.size() : std::size_t{0});
  std::string name = spec.substr(0, colon);
  std::string params = colon == std::string::npos ? "" : spec.substr(colon + 1);
  if (name.empty())
    throw InputError(fmt::format("method '{}' has no name; write name or name:key=value,...",
                                 spec));
  return {name, params};
}

int command_compare(const Catalogue& c, const CompareOptions& o, std::ostream& out,
                    std::ostream& progress) {
  if (o.methods.empty())
    throw InputError("no method given; name one or more with --method (see mfv list)");
  CaseSpec base;
  base.problem = o.problem;
  base.problem_params = Params::parse(o.problem_params);
  base.perturbation = o.perturbation;
  base.analysis = o.analysis;
  const auto problem = create_problem(c, base.problem, base.problem_params);
  if (o.full && !o.nodes.empty())
    throw InputError("--full and --nodes both choose the resolutions; give one of them");
  if (!(o.perturbation >= 0 && o.perturbation < 0.5))
    throw InputError(fmt::format("--perturb {} must be in [0, 0.5) of the particle spacing",
                                 o.perturbation));
  std::vector<int> nodes = o.nodes;
  if (nodes.empty()) nodes = problem->resolutions(o.full ? Level::full : Level::standard);
  for (int n : nodes)
    if (n < 2) throw InputError(fmt::format("--nodes {} is too few; give at least 2", n));
  // Resolutions run coarse to fine whatever order they were given in (the rates and the
  // table read them so); a repeated one would give a rate of 0/0 and is refused.
  std::sort(nodes.begin(), nodes.end());
  if (const auto dup = std::adjacent_find(nodes.begin(), nodes.end()); dup != nodes.end())
    throw InputError(fmt::format("--nodes {} is given twice; give each resolution once", *dup));

  // Check every name and parameter before the first (possibly long) study runs.
  std::vector<CaseSpec> specs;
  for (const auto& m : o.methods) {
    CaseSpec s = base;
    auto [name, params] = split_method_spec(m);
    s.method = name;
    s.method_params = Params::parse(params);
    resolve_case(c, s);  // method keys the analysis declares (solver=petsc) are routed there
    specs.push_back(s);
  }

  std::unique_ptr<StagedDirectory> staged;
  if (!o.report.empty()) staged = stage_report(o.report, o.force, base.problem);
  petsc::checks_done();

  const double w0 = wall_seconds(), c0 = cpu_seconds();
  std::vector<ReportSection> sections;
  std::vector<StudyResult> done;
  std::vector<std::string> failures;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const std::string label = study_label(specs[k]);
    int running = 0;  // the resolution in progress, for an out-of-memory message
    const StudyProgress print =
        progress_printer(progress, fmt::format("[{}/{}] {}:", k + 1, specs.size(), label));
    try {
      StudyResult s = run_study(c, specs[k], nodes, [&](int i, int n, int m) {
        running = m;
        print(i, n, m);
      });
      done.push_back(s);
      add_to_sections(c, sections, std::move(s));
    } catch (const std::bad_alloc&) {
      throw std::runtime_error(fmt::format("out of memory in the study of {} on {} at {} nodes; "
                                           "lower --nodes or free memory",
                                           label, base.problem, running));
    } catch (const SingularError& e) {
      failures.push_back(fmt::format("{}: {}", label, e.what()));
      progress << fmt::format("[{}/{}] {}: could not run: {}\n", k + 1, specs.size(), label,
                              e.what());
    } catch (const MeasurementError& e) {
      // The run ended but its measurement could not be taken (a period without two
      // crossings): this study fails with the reason; the others still run.
      failures.push_back(fmt::format("{}: {}", label, e.what()));
      progress << fmt::format("[{}/{}] {}: could not measure: {}\n", k + 1, specs.size(), label,
                              e.what());
    } catch (const ExternalSolverError& e) {
      // An external solver that failed, timed out or wrote a broken frame: this study fails
      // with the reason; the others still run.
      failures.push_back(fmt::format("{}: {}", label, e.what()));
      progress << fmt::format("[{}/{}] {}: could not run: {}\n", k + 1, specs.size(), label,
                              e.what());
    } catch (const ExternalSolverMissing& e) {
      failures.push_back(fmt::format("{}: not run: {}", label, e.what()));
      progress << fmt::format("[{}/{}] {}: not run: {}\n", k + 1, specs.size(), label,
                              e.what());
    }
  }
  if (!done.empty()) print_rate_table(c, done, out);
  if (nodes.size() == 1)
    out << fmt::format("one resolution ({} nodes): a rate needs two; give -n twice or more, e.g. "
                       "-n {} -n {}\n",
                       nodes.front(), nodes.front(), 2 * nodes.front() - 1);
  for (const auto& f : failures) out << "could not run: " << f << "\n";
  // The problem's findings, checked on the studies just run (the same verdicts as the
  // report's page and results.json), with or without a report.
  if (!done.empty()) out << findings_text(c, *problem, done);

  if (staged) {
    if (sections.empty()) {
      ReportSection empty;
      empty.problem = base.problem;
      empty.problem_params = base.problem_params;
      sections.push_back(empty);
    }
    sections.front().failures = failures;
    const double wall = wall_seconds() - w0, cpu = cpu_seconds() - c0;
    const std::string results =
        results_json(c, run_info(c, specs.size() == 1 ? "study" : "compare", wall, cpu), done,
                     failures);
    std::string head = fmt::format("# mfv comparison: {}\n\n{}\n\nMachine-readable: "
                                   "[results.json](results.json).\n\n",
                                   o.problem, machine_line(wall, cpu));
    if (sections.front().studies.empty()) {
      head += "No study could run; see the failures below.\n\n";
      for (const auto& f : failures) head += fmt::format("- {}\n", f);
      write_file_atomic(staged->path() / "results.json", results);
      write_file_atomic(staged->path() / "index.md", head);
      staged->commit();
    } else {
      write_report(c, *staged, head, std::move(sections), o.vtk, o.vtk_finest_only,
                   {{"results.json", results}});
    }
    out << fmt::format("report: {}/index.md\n", o.report);
  }
  return failures.empty() ? 0 : 3;
}

}  // namespace mfv
