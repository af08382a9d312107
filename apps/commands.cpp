#include "apps/commands.hpp"
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

/// How reports print the time.
constexpr const char* kReportTime = "%Y-%m-%d %H:%M:%S UTC";

unsigned cores() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : n;
}

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

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
  return fmt::format("{}\n\n{}", s.label, t.str());
}

namespace {

/// Per study a convergence table (as deal.II's ConvergenceTable prints): one row per
/// resolution with each error and its pairwise rate, then the least-squares rate.
void print_rate_table(const Registries& c, const std::vector<StudyResult>& studies,
                      std::ostream& out) {
  for (const auto& s : studies) out << convergence_table(c, s) << "\n";
  out << "h: particle spacing in the problem's length unit; errors relative to the exact "
         "solution's norm on the common rule; rate: slope of ln(error) against ln(h) between "
         "successive resolutions, least squares: over all (004 II eq 7.3); CPU: setup + "
         "assembly + solve.\n";
}

/// Report header lines shared by compare and verify.
std::string machine_line(double wall, double cpu) {
  return fmt::format("Run {}, {} cores, wall {}, CPU {}.", utc_now(kReportTime), cores(),
                     fmt_seconds(wall), fmt_seconds(cpu));
}

/// Where write_report puts the list of problem sections in a report's head.
constexpr const char* kProblemsToc = "<!-- mfv: problems toc -->";

/// GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces to '-'.
std::string heading_anchor(const std::string& heading) {
  std::string out;
  for (unsigned char ch : heading) {
    if (ch >= 0x80 || std::isalnum(ch) || ch == '-' || ch == '_')
      out += static_cast<char>(std::tolower(ch));
    else if (ch == ' ')
      out += '-';
  }
  return out;
}

/// Every study's convergence table as CSV and LaTeX (booktabs) under tables/<problem>/:
/// h, the particle count, the relative L2, H1-seminorm and (2D) energy errors on the common
/// rule with their pairwise and least-squares rates, and CPU seconds. Returns the index's
/// line about them ("" when no study has two resolutions).
std::string write_convergence_tables(const std::filesystem::path& dir,
                                     const std::vector<ReportSection>& sections) {
  int written = 0;
  for (const auto& section : sections)
    for (const auto& s : section.studies) {
      if (s.cases.size() < 2) continue;  // one resolution has no rate to tabulate
      ConvergenceTable t("h");
      const bool vector = s.cases.front().components > 1;
      for (const auto& c : s.cases) {
        t.add_row({{"h", c.h},
                   {"particles", static_cast<double>(c.particles)},
                   {"L2 relative", c.errors.l2_rel},
                   {"H1-seminorm relative", c.errors.h1_semi_rel}});
        if (vector) t.add_value("energy relative", c.errors.energy_rel);
        t.add_value("CPU s", c.cpu.total());
      }
      t.omit_from_rates("particles");
      t.omit_from_rates("CPU s");
      t.set_format("particles", [](double v) { return fmt::format("{:.0f}", v); });
      t.evaluate_all_rates();
      const std::filesystem::path sub =
          make_report_subdir(dir, std::filesystem::path("tables") / slug(section.problem)) /
          slug(s.label.empty() ? "study" : s.label);
      write_file_atomic(sub.string() + ".csv", t.csv());
      write_file_atomic(sub.string() + ".tex", t.tex());
      ++written;
    }
  return written == 0 ? ""
                      : fmt::format("Convergence tables of the {} studies with two or more "
                                    "resolutions, as CSV and LaTeX (`booktabs`): `tables/`.\n\n",
                                    written);
}

/// Writes index.md (the head, then each section's summary), the files beside it (name →
/// content, e.g. results.json) and the sections' own files into the staging directory (made,
/// checked and locked before the computation) and swaps it in for the target. A kProblemsToc marker in the head becomes a list of links to the
/// sections' first "## " headings.
void write_report(const Catalogue& c, StagedDirectory& staged, const std::string& head,
                  std::vector<ReportSection> sections, bool vtk, bool vtk_finest_only,
                  const std::vector<std::pair<std::string, std::string>>& files = {}) {
  std::string body, toc;
  for (auto& s : sections) {
    s.vtk_finest_only = vtk_finest_only;
    const std::string md = write_problem_section(c, s, staged.path(), vtk);
    const auto at = md.rfind("## ", 0) == 0 ? 0 : md.find("\n## ");
    if (at != std::string::npos) {
      const auto start = at == 0 ? 3 : at + 4;
      const std::string title = md.substr(start, md.find('\n', start) - start);
      toc += fmt::format("  - [{}](#{})\n", title, heading_anchor(title));
    }
    body += md;
  }
  std::string md = head;
  if (const auto marker = md.find(kProblemsToc); marker != std::string::npos)
    md.replace(marker, std::string(kProblemsToc).size(), toc);
  md += write_convergence_tables(staged.path(), sections);
  // The same problem and method under different kernels, side by side (issue 29).
  if (const auto comparisons = kernel_comparisons(sections); !comparisons.empty()) {
    write_file_atomic(staged.path() / "kernels.md", kernel_comparison_page(comparisons));
    md += fmt::format("**Kernels compared**: [kernels.md](kernels.md), {} table(s) of the same "
                      "problem and method under different kernels.\n\n",
                      comparisons.size());
  }
  // External solvers beside mfv's methods, across problems (issue 30).
  if (const TextTable ext = external_comparison(sections); !ext.rows.empty()) {
    write_file_atomic(staged.path() / "external.md", external_comparison_page(ext));
    md += fmt::format("**External solvers beside mfv**: [external.md](external.md), {} row(s): "
                      "each problem an external solver ran, every method at its resolutions.\n\n",
                      ext.rows.size());
  }
  md += body;
  for (const auto& [name, content] : files) write_file_atomic(staged.path() / name, content);
  write_file_atomic(staged.path() / "index.md", md);
  staged.commit();
}

/// The report's staging directory, made before the computation so that a target mfv may not
/// replace, an unwritable parent or a second writer fails at once (InputError, exit 2).
std::unique_ptr<StagedDirectory> stage_report(const std::filesystem::path& dir, bool force,
                                              const std::string& suite) {
  return std::make_unique<StagedDirectory>(dir, StagedDirectory::Options{force, suite});
}

bool written_by_mfv_verify(const std::string& head) {
  return head.rfind("# generated by `mfv verify", 0) == 0;
}
bool written_by_manifest_ctest(const std::string& head) {
  return head.rfind("# generated by mfv manifest-ctest", 0) == 0;
}
bool is_vtk_xml(const std::string& head) { return head.find("<VTKFile") != std::string::npos; }

RunInfo run_info(const Catalogue& c, const std::string& kind, double wall, double cpu) {
  return RunInfo{kind, utc_now(kReportTime), cores(), wall, cpu, c.plugins};
}

StudyProgress progress_printer(std::ostream& progress, const std::string& prefix) {
  return [&progress, prefix](int i, int n, int nodes) {
    progress << fmt::format("{} resolution {}/{}: {} nodes\n", prefix, i + 1, n, nodes)
             << std::flush;
  };
}

}  // namespace

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
    out << fmt::format("      analyses (the first is the default): {}\n",
                       fmt::join(c.problems.create(name)->analyses(), ", "));
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
    if (r.components > 1) {
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

int command_verify(const Catalogue& c, const VerifyOptions& o, std::ostream& out,
                   std::ostream& progress) {
  const Manifest manifest = load_manifest(o.manifest);
  std::vector<const ManifestCase*> selected;
  if (o.cases.empty()) {
    for (const auto& mc : manifest.cases)
      if (o.full || !mc.full_only) selected.push_back(&mc);
  } else {
    // Ids and globs, each case once, in manifest order. A full-only case named by its id
    // without --full is a mistake; one a pattern sweeps up is left out, and said so.
    std::set<const ManifestCase*> chosen;
    int full_only_skipped = 0;
    for (const auto& pattern : o.cases) {
      const auto matched = manifest.select(pattern);
      const bool by_id = matched.size() == 1 && matched.front()->id == pattern;
      for (const ManifestCase* mc : matched) {
        if (mc->full_only && !o.full) {
          if (by_id)
            throw InputError(fmt::format("{}:{}: case '{}' runs only with --full (full_only = "
                                         "true); add --full",
                                         manifest.path.string(), mc->line, mc->id));
          if (!chosen.count(mc)) ++full_only_skipped;
          continue;
        }
        chosen.insert(mc);
      }
    }
    for (const auto& mc : manifest.cases)
      if (chosen.count(&mc)) selected.push_back(&mc);
    if (full_only_skipped > 0)
      progress << fmt::format("{} full-only case(s) the pattern(s) matched are left out; add "
                              "--full to run them\n",
                              full_only_skipped);
    if (selected.empty())
      throw InputError(fmt::format("--case {} selects only full-only cases; add --full",
                                   fmt::join(o.cases, " --case ")));
  }
  if (o.list) {
    for (const auto* mc : selected)
      out << fmt::format("{:<48} {:<22} {}{}\n", mc->id, mc->problem, mc->method,
                         mc->full_only ? "  (--full only)" : "");
    out << fmt::format("{} case(s) of {}\n", selected.size(), manifest.path.string());
    return 0;
  }
  if (!o.junit.empty()) check_output_file(o.junit, "JUnit file", is_mfv_junit);

  // Names and parameters are checked up front: a typo fails in a second, not after an hour.
  for (const auto* mc : selected) {
    try {
      CaseSpec spec;
      spec.problem = mc->problem;
      spec.problem_params = mc->problem_params;
      spec.method = mc->method;
      spec.method_params = mc->method_params;
      spec.analysis = mc->analysis;
      resolve_case(c, spec);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}:{}: case '{}': {}", manifest.path.string(), mc->line,
                                   mc->id, e.what()));
    }
  }
  const Baseline baseline =
      manifest.baseline.empty() ? Baseline{} : load_baseline(manifest.baseline);
  if (!baseline.suite.empty() && baseline.suite != manifest.name)
    throw InputError(fmt::format("baseline {} records suite '{}', not this manifest's '{}'; point "
                                 "[suite] baseline at '{}''s own baseline, or record one with "
                                 "--update-baseline into a new file",
                                 manifest.baseline.string(), baseline.suite, manifest.name,
                                 manifest.name));
  if (o.update_baseline && !manifest.baseline.empty())
    check_output_file(manifest.baseline, "baseline", written_by_mfv_verify);
  const std::filesystem::path report_dir =
      o.report.empty() ? std::filesystem::path("runs") / manifest.name
                       : std::filesystem::path(o.report);
  std::unique_ptr<StagedDirectory> staged;
  if (!o.no_report) staged = stage_report(report_dir, o.force, manifest.name);
  // The history file is opened (created, migrated, checked) before the first case runs.
  std::optional<HistoryStore> history;
  if (!o.no_history) {
    std::filesystem::path file = o.history;
    if (file.empty() && staged) {
      // Beside the report, never inside it: "-r runs/x/" names the directory x too.
      const std::filesystem::path target =
          report_dir.has_filename() ? report_dir : report_dir.parent_path();
      file = target.parent_path() / (target.filename().string() + ".history.sqlite");
    }
    if (!file.empty()) history.emplace(file);
  }
  // The run this report replaces, if it was a verification run: the report leads with what
  // changed since it (an unreadable or foreign one is simply not compared).
  std::optional<nlohmann::json> previous;
  if (staged) {
    try {
      if (std::filesystem::exists(report_dir / "results.json"))
        previous = load_run_results(report_dir / "results.json");
    } catch (const InputError&) {
    }
  }
  // The ledger is checked before the first case runs too (its rows name cases and values).
  std::optional<Ledger> ledger;
  if (!manifest.ledger.empty()) ledger = load_ledger(manifest.ledger, manifest, c);
  petsc::checks_done();

  const double w0 = wall_seconds(), c0 = cpu_seconds();
  struct Outcome {
    const ManifestCase* mc;
    std::optional<StudyResult> study;
    std::string error;
    std::vector<BandViolation> bands;
    std::vector<Drift> drifts;
    std::vector<std::string> stability;  ///< blown up, or stable against expect = "unstable"
    double seconds = 0;                  ///< wall time of the case
  };
  std::vector<Outcome> outcomes;
  std::vector<ReportSection> sections;
  Baseline updated = baseline;
  updated.suite = manifest.name;
  // CPU seconds compare only on the machine (CPU model, hardware and OpenMP threads) that
  // recorded them; an update records this one.
  const Provenance here = provenance();
  const std::string machine = machine_note(here.cpu, here.cores, here.threads);
  const bool cpu_comparable = same_machine(baseline.machine, machine);
  if (o.update_baseline && !o.full) updated.machine = machine;
  const std::string manifest_file = manifest.path.filename().string();

  for (std::size_t k = 0; k < selected.size(); ++k) {
    const ManifestCase& mc = *selected[k];
    Outcome oc{&mc, std::nullopt, "", {}, {}, {}, 0};
    const double case_start = wall_seconds();
    CaseSpec spec;
    spec.problem = mc.problem;
    spec.problem_params = mc.problem_params;
    spec.analysis = mc.analysis;
    spec.method = mc.method;
    spec.method_params = mc.method_params;
    spec.perturbation = mc.perturbation;
    const auto nodes = resolutions(mc, o.full);
    try {
      StudyResult s = run_study(
          c, spec, nodes,
          progress_printer(progress, fmt::format("[{}/{}] {}:", k + 1, selected.size(), mc.id)));
      s.label = mc.id;
      oc.bands = check_bands(mc, s, manifest_file);
      oc.stability = check_stability(mc, s);
      BaselineCase current = baseline_from_study(s);
      if (mc.full_only) {
        // Runs only with --full: the baseline records the nightly, its bands guard it.
      } else if (o.update_baseline) {
        // A number the baseline held that this run did not measure (NaN) is a lost
        // measurement, never a new record: the case fails and keeps its old entry.
        // A headline the run measured as NaN is a value ("not unstable", "not reached"), not
        // a loss; a headline it no longer measures at all is one.
        std::vector<Drift> lost;
        if (const auto it = baseline.cases.find(mc.id); it != baseline.cases.end())
          for (const Drift& d : check_drift(mc.id, it->second, current, INFINITY, 0))
            if (d.lost)
              lost.push_back(d);
        for (Drift& d : lost)
          d.message = fmt::format("{}: {}{}: the baseline holds {:.6g}, this run measured "
                                  "nothing; its baseline entry is kept (fix the run, or remove "
                                  "the entry from {} by hand if the measurement went on purpose)",
                                  mc.id, d.metric, d.nodes > 0 ? fmt::format(" at {} nodes", d.nodes) : "",
                                  d.baseline, manifest.baseline.string());
        if (lost.empty()) {
          if (!o.full) updated.cases[mc.id] = current;
        } else {
          oc.drifts = std::move(lost);
        }
      } else if (!manifest.baseline.empty()) {
        const auto it = baseline.cases.find(mc.id);
        if (it == baseline.cases.end()) {
          oc.drifts.push_back(Drift{mc.id, "resolution", 0, 0, 0, 0, false, false,
                                    fmt::format("{}: not in the baseline {}; record it with "
                                                "`mfv verify {} --update-baseline`",
                                                mc.id, manifest.baseline.string(), o.manifest)});
        } else {
          BaselineCase base = it->second;
          if (o.full) {
            // --full runs other resolutions: compare those in both, not the rates.
            std::erase_if(current.resolutions, [&](const BaselineEntry& e) {
              return std::none_of(base.resolutions.begin(), base.resolutions.end(),
                                  [&](const BaselineEntry& b) { return b.nodes == e.nodes; });
            });
            std::erase_if(base.resolutions, [&](const BaselineEntry& e) {
              return std::none_of(current.resolutions.begin(), current.resolutions.end(),
                                  [&](const BaselineEntry& b) { return b.nodes == e.nodes; });
            });
            base.l2_rate = base.h1_rate = current.l2_rate = current.h1_rate = std::nan("");
          }
          if (o.full) base.cpu_seconds = current.cpu_seconds = std::nan("");
          oc.drifts = check_drift(mc.id, base, current,
                                  mc.drift_tolerance.value_or(manifest.drift_tolerance),
                                  manifest.drift_floor, cpu_comparable);
        }
      }
      oc.study = s;
      add_to_sections(c, sections, std::move(s));
    } catch (const std::bad_alloc&) {
      // The case fails with its size named; the other cases still run.
      oc.error = fmt::format("out of memory at resolutions {} (nodes); lower them in the manifest",
                             fmt::join(nodes, ", "));
      progress << fmt::format("[{}/{}] {}: could not run: {}\n", k + 1, selected.size(), mc.id,
                              oc.error);
    } catch (const SingularError& e) {
      oc.error = e.what();
      progress << fmt::format("[{}/{}] {}: could not run: {}\n", k + 1, selected.size(), mc.id,
                              e.what());
    } catch (const MeasurementError& e) {
      oc.error = e.what();
      progress << fmt::format("[{}/{}] {}: could not measure: {}\n", k + 1, selected.size(),
                              mc.id, e.what());
    } catch (const ExternalSolverError& e) {
      oc.error = e.what();
      progress << fmt::format("[{}/{}] {}: could not run: {}\n", k + 1, selected.size(), mc.id,
                              e.what());
    } catch (const ExternalSolverMissing& e) {
      // Not installed here: the case did not run, which a regression run must not pass.
      oc.error = fmt::format("not run: {}", e.what());
      progress << fmt::format("[{}/{}] {}: not run: {}\n", k + 1, selected.size(), mc.id,
                              e.what());
    }
    oc.seconds = wall_seconds() - case_start;
    outcomes.push_back(std::move(oc));
  }
  const double wall = wall_seconds() - w0, cpu = cpu_seconds() - c0;

  // Verdicts: a band violation, a case that could not run or a number worse than the
  // baseline fails; a better number only asks for --update-baseline.
  int failed = 0;
  // Rates by norm name: the energy norm exists only for vector (2D) problems; in 1D it is
  // the H1 seminorm.
  MarkdownTable verdicts({"case", "problem", "method", "nodes", "L2 rate", "H1-seminorm rate",
                          "energy rate", "bands", "baseline", "verdict"},
                         {'l', 'l', 'l', 'l', 'r', 'r', 'r', 'l', 'l', 'l'});
  // The report's copy, unpadded and without the problem and method the case id already names.
  std::string verdicts_md =
      "| case | nodes | L2 rate | H1-seminorm rate | energy rate | bands | baseline | verdict |\n"
      "|:--|:--|--:|--:|--:|:--|:--|:--|\n";
  std::vector<std::string> messages;
  std::vector<VerifyCaseJson> case_json;
  JUnitSuite junit;
  for (const auto& oc : outcomes) {
    const auto worse = std::count_if(oc.drifts.begin(), oc.drifts.end(),
                                     [](const Drift& d) { return d.worse; });
    const bool missing_baseline = std::any_of(oc.drifts.begin(), oc.drifts.end(), [](auto& d) {
      return d.metric == "resolution";
    });
    const bool ok = oc.error.empty() && oc.bands.empty() && oc.stability.empty() && worse == 0 &&
                    !missing_baseline;
    if (!ok) ++failed;
    std::vector<std::string> nodes;
    for (int n : resolutions(*oc.mc, o.full)) nodes.push_back(std::to_string(n));
    std::string base_state = manifest.baseline.empty() ? "none"
                             : oc.mc->full_only       ? "none (--full only)"
                             : o.update_baseline      ? (worse > 0 ? "kept (a measurement was lost)" : "updated")
                             : oc.drifts.empty()      ? "unchanged"
                                                      : fmt::format("{} drift(s)", oc.drifts.size());
    const bool vector_field = oc.study && !oc.study->cases.empty() &&
                              oc.study->cases.front().components > 1;
    // A run that blew up (or stayed stable against expect = "unstable") says so here too.
    const std::string bands_state =
        !oc.error.empty()       ? "not run"
        : !oc.stability.empty() ? (oc.bands.empty() ? "inside; stability wrong"
                                                    : fmt::format("{} violated; stability wrong",
                                                                  oc.bands.size()))
        : oc.bands.empty()      ? "inside"
                                : fmt::format("{} violated", oc.bands.size());
    verdicts.add_row(
        {oc.mc->id, oc.mc->problem, oc.mc->method, fmt::format("{}", fmt::join(nodes, ",")),
         oc.study ? fmt_rate(oc.study->rates.rate("L2")) : "–",
         oc.study ? fmt_rate(oc.study->rates.rate("H1-semi")) : "–",
         vector_field ? fmt_rate(oc.study->rates.rate("energy")) : "–", bands_state, base_state,
         ok ? "PASS" : "FAIL"});
    verdicts_md += fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {} |\n", oc.mc->id, fmt::join(nodes, ","),
        oc.study ? fmt_rate(oc.study->rates.rate("L2")) : "–",
        oc.study ? fmt_rate(oc.study->rates.rate("H1-semi")) : "–",
        vector_field ? fmt_rate(oc.study->rates.rate("energy")) : "–", bands_state, base_state,
        ok ? "PASS" : "**FAIL**");
    VerifyCaseJson cj{oc.mc->id, oc.mc->problem, oc.mc->method, resolutions(*oc.mc, o.full),
                      bands_state, base_state, ok ? "PASS" : "FAIL", {},
                      oc.study ? &*oc.study : nullptr, oc.error};
    if (!oc.error.empty()) messages.push_back(fmt::format("{}: could not run: {}", oc.mc->id,
                                                          oc.error));
    for (const auto& m : oc.stability) {
      messages.push_back(m);
      cj.messages.push_back(m);
    }
    for (const auto& b : oc.bands) {
      messages.push_back(b.message);
      cj.messages.push_back(b.message);
    }
    for (const auto& d : oc.drifts) {
      messages.push_back(d.message);
      cj.messages.push_back(d.message);
    }
    JUnitCase jc{"mfv." + oc.mc->problem, oc.mc->id, oc.seconds, {},
                 fmt::format("{} with {} at nodes {}: L2 rate {}, bands {}, baseline {}: {}",
                             oc.mc->problem, oc.mc->method, fmt::join(nodes, ","),
                             oc.study ? fmt_rate(oc.study->rates.rate("L2")) : "–", bands_state,
                             base_state, ok ? "PASS" : "FAIL")};
    if (!oc.error.empty())
      jc.problems.push_back({JUnitProblem::Kind::error, "could-not-run", oc.error, oc.error});
    for (const auto& m : oc.stability)
      jc.problems.push_back({JUnitProblem::Kind::failure, "stability", m, m});
    for (const auto& b : oc.bands)
      jc.problems.push_back({JUnitProblem::Kind::failure, "band", b.message,
                             fmt::format("{} = {:.6g}, band [{:.6g}, {:.6g}]", b.metric, b.value,
                                         b.band.low, b.band.high)});
    for (const auto& d : oc.drifts) {
      if (d.worse || d.metric == "resolution")
        jc.problems.push_back({JUnitProblem::Kind::failure, "baseline", d.message,
                               d.metric == "resolution"
                                   ? d.message
                                   : fmt::format("{}{}: baseline {:.6g}, now {:.6g} ({:+.1f} %)",
                                                 d.metric,
                                                 d.nodes > 0 ? fmt::format(" at {} nodes", d.nodes)
                                                             : "",
                                                 d.baseline, d.current,
                                                 100 * (d.current - d.baseline) /
                                                     std::max(std::abs(d.baseline), 1e-300))});
      else
        jc.system_out += "\n" + d.message;  // better than the baseline: a note, not a failure
    }
    junit.cases.push_back(std::move(jc));
    case_json.push_back(std::move(cj));
  }

  out << verdicts.str();
  for (const auto& m : messages) out << m << "\n";
  const std::string summary =
      failed == 0 ? fmt::format("PASS: all {} case(s) of suite '{}' inside their bands{}",
                                outcomes.size(), manifest.name,
                                manifest.baseline.empty() ? "" : " and the baseline")
                  : fmt::format("FAIL: {} of {} case(s) of suite '{}' failed (see above)",
                                failed, outcomes.size(), manifest.name);
  out << summary << "\n";

  // Reproduction, computed from the same run and shown apart from the regression verdict.
  std::vector<LedgerEntry> entries;
  if (ledger) {
    std::map<std::string, CaseOutcome> ran;
    for (const auto& oc : outcomes)
      ran[oc.mc->id] = CaseOutcome{oc.study ? &*oc.study : nullptr, oc.error};
    entries = evaluate_ledger(*ledger, c, manifest, ran);
    out << fmt::format("Ledger ({}): {}\n", ledger->path.string(), verdict_counts_line(entries));
  }
  const std::string results_text =
      verify_results_json(c, run_info(c, "verify", wall, cpu), manifest.name, o.manifest, o.full,
                          case_json, ledger ? &*ledger : nullptr, entries);

  // The history: this run appended, then the slow drifts over the last runs (each step
  // inside the tolerance, the whole window not) reported; they do not change the exit code.
  // Parsed once, for the history and the report's diff, and only when one of them reads it.
  const nlohmann::json results_doc =
      history || previous ? nlohmann::json::parse(results_text) : nlohmann::json();
  std::vector<HistoryDrift> creeping;
  if (history) {
    const long id = history->append(results_doc);
    creeping = history->drifts(id, kHistoryWindow,
                               manifest.drift_tolerance > 0 ? manifest.drift_tolerance : 0.05);
    out << fmt::format("history: run {} appended to {}{}\n", id, history->path().string(),
                       creeping.empty() ? ""
                                        : fmt::format("; {} quantity(ies) crept over the last {} "
                                                      "runs:",
                                                      creeping.size(), kHistoryWindow));
    for (const auto& d : creeping) out << "  " << d.message << "\n";
  }

  if (!o.junit.empty()) {
    // The regression verdicts are the test cases; provenance and the ledger's verdicts (a
    // paper not reproduced is not a failed test) are the suite's properties.
    for (const auto& d : creeping)
      for (auto& jc : junit.cases)
        if (jc.name == d.case_id) jc.system_out += "\nhistory: " + d.message;
    junit.name = manifest.name;
    junit.timestamp = utc_now("%Y-%m-%dT%H:%M:%S");
    junit.seconds = wall;
    const Provenance& prov = here;
    junit.hostname = prov.hostname;
    junit.properties = {
        {"manifest", o.manifest},
        {"full", o.full ? "true" : "false"},
        {"mfv.version", prov.version},
        {"mfv.commit", prov.commit + (prov.dirty ? " (with uncommitted changes)" : "")},
        {"mfv.build", prov.build_type + ", " + prov.compiler},
        {"machine", fmt::format("{} cores, {}", prov.cores, prov.cpu)},
        {"threads", fmt::format("{} (OMP_WAIT_POLICY {})", prov.threads,
                                prov.omp_wait_policy.empty() ? "unset" : prov.omp_wait_policy)},
        {"summary", summary.substr(0, summary.find(" (see above)"))},
    };
    if (ledger) {
      junit.properties.emplace_back("ledger", verdict_counts_line(entries));
      for (const auto& e : entries) {
        const LedgerRow& read = e.read ? *e.read : *e.row;
        junit.properties.emplace_back(
            "ledger:" + e.row->id,
            fmt::format("{}{}{}", e.verdict,
                        e.evidence.empty() || e.evidence == "–" ? "" : "; evidence " + e.evidence,
                        read.cases.empty()
                            ? std::string()
                            : fmt::format("; cases {}", fmt::join(read.cases, ", "))));
      }
    }
    write_file_atomic(o.junit, junit_xml(junit));
    out << fmt::format("JUnit: {}\n", o.junit);
  }

  if (o.update_baseline && !manifest.baseline.empty()) {
    if (o.full) {
      out << "baseline not updated: it records the default resolutions; run without --full\n";
    } else {
      // A baseline beside a manifest in the working directory has no parent to create.
      if (const auto parent = manifest.baseline.parent_path(); !parent.empty())
        std::filesystem::create_directories(parent);
      write_file_atomic(manifest.baseline, baseline_to_toml(updated));
      out << fmt::format("baseline written: {}\n", manifest.baseline.string());
    }
  }

  if (staged) {
    const std::filesystem::path& dir = report_dir;
    std::string head = fmt::format("# mfv verification report: {}\n\n", manifest.name);
    if (!manifest.description.empty()) head += manifest.description + "\n\n";
    // 1. Summary: reproduction and regression apart, so that "no regression" is never read
    // as "the papers are reproduced".
    MarkdownTable summary_table({"", ""}, {'l', 'l'});
    summary_table.add_row({"**reproduction** of the papers (ledger)",
                           ledger ? verdict_counts_line(entries)
                                  : "no ledger: the manifest names none ([suite] ledger)"});
    // On stdout the messages come before the summary; in the report they follow it.
    std::string report_summary = summary;
    if (const auto at = report_summary.find(" (see above)"); at != std::string::npos)
      report_summary.replace(at, 12, " (see [Regression](#regression))");
    summary_table.add_row({"**regression** against bands and baseline", report_summary});
    // What changed since the run this report replaces: the first thing a nightly reader needs.
    std::string changes_md;
    if (previous) {
      try {
        const RunDiff d = diff_runs(*previous, results_doc);
        summary_table.add_row(
            {"**changes** since the last run here",
             fmt::format("{} worse, {} better ([Changes](#changes-since-the-last-run))", d.worse(),
                         d.better())});
        changes_md = "## Changes since the last run\n\n" + diff_text(d, true) + "\n";
      } catch (const InputError& e) {
        changes_md = fmt::format("## Changes since the last run\n\nNot compared: {}\n\n", e.what());
      }
    } else {
      summary_table.add_row({"**changes** since the last run here",
                             "no earlier verification run at this report path"});
    }
    if (history) {
      std::string h = fmt::format(
          "\nHistory: `{}` (`mfv history CASE --history {}` prints a quantity over the runs). ",
          history->path().string(), history->path().string());
      if (creeping.empty()) {
        h += fmt::format("No quantity crept the wrong way by more than the drift tolerance over "
                         "the last {} runs.\n\n",
                         kHistoryWindow);
      } else {
        h += fmt::format("Crept the wrong way over the last {} runs, each step inside the "
                         "tolerance:\n\n",
                         kHistoryWindow);
        for (const auto& d : creeping) h += fmt::format("- {}\n", d.message);
        h += "\n";
      }
      if (changes_md.empty()) changes_md = "## Changes since the last run\n\n";
      changes_md += h;
    }
    summary_table.add_row({"machine", machine});
    if (!c.plugins.empty())
      summary_table.add_row({"plugins", fmt::format("`{}`", fmt::join(c.plugins, "`, `"))});
    summary_table.add_row({"time", fmt::format("wall {}, CPU {} (finished {})", fmt_seconds(wall),
                                               fmt_seconds(cpu), utc_now(kReportTime))});
    summary_table.add_row({"manifest", fmt::format("`{}`{}", o.manifest,
                                                   o.full ? " (`--full` resolutions)" : "")});
    head += "## Summary\n\n" + summary_table.str() +
            "\nRegression PASS means our numbers stayed inside the manifest's bands and the "
            "recorded baseline; it says nothing about the papers. Whether a paper's claim is "
            "reproduced is the ledger's verdict, computed from this run against the tolerance "
            "each row states.\n\n";
    head += changes_md;
    // 2. Contents.
    head += "## Contents\n\n";
    head += "- [Regression](#regression) (every case: [regression.md](regression.md))\n";
    if (ledger) head += "- [Reproduction ledger](#reproduction-ledger) (in full: [ledger.md](ledger.md))\n";
    head += fmt::format("- Problems\n{}\n", kProblemsToc);
    head += o.vtk ? (o.vtk_finest_only ? "VTK fields: each study's finest resolution "
                                         "(`--vtk=all` writes every resolution).\n\n"
                                       : "VTK fields: every resolution.\n\n")
                  : "VTK fields: none written (`mfv verify … --vtk=finest` writes each study's "
                    "finest resolution, `--vtk=all` every resolution, for ParaView).\n\n";
    head += "Machine-readable: [results.json](results.json) (every case, the regression "
            "verdicts and the ledger; schema in docs/results-schema.md)";
    if (ledger) head += ", [ledger.csv](ledger.csv), [ledger.json](ledger.json)";
    head += ".\n\n";
    const std::string legend =
        "Verdicts: **reproduced** (within the row's tolerance), **reproduced under a stated "
        "reading** (the row states the reading), **partly** (within three times the tolerance, "
        "or some of the row's values), **not reproduced** (the gap and the best reason), **not "
        "reached** (the run gave no finite value), **not run** (its case was not selected), "
        "**not yet built** (the problem or check does not exist yet). Ratio = ours / paper. "
        "Each row may try several readings of the paper's text (each quoted); the verdict is "
        "the closest reading's that is not a fitted constant, and names it. Evidence says how "
        "sure ours is: **independent** (a second route agrees), **converged** (refinement "
        "moves it less than the tolerance), **single run**.";
    // 3. The ledger: short rows here, every column (paper, ours, tolerance, reason, reading)
    // on ledger.md.
    std::vector<std::pair<std::string, std::string>> files;
    // After the regression (issue 28: a nightly reader wants what changed and what failed
    // first): the counts by paper and section here, every row one link away.
    std::string ledger_md;
    if (ledger) {
      ledger_md = fmt::format(
          "## Reproduction ledger\n\nOne row per claim of the papers (`{}`). {} Every row — "
          "the paper's and our values, the tolerance, the case that measures ours, the reason "
          "for each gap, every reading tried and its checks — is in [ledger.md](ledger.md), by "
          "paper; [ledger.csv](ledger.csv) has them for a spreadsheet.\n\n{}\n",
          ledger->path.filename().string(), legend, ledger_counts_markdown(entries));
      files.emplace_back(
          "ledger.md",
          fmt::format("# Reproduction ledger: {}\n\n[Back to the report](index.md)\n\n{}\n\n"
                      "**{}**\n\n{}\n",
                      manifest.name, legend, verdict_counts_line(entries),
                      ledger_markdown(entries)));
    }
    // 4. Regression: the status and what failed here, every case on regression.md.
    const std::string regression_note =
        "Rates are least-squares slopes on the common rule, by norm: L2, H1 seminorm, and the "
        "energy norm (2D problems only).";
    head += fmt::format("## Regression\n\n**{}** Every case with its rates, bands and baseline: "
                        "[regression.md](regression.md).\n\n",
                        summary);
    // What the baseline watches, and whether this run's CPU could be judged against it.
    if (!manifest.baseline.empty() && !o.update_baseline)
      head += fmt::format(
          "The baseline holds every case's errors, rates and headline values (relative drift "
          "tolerance {:g}, a headline move fails until the baseline is updated) and its CPU "
          "seconds, judged by a ratio: more than {:g}× (and {:g} s) slower fails. CPU {}.\n\n",
          manifest.drift_tolerance, kCpuRatio, kCpuFloorSeconds,
          cpu_comparable
              ? "compared: the baseline was recorded on this machine (" + machine + ")"
              : fmt::format("not compared: the baseline was recorded on {}, this run on {}",
                            baseline.machine.empty() ? std::string("an unnamed machine")
                                                     : baseline.machine,
                            machine));
    std::string messages_md;
    if (!messages.empty()) {
      messages_md += "Messages:\n\n";
      for (const auto& m : messages) messages_md += fmt::format("- {}\n", m);
      messages_md += "\n";
    }
    head += messages_md;
    head += ledger_md;
    files.emplace_back("regression.md",
                       fmt::format("# Regression verdict per case: {}\n\n[Back to the "
                                   "report](index.md)\n\n**{}**\n\n{}\n\n{}\n{}",
                                   manifest.name, summary, regression_note, verdicts_md,
                                   messages_md));
    for (auto& s : sections)
      for (const auto& oc : outcomes)
        if (!oc.error.empty() && oc.mc->problem == s.problem)
          s.failures.push_back(fmt::format("{}: {}", oc.mc->id, oc.error));
    files.emplace_back("results.json", results_text);
    if (ledger) {
      files.emplace_back("ledger.csv", ledger_csv(entries));
      files.emplace_back("ledger.json", ledger_json_text(*ledger, entries));
    }
    write_report(c, *staged, head, std::move(sections), o.vtk, o.vtk_finest_only, files);
    out << fmt::format("report: {}\n", (dir / "index.md").string());
  }
  return failed == 0 ? 0 : 1;
}

