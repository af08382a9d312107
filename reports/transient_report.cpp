/// The report section of transient problems: engine settings, errors at the checkpoints,
/// energy drift, time steps and CPU per case, rates, plots of errors and time histories,
/// history CSV files, published values and ParaView time series.
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "reports/study_report.hpp"
#include "reports/time_series.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

TimeHistory history_of(const TransientData& t) {
  TimeHistory h;
  h.columns = t.history_columns;
  for (const auto& row : t.history) h.add(row);
  return h;
}

std::string fmt_value(double v) {
  if (std::isnan(v)) return "–";
  return std::abs(v) < 1e-2 || std::abs(v) >= 1e5 ? fmt_sci(v, 3) : fmt::format("{:.4g}", v);
}

}  // namespace

std::string write_transient_section(const Catalogue& catalogue, const ReportSection& section,
                                    const std::string& title, const fs::path& dir, bool vtk) {
  const auto problem = catalogue.problems.create(section.problem, section.problem_params);
  const std::string base = slug(title);
  std::string md = fmt::format("# {}\n\n[← report](../index.md)\n\n{}\n\nResolutions count {}.\n\n",
                               title,
                               catalogue.problems.entry(section.problem).description,
                               problem->resolution_name());
  md += "**Methods and time integration.**\n\n";
  for (const auto& s : section.studies)
    md += fmt::format("- `{}`: {}; {}\n", s.label, s.cases.front().method_description,
                      s.cases.front().transient.dynamics);
  for (const auto& f : section.failures) md += fmt::format("- **could not run:** {}\n", f);
  md += "\n";

  md += findings_block(*problem, section.studies);

  // Errors, steps and CPU per case; the headline columns are whatever the problem measured.
  std::set<std::string> keys;
  for (const auto& s : section.studies)
    for (const auto& r : s.cases)
      for (const auto& [k, v] : r.headline) keys.insert(k);
  md += "## Errors, time steps and CPU\n\n\"dt/crit\" is the step over the critical step "
        "2/ω_max of the method's own stiffness and lumped mass (power iteration); \"energy "
        "drift\" is max |K + W_int − W_ext − K₀| over the run relative to the largest energy. "
        "CPU seconds: set-up (neighbours, shape functions), engine (force tables, critical "
        "step) and the time loop; particle-steps/s from the loop's CPU time.\n\n";
  {
    std::vector<std::string> head = {"method", problem->resolution_name(), "particles",
                                      "stress pts", "quad pts", "dt", "dt/crit", "steps"};
    for (const auto& k : keys) head.push_back(k);
    for (const char* c : {"setup s", "engine s", "loop s", "particle-steps/s"}) head.push_back(c);
    std::vector<char> align(head.size(), 'r');
    align[0] = 'l';
    MarkdownTable t(head, align);
    for (const auto& s : section.studies)
      for (const auto& r : s.cases) {
        const TransientData& d = r.transient;
        std::vector<std::string> row = {
            s.label, std::to_string(r.spec.nodes), std::to_string(r.particles),
            r.stress_points > 0 ? std::to_string(r.stress_points) : "–",
            std::to_string(r.quadrature_points), fmt_sci(d.dt, 3),
            d.dt_critical > 0 ? fmt::format("{:.3f}", d.dt / d.dt_critical) : "–",
            std::to_string(d.steps)};
        for (const auto& k : keys) {
          const auto it = r.headline.find(k);
          row.push_back(it == r.headline.end() ? "–" : fmt_value(it->second));
        }
        row.push_back(fmt::format("{:.3f}", r.cpu.setup));
        row.push_back(fmt::format("{:.3f}", r.cpu.assembly));
        row.push_back(fmt::format("{:.3f}", r.cpu.solve));
        row.push_back(r.cpu.solve > 0 ? fmt_sci(r.particles * double(d.steps) / r.cpu.solve, 2)
                                      : "–");
        t.add_row(row);
      }
    md += t.str() + "\n";
  }

  // Rates of the main error over the resolutions.
  bool several = false;
  for (const auto& s : section.studies) several = several || s.cases.size() > 1;
  fs::create_directories(dir / "plots");
  if (several) {
    md += "## Convergence of the main error\n\nLeast-squares slope of ln(error) against "
          "ln(h) and the slopes between successive resolutions (error: the problem's "
          "relative L2 error, for rod-pulse the velocity error at L/c).\n\n";
    MarkdownTable t({"method", "rate", "pairwise"}, {'l', 'r', 'r'});
    for (const auto& s : section.studies)
      t.add_row({s.label, fmt_rate(s.rates.l2), fmt_rates(s.rates.l2_pairwise)});
    md += t.str() + "\n";
    const std::string name = fmt::format("plots/{}-error.svg", base);
    const PlotSpec spec = convergence_plot(title + ": main error", section.studies, false);
    if (const auto why = write_svg_plot(dir / name, spec))
      md += fmt::format("_error plot skipped: {}_\n\n", *why);
    else
      md += fmt::format("![error against h]({}{})\n\n", kPageUp, name);
  }

  // Time histories of the finest case of each study: CSV and plots.
  md += "## Time histories\n\nEnergy balance and probes of the finest case of each study "
        "(CSV beside the plots).\n\n";
  fs::create_directories(dir / "histories");
  for (const auto& s : section.studies) {
    const CaseResult& r = s.cases.back();
    if (r.transient.history.empty()) continue;
    const TimeHistory h = history_of(r.transient);
    const std::string stem = fmt::format("{}-{}-n{}", base, slug(s.label), r.spec.nodes);
    write_history_csv(dir / "histories" / (stem + ".csv"), h);
    md += fmt::format("- `{}` ({} {}): [CSV]({}histories/{}.csv)", s.label, r.spec.nodes,
                      problem->resolution_name(), kPageUp, stem);
    const std::vector<std::string> energy = {"kinetic", "internal work", "external work",
                                             "energy balance"};
    std::vector<std::string> probes;
    for (std::size_t c = 5; c < h.columns.size(); ++c) probes.push_back(h.columns[c]);
    const std::string en = fmt::format("plots/{}-energy.svg", stem);
    if (!write_svg_plot(dir / en, history_plot(h, energy, s.label + ": energy", "energy")))
      md += fmt::format(" · [energy plot]({}{})", kPageUp, en);
    if (!probes.empty()) {
      const std::string pr = fmt::format("plots/{}-probes.svg", stem);
      if (!write_svg_plot(dir / pr, history_plot(h, probes, s.label + ": probes", "value")))
        md += fmt::format("\n\n  ![probes of {}]({}{})", s.label, kPageUp, pr);
    }
    md += "\n";
  }
  md += "\n";

  md += published_block(*problem, section.studies,
                        catalogue.problems.resolve(section.problem, Params{}));

  if (vtk) {
    md += "## VTK time series\n\nParticles at their current positions with velocity, "
          "displacement, Cauchy stress and the problem's exact values and errors; open a "
          "`.pvd` in ParaView and play it.\n\n";
    for (const auto& s : section.studies)
      for (const auto& r : s.cases) {
        if (r.transient.frames.empty()) continue;
        const std::string sub = fmt::format("vtk/{}/{}", base, slug(s.label));
        VtuSeriesWriter w(dir / sub, fmt::format("n{}", r.spec.nodes));
        for (const auto& f : r.transient.frames) {
          ParticleFrame pf;
          pf.time = f.time;
          pf.x = f.x;
          pf.point_data = f.data;
          w.write(pf);
        }
        w.finish();
        md += fmt::format("- `{}` n={}: [{}/n{}.pvd]({}{}/n{}.pvd)\n", s.label, r.spec.nodes, sub,
                          r.spec.nodes, kPageUp, sub, r.spec.nodes);
      }
    md += "\n";
  }
  return md;
}

}  // namespace mfv
