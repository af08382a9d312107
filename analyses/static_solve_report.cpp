/// The report page of a 2D elasticity problem (001 §9.1): errors in L2 and energy on the
/// common rule and on each method's own quadrature, particles / stress points / cells, CPU
/// per phase, solver statistics, rates, plots, the paper's findings with our verdicts, VTK.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "analyses/report_section.hpp"
#include "analyses/case_vtk.hpp"
#include "analyses/order_of_accuracy.hpp"
#include "reports/vtk.hpp"

namespace mfv {

namespace fs = std::filesystem;

std::vector<StudySummary> summarize(const Registries& plugins,
                                    const std::vector<StudyResult>& studies) {
  std::vector<StudySummary> out;
  for (const auto& s : studies) {
    if (s.cases.empty()) continue;
    const CaseResult& f = s.cases.back();
    StudySummary m;
    m.method = f.spec.method;
    m.label = s.label;
    m.params = f.spec.method_params;
    m.finest_nodes = f.spec.nodes;
    m.finest_particles = f.particles;
    m.resolutions = static_cast<int>(s.cases.size());
    m.l2_rate = s.rates.rate("L2");
    m.energy_rate = s.rates.rate("energy");
    m.l2_rel_finest = f.errors.l2_rel;
    m.energy_rel_finest = f.errors.energy_rel;
    m.problem_params = f.spec.problem_params;
    // Resolved here from what the case was given, so that a study built by hand reads the
    // same defaults as one the runner ran.
    m.resolved = plugins.methods.resolve(f.spec.method, f.spec.method_params);
    m.problem_resolved = resolved_case_params(plugins, f.spec.problem, f.spec.problem_params,
                                              f.analysis.empty() ? f.spec.analysis : f.analysis);
    for (const auto& c : s.cases) {
      m.headlines.push_back(c.headline);
      m.h.push_back(c.h);
      m.l2_rel.push_back(c.errors.l2_rel);
      m.energy_rel.push_back(c.errors.energy_rel);
    }
    m.l2_trend = judge_convergence(m.l2_rel, m.h);
    m.energy_trend = judge_convergence(m.energy_rel, m.h);
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<FindingOutcome> check_findings(const Registries& plugins,
                                           const std::vector<Finding>& findings,
                                           const std::vector<StudyResult>& studies) {
  std::vector<FindingOutcome> out;
  if (findings.empty()) return out;
  const auto summaries = summarize(plugins, studies);
  std::vector<std::string> ran;
  for (const auto& s : summaries) {
    const std::string pp = s.problem_params.to_string();
    ran.push_back(fmt::format("{} at {} resolution{}{}", s.label, s.resolutions,
                              s.resolutions == 1 ? "" : "s", pp.empty() ? "" : " (" + pp + ")"));
  }
  for (const auto& f : findings) {
    FindingOutcome o;
    o.finding = &f;
    o.verdict = f.check(summaries);
    if (o.verdict.status == "not run")
      o.ran = ran.empty() ? "no study ran" : fmt::format("ran: {}", fmt::join(ran, "; "));
    out.push_back(std::move(o));
  }
  return out;
}

std::string findings_text(const Registries& plugins, const Problem& problem,
                          const std::vector<StudyResult>& studies) {
  const auto findings = problem.findings();
  const auto outcomes = check_findings(plugins, findings, studies);
  if (outcomes.empty()) return "";
  std::string text = fmt::format("Findings of the papers, checked on the studies above ({}):\n",
                                 outcomes.size());
  for (const auto& o : outcomes)
    text += fmt::format("  {:<16} {}: {}\n  {:<16} ours: {}{}\n", o.verdict.status,
                        o.finding->source, o.finding->claim, "", o.verdict.ours,
                        o.ran.empty() ? "" : " (" + o.ran + ")");
  return text;
}

/// Every static study's observed orders beside its method's formal ones (issue 46).
std::string order_block(const Registries& plugins, const std::vector<StudyResult>& studies) {
  MarkdownTable t({"study", "formal L2 / gradient", "observed L2 (finest pair, least squares)",
                   "L2 verdict", "observed gradient norm", "its verdict", "formal order's source"},
                  {'l', 'l', 'l', 'l', 'l', 'l', 'l'});
  int rows = 0;
  for (const auto& s : studies) {
    const CaseResult& f = s.cases.front();
    const double gradient = f.components > 1 ? f.errors.energy_rel : f.errors.h1_semi_rel;
    if (s.cases.size() < 2 || !std::isfinite(f.errors.l2_rel) || !std::isfinite(gradient)) continue;
    const OrderJudgement j = judge_order(plugins, s);
    if (j.norms.size() != 2) continue;
    auto obs = [](const NormOrder& n) {
      return fmt::format("{}{:.2f} ({:.2f})", n.norm == "L2" ? "" : n.norm + " ", n.observed,
                         n.least_squares);
    };
    t.add_row({s.label,
               j.formal.declared() ? fmt::format("{:g} / {:g}", j.formal.l2, j.formal.h1) : "–",
               obs(j.norms[0]), j.norms[0].verdict, obs(j.norms[1]), j.norms[1].verdict,
               j.formal.source});
    ++rows;
  }
  if (rows == 0) return "";
  return "**Order of accuracy** (observed on the finest pair and by least squares, against the "
         "order each method declares, the gradient's norm being the energy norm for elasticity "
         "and the seminorm of the gradient for scalar fields; at formal order within " +
         fmt::format("{:g}", kOrderTolerance) + "):\n\n" + t.str() + "\n";
}

std::string findings_block(const Registries& plugins, const Problem& problem,
                           const std::vector<StudyResult>& studies) {
  const auto findings = problem.findings();
  const std::string orders = order_block(plugins, studies);
  if (findings.empty()) return orders;
  MarkdownTable t({"source", "finding", "our criterion", "verdict", "ours"},
                  {'l', 'l', 'l', 'l', 'l'});
  for (const auto& o : check_findings(plugins, findings, studies))
    t.add_row({o.finding->source, o.finding->claim, o.finding->criterion,
               "**" + o.verdict.status + "**",
               o.ran.empty() ? o.verdict.ours : o.verdict.ours + " (" + o.ran + ")"});
  return orders + t.str() + "\n";
}

std::string write_elasticity_section(const Registries& catalogue, const ReportSection& section,
                                     const std::string& title, const fs::path& dir, bool vtk) {
  const auto problem = create_problem(catalogue, section.problem, section.problem_params);
  const std::string base = slug(title);
  PageParts page;
  page.lead = page_lead(*problem);
  page.methods = methods_list(section, [](const StudyResult& s) {
    return fmt::format("`{}`: {}", s.label, s.cases.front().method_description);
  });

  // Errors, sizes, solver and times.
  page.errors =
      "\"L2\" is the relative displacement error (001 eq "
      "71), \"energy\" the relative energy error (eq 73, with a square root, see below); "
      "\"common\" on 4×4 Gauss over a uniform grid with the trial field, \"own\" on the "
      "method's own quadrature with its own values and gradients. \"rcond\" is UMFPACK's "
      "reciprocal condition estimate, \"fill\" the nonzeros of L+U. CPU seconds per phase.\n\n";
  {
    std::vector<std::string> head = {"method", problem->resolution_name(), "particles",
                                     "stress pts", "cells", "quad pts", "h", "L2 common",
                                     "energy common", "L2 own", "energy own"};
    for (const auto& [k, v] : problem->headline_exact()) head.push_back(k);
    for (const char* c : {"unknowns", "fill", "rcond", "residual", "setup s", "assembly s",
                          "solve s"})
      head.push_back(c);
    std::vector<char> align(head.size(), 'r');
    align[0] = 'l';
    MarkdownTable t(head, align);
    for (const auto& s : section.studies)
      for (const auto& r : s.cases) {
        std::vector<std::string> row = {
            s.label, std::to_string(r.spec.nodes), std::to_string(r.particles),
            r.stress_points > 0 ? std::to_string(r.stress_points) : "–",
            r.quadrature_kind == "gauss-cells" ? std::to_string(r.cells) : "–",
            std::to_string(r.quadrature_points), fmt_sci(r.h, 2), fmt_sci(r.errors.l2_rel),
            fmt_sci(r.errors.energy_rel), fmt_sci(r.errors_paper.l2_rel),
            fmt_sci(r.errors_paper.energy_rel)};
        for (const auto& [k, v] : problem->headline_exact()) {
          const auto it = r.headline.find(k);
          row.push_back(it == r.headline.end() ? "–" : fmt::format("{:.6g}", it->second));
        }
        row.push_back(std::to_string(r.data<StaticSolveData>().solve.unknowns));
        row.push_back(r.data<StaticSolveData>().solve.fill > 0 ? std::to_string(r.data<StaticSolveData>().solve.fill) : "–");
        row.push_back(fmt_sci(r.data<StaticSolveData>().solve.rcond, 1));
        row.push_back(fmt_sci(r.data<StaticSolveData>().solve.residual, 1));
        row.push_back(fmt::format("{:.3f}", r.cpu.setup));
        row.push_back(fmt::format("{:.3f}", r.cpu.assembly));
        row.push_back(fmt::format("{:.3f}", r.cpu.solve));
        t.add_row(row);
      }
    page.errors += t.str() + "\n";
    std::vector<std::string> solvers;
    for (const auto& s : section.studies)
      for (const auto& r : s.cases)
        if (std::find(solvers.begin(), solvers.end(), r.data<StaticSolveData>().solve.solver) == solvers.end())
          solvers.push_back(r.data<StaticSolveData>().solve.solver);
    page.errors += fmt::format("Solvers used: {}.\n\n", fmt::join(solvers, "; "));
  }

  page.rates =
      "Least-squares slope of ln(error) against ln(h), and the slopes "
      "between successive resolutions. The trends judge the pairwise rates and the finest "
      "error (reports/convergence.hpp): converges only if the finest error is the smallest and "
      "the last pairwise and the fitted rate are at least 0.5.\n\n";
  {
    MarkdownTable t({"method", "L2 rate", "L2 pairwise", "energy rate", "energy pairwise",
                     "L2 rate (own)", "energy rate (own)", "L2 trend", "energy trend"},
                    {'l', 'r', 'r', 'r', 'r', 'r', 'r', 'l', 'l'});
    for (const auto& s : section.studies)
      t.add_row({s.label, fmt_rate(s.rates.rate("L2")), fmt_rates(s.rates.pairwise_of("L2")),
                 fmt_rate(s.rates.rate("energy")), fmt_rates(s.rates.pairwise_of("energy")),
                 fmt_rate(s.rates_paper.rate("L2")), fmt_rate(s.rates_paper.rate("energy")),
                 judge_study(s, [](const CaseResult& c) { return c.errors.l2_rel; }).label(),
                 judge_study(s, [](const CaseResult& c) { return c.errors.energy_rel; }).label()});
    page.rates += t.str() + "\n";
  }

  for (bool energy : {false, true}) {
    const auto spec =
        energy ? convergence_plot(
                     title + ": energy error", section.studies, "relative energy error",
                     [](const CaseResult& c) { return c.errors.energy_rel; },
                     [](const Rates& r) { return r.rate("energy"); })
               : convergence_plot(
                     title + ": L2 error", section.studies, "relative L2 displacement error",
                     [](const CaseResult& c) { return c.errors.l2_rel; },
                     [](const Rates& r) { return r.rate("L2"); });
    page.plots += plot_image(dir, fmt::format("plots/{}-{}.svg", base, energy ? "energy" : "l2"),
                             spec, fmt::format("{} error against h", energy ? "energy" : "L2"),
                             energy ? "energy" : "L2");
  }

  // Particles and quadrature points per resolution, one collection per study.
  if (vtk)
    page.vtk =
        "Particles (displacement, exact, error; stress, exact, error; "
        "volume) and the method's quadrature points (stress, exact, error; stress points "
        "and Gauss points). Open the `.pvd` in ParaView, warp by `displacement` and step "
        "through the resolutions: its time axis is the particle spacing h.\n\n" +
        write_vtk_collections(
            dir, base, section.studies,
            {{".vtp", write_particles_vtp}, {"-quadrature.vtp", write_quadrature_vtp}},
            section.vtk_finest_only);
  return section_page(catalogue, *problem, section, title, std::move(page), dir);
}

}  // namespace mfv