int command_diff(const DiffCommandOptions& o, std::ostream& out) {
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw InputError(fmt::format("--tolerance {} must be a positive finite relative change, "
                                 "e.g. 0.05",
                                 o.tolerance));
  DiffOptions d;
  d.tolerance = o.tolerance;
  // A path (a report directory or a results.json), or a run id of the history.
  std::optional<HistoryStore> history;
  auto record_of = [&](const std::string& what) {
    std::error_code ec;
    const bool digits = !what.empty() && std::all_of(what.begin(), what.end(), [](char ch) {
      return std::isdigit(static_cast<unsigned char>(ch));
    });
    if (!digits || std::filesystem::exists(what, ec)) return run_record(load_run_results(what));
    if (o.history.empty())
      throw InputError(fmt::format("mfv diff: '{}' is a run id; name the history it is in with "
                                   "--history FILE",
                                   what));
    if (!history) history.emplace(o.history);
    return history->record(std::stol(what));
  };
  const RunDiff diff = diff_runs(record_of(o.before), record_of(o.after), d);
  out << diff_text(diff);
  return diff.worse() > 0 ? 1 : 0;
}

int command_history(const HistoryCommandOptions& o, std::ostream& out) {
  if (o.last < 1)
    throw InputError(fmt::format("--last {} must be at least 1", o.last));
  if (!std::filesystem::exists(o.history))
    throw InputError(fmt::format("no history at '{}'; `mfv verify` writes one beside its report "
                                 "(<report>.history.sqlite) or where --history says",
                                 o.history));
  const HistoryStore h(o.history);
  if (o.subject.empty()) {
    MarkdownTable t({"run", "time", "suite", "commit", "status", "failed"},
                    {'r', 'l', 'l', 'l', 'l', 'r'});
    for (const auto& r : h.runs(o.last))
      t.add_row({std::to_string(r.id), r.generated_utc, r.suite + (r.full ? " (--full)" : ""),
                 r.commit.substr(0, 12) + (r.dirty ? "+changes" : ""), r.status,
                 fmt::format("{} of {}", r.failed, r.cases)});
    out << t.str();
    return 0;
  }
  // CASE/QUANTITY: the longest recorded case id that the subject starts with.
  const std::vector<std::string> cases = h.cases();
  std::string case_id, quantity = o.quantity;
  for (const auto& c : cases)
    if ((o.subject == c || o.subject.starts_with(c + "/")) && c.size() > case_id.size()) case_id = c;
  if (case_id.empty())
    throw InputError(fmt::format("history {} has no case '{}'; {}{} cases are recorded",
                                 o.history, o.subject, did_you_mean(o.subject, cases),
                                 cases.size()));
  if (o.subject.size() > case_id.size()) quantity = o.subject.substr(case_id.size() + 1);
  if (quantity.empty()) {
    // Every quantity of the case with its last value and trend.
    MarkdownTable t({"quantity", "last", "trend (oldest → newest)"}, {'l', 'r', 'l'});
    for (const auto& q : h.quantities(case_id)) {
      const auto pts = h.series(case_id, q, o.last);
      std::vector<double> v;
      for (const auto& p : pts) v.push_back(p.value);
      t.add_row({q, pts.empty() || !std::isfinite(pts.back().value)
                        ? "–"
                        : fmt::format("{:.4g}", pts.back().value),
                 sparkline(v)});
    }
    out << t.str();
    return 0;
  }
  const auto known = h.quantities(case_id);
  if (std::find(known.begin(), known.end(), quantity) == known.end())
    throw InputError(fmt::format("history {}: case '{}' has no quantity '{}'; {}`mfv history {}` "
                                 "lists its {}",
                                 o.history, case_id, quantity, did_you_mean(quantity, known),
                                 case_id, known.size()));
  MarkdownTable t({"run", "time", "commit", quantity}, {'r', 'l', 'l', 'r'});
  std::vector<double> v;
  for (const auto& p : h.series(case_id, quantity, o.last)) {
    t.add_row({std::to_string(p.run), p.generated_utc, p.commit.substr(0, 12),
               std::isfinite(p.value) ? fmt::format("{:.6g}", p.value) : "not measured"});
    v.push_back(p.value);
  }
  out << t.str() << fmt::format("trend: {}\n", sparkline(v));
  return 0;
}

namespace {
/// A CMake bracket argument that survives any text: as many '=' as it takes for the closing
/// bracket not to occur in it (a case id holding "]==]" would otherwise end the argument).
std::string bracket(const std::string& s) {
  std::string eq = "==";
  while (s.find("]" + eq + "]") != std::string::npos) eq += '=';
  return "[" + eq + "[" + s + "]" + eq + "]";
}
}  // namespace

void command_manifest_ctest(const std::string& manifest_path, const std::string& mfv_executable,
                            const std::string& output) {
  const Manifest m = load_manifest(manifest_path);
  check_output_file(output, "CTest script", written_by_manifest_ctest);
  const std::string manifest_abs = std::filesystem::absolute(manifest_path).string();
  std::string text = fmt::format("# generated by mfv manifest-ctest from {}\n", manifest_abs);
  for (const auto& c : m.cases) {
    if (c.full_only) continue;  // the nightly's tests; --full runs these
    std::vector<std::string> labels = {"regression", c.problem, c.method};
    for (const auto& l : c.labels) labels.push_back(l);
    text += fmt::format("add_test({} {} verify {} --case {} --no-report)\n", bracket(c.id),
                        bracket(mfv_executable), bracket(manifest_abs), bracket(c.id));
    // Idle OpenMP threads sleep: two tests share the 2 cores under ctest -j2, and spinning
    // threads would inflate the CPU seconds the baseline's ratio judges (scripts/main.sh).
    text += fmt::format("set_tests_properties({} PROPERTIES LABELS {} TIMEOUT 900 "
                        "ENVIRONMENT OMP_WAIT_POLICY=passive)\n",
                        bracket(c.id), bracket(fmt::format("{}", fmt::join(labels, ";"))));
  }
  write_file_atomic(output, text);
}

}  // namespace mfv
