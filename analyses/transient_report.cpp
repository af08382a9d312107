/// The report section of transient problems: engine settings, errors at the checkpoints,
/// energy drift, time steps and CPU per case, rates, plots of errors and time histories,
/// history CSV files, published values and ParaView time series.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "reports/atomic.hpp"
#include "dynamics/external_solver.hpp"
#include "analyses/external_comparison.hpp"
#include "analyses/transient.hpp"
#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "analyses/report_section.hpp"
#include "reports/time_series.hpp"

namespace mfv {

namespace fs = std::filesystem;

// Declared in analyses/external_comparison.hpp (the external-solver page prints it too).
std::string fmt_particle_steps(const CaseResult& r, const TransientData& t) {
  // An external solver's steps are its own (t.steps counts the frames read back): known only
  // when it states them (index.csv's steps column), over its CPU time.
  if (t.external)
    return t.external->solver_steps >= 0 && r.cpu.solve > 0
               ? fmt_sci(r.particles * double(t.external->solver_steps) / r.cpu.solve, 2)
               : "–";
  return r.cpu.solve > 0 ? fmt_sci(r.particles * double(t.steps) / r.cpu.solve, 2) : "–";
}

namespace {

TimeHistory history_of(const TransientData& t) {
  TimeHistory h;
  h.columns = t.history_columns;
  for (const auto& row : t.history) h.add(row);
  return h;
}

std::string fmt_value(double v) {
  if (std::isnan(v)) return "–";
  if (v == 0) return "0";
  return std::abs(v) < 1e-2 || std::abs(v) >= 1e5 ? fmt_sci(v, 3) : fmt::format("{:.4g}", v);
}

/// A headline of one case as the table prints it: NaN is "not reached" in a run stopped as
/// unstable (its checkpoints came after the stop) and "–" otherwise; a peak of a run stopped
/// early is a lower bound, "≥ 100 (stopped early)".
std::string fmt_headline(const std::string& name, double v, const TransientData& t) {
  if (std::isnan(v)) return t.instability ? "not reached" : "–";
  if (t.stopped_early && name.rfind("peak", 0) == 0)
    return fmt::format("≥ {} (stopped early)", fmt_value(v));
  return fmt_value(v);
}

/// "unstable at step 9, t = 0.0018" or "ran to the end".
std::string fmt_run(const TransientData& t) {
  if (!t.instability) return t.stopped_early ? "stopped early" : "ran to the end";
  return fmt::format("unstable at step {}, t = {:.4g}", t.instability->step, t.instability->time);
}

/// Pairs of studies that differ only in the kernel frame (Lagrangian against Eulerian, any
/// update interval): the largest relative difference of their finite headline values at the
/// resolutions both ran, and the largest particle displacement over a spacing. Small strain
/// keeps the Eulerian tables, recomputed at positions that moved a tiny fraction of a spacing,
/// nearly the Lagrangian ones; the paragraph says so when the numbers agree to the digits
/// printed.
std::string frame_comparison(const std::vector<StudyResult>& studies) {
  auto frame_of = [](const CaseSpec& c) {
    return c.problem_params.has("frame") ? c.problem_params.text("frame") : "lagrangian";
  };
  auto without_frame = [](Params p) {
    Params out;
    for (const auto& [k, v] : p.values())
      if (k != "frame" && k != "update_every" && k != "frames") out.set(k, v);
    return out.to_string();
  };
  std::string md;
  for (const auto& a : studies)
    for (const auto& b : studies) {
      if (a.cases.empty() || b.cases.empty()) continue;
      const CaseSpec &sa = a.cases.front().spec, &sb = b.cases.front().spec;
      if (frame_of(sa) != "lagrangian" || frame_of(sb) != "eulerian") continue;
      // Two blow-ups differ by whatever the instability amplified: nothing to compare.
      auto unstable = [](const StudyResult& s) {
        return std::any_of(s.cases.begin(), s.cases.end(),
                           [](const CaseResult& r) { return r.data<TransientData>().instability.has_value(); });
      };
      if (unstable(a) || unstable(b)) continue;
      if (sa.method != sb.method || sa.method_params.to_string() != sb.method_params.to_string() ||
          without_frame(sa.problem_params) != without_frame(sb.problem_params))
        continue;
      double worst = 0, moved = 0;
      int compared = 0;
      bool same_digits = true;
      for (const auto& ra : a.cases)
        for (const auto& rb : b.cases) {
          if (ra.spec.nodes != rb.spec.nodes) continue;
          if (ra.h > 0) moved = std::max({moved, ra.data<TransientData>().max_displacement / ra.h,
                                          rb.data<TransientData>().max_displacement / rb.h});
          for (const auto& [k, va] : ra.headline) {
            const auto it = rb.headline.find(k);
            if (it == rb.headline.end() || !std::isfinite(va) || !std::isfinite(it->second) ||
                k.find("CPU") != std::string::npos)
              continue;
            const double scale = std::max(std::abs(va), std::abs(it->second));
            if (scale > 0) worst = std::max(worst, std::abs(va - it->second) / scale);
            same_digits = same_digits && fmt_value(va) == fmt_value(it->second);
            ++compared;
          }
        }
      if (compared == 0) continue;
      md += fmt::format(
          "- `{}` (Lagrangian kernel) and `{}` (Eulerian): largest relative difference of their "
          "{} common headline values {} (CPU excluded); the particles moved at most {} of a "
          "spacing.{}\n",
          a.label, b.label, compared, fmt_sci(worst, 2), fmt_sci(moved, 2),
          same_digits ? " They agree to every printed digit because the strain is small: the "
                        "Eulerian tables, recomputed at positions that moved that little, are "
                        "nearly the Lagrangian ones."
                      : "");
    }
  if (md.empty()) return md;
  return "### Lagrangian and Eulerian kernels\n\n" + md + "\n";
}

/// The problems' curves over space (TransientMeasures::Profile) of the finest case of each
/// study, one plot per title with every study's curves overlaid ("<study>: <curve>").
std::string profile_plots(const std::vector<StudyResult>& studies, const fs::path& dir,
                          const std::string& base) {
  std::vector<std::string> titles;
  std::map<std::string, PlotSpec> specs;
  for (const auto& s : studies) {
    if (s.cases.empty()) continue;
    for (const auto& p : s.cases.back().data<TransientData>().profiles) {
      auto [it, fresh] = specs.try_emplace(p.title);
      if (fresh) {
        titles.push_back(p.title);
        it->second.title = p.title;
        it->second.xlabel = p.xlabel;
        it->second.ylabel = p.ylabel;
        it->second.style = "lines";
        it->second.auto_logy = false;
      }
      PlotSpec& spec = it->second;
      for (std::size_t c = 0; c < p.labels.size() && c < p.x.size() && c < p.y.size(); ++c) {
        const SeriesRole role = p.role(c);
        if (role == SeriesRole::computed) {
          spec.series.push_back({s.label + ": " + p.labels[c], p.x[c], p.y[c]});
          continue;
        }
        // The problem's own curves (a closed form, a paper's data, a band) are the same for
        // every study: drawn once, under their own name.
        const bool seen = std::any_of(spec.series.begin(), spec.series.end(),
                                      [&](const Series& d) { return d.label == p.labels[c]; });
        if (role == SeriesRole::band) {
          // Two consecutive band curves on the same x: the lower and upper edge.
          const bool pair = c + 1 < p.labels.size() && c + 1 < p.x.size() &&
                            c + 1 < p.y.size() && p.role(c + 1) == SeriesRole::band &&
                            p.x[c + 1] == p.x[c] && p.y[c + 1].size() == p.y[c].size();
          if (!seen) {
            Series band{p.labels[c], p.x[c], p.y[c], SeriesRole::band, p.y[c]};
            if (pair)
              for (std::size_t i = 0; i < p.y[c].size(); ++i) {
                band.y[i] = std::min(p.y[c][i], p.y[c + 1][i]);
                band.y_hi[i] = std::max(p.y[c][i], p.y[c + 1][i]);
              }
            spec.series.push_back(std::move(band));
          }
          if (pair) ++c;
          continue;
        }
        if (!seen) spec.series.push_back({p.labels[c], p.x[c], p.y[c], role});
      }
    }
  }
  if (titles.empty()) return "";
  std::string md = "### Profiles\n\nCurves over space at the end of the finest case of each "
                   "study, overlaid across studies.\n\n";
  for (std::size_t i = 0; i < titles.size(); ++i)
    md += plot_image(dir, fmt::format("plots/{}-profile{}.svg", base, i + 1), specs[titles[i]],
                     titles[i], titles[i]);
  return md + "\n";
}

}  // namespace

std::string write_transient_section(const Registries& catalogue, const ReportSection& section,
                                    const std::string& title, const fs::path& dir, bool vtk) {
  const auto problem = create_problem(catalogue, section.problem, section.problem_params);
  const std::string base = slug(title);
  PageParts page;
  page.lead = page_lead(*problem);
  page.methods = methods_list(section, [](const StudyResult& s) {
    const TransientData& d = s.cases.back().data<TransientData>();
    return fmt::format("`{}`: {}; {}{}", s.label, s.cases.front().method_description,
                       s.cases.front().data<TransientData>().dynamics,
                       d.retabulations > 0
                           ? fmt::format(" ({} retabulations, {} neighbour searches{} at the "
                                         "finest resolution)",
                                         d.retabulations, d.neighbour_rebuilds,
                                         degenerate_note(d.degenerate_peak))
                           : "");
  });

  // The problem's chosen quantities side by side, one row per study (its finest case).
  std::string side_by_side;
  if (const std::vector<std::string> keys = problem->comparison_headlines(); !keys.empty()) {
    std::vector<std::string> head = {"study", "kernel", "particles", "integration points", "run"};
    for (const auto& k : keys) head.push_back(k);
    head.push_back("particle-steps/s");
    std::vector<char> align(head.size(), 'r');
    align[0] = align[1] = align[4] = 'l';
    MarkdownTable t(head, align);
    for (const auto& s : section.studies) {
      if (s.cases.empty()) continue;
      const CaseResult& r = s.cases.back();
      const TransientData& d = r.data<TransientData>();
      const CaseSpec& c = r.spec;
      std::vector<std::string> row = {
          s.label, c.problem_params.has("frame") ? c.problem_params.text("frame") : "lagrangian",
          std::to_string(r.particles), std::to_string(r.quadrature_points), fmt_run(d)};
      for (const auto& k : keys) {
        const auto it = r.headline.find(k);
        row.push_back(it == r.headline.end() ? "–" : fmt_headline(k, it->second, d));
      }
      row.push_back(fmt_particle_steps(r, d));
      t.add_row(row);
    }
    side_by_side = "**Side by side** (the finest case of each study; every measured value is "
                   "in the table below).\n\n" +
                   t.str() + "\n";
  }

  // Errors, steps and CPU per case; the headline columns are whatever the problem measured.
  std::set<std::string> keys;
  for (const auto& s : section.studies)
    for (const auto& r : s.cases)
      for (const auto& [k, v] : r.headline) keys.insert(k);
  page.errors =
      "\"dt/crit\" is the step over the critical step "
      "2/ω_max of the method's own stiffness and lumped mass (power iteration); \"energy "
      "drift\" is max |K + W_int − W_ext − K₀| over the run relative to the largest energy. "
      "CPU seconds: set-up (neighbours, shape functions), engine (force tables, critical "
      "step) and the time loop; particle-steps/s from the loop's CPU time.\n\n";
  // The problem's own table and charts over every study of the section.
  const std::vector<StudySummary> summaries = summarize(catalogue, section.studies);
  page.errors = problem->studies_table(summaries) + side_by_side + page.errors;
  std::string studies_plots;
  const std::vector<PlotSpec> charts = problem->studies_plots(summaries);
  for (std::size_t i = 0; i < charts.size(); ++i)
    studies_plots += plot_image(dir, fmt::format("plots/{}-studies{}.svg", base, i + 1), charts[i],
                                charts[i].title, charts[i].title);
  {
    std::vector<std::string> head = {"method", problem->resolution_name(), "particles",
                                      "stress pts", "quad pts", "dt", "dt/crit", "steps", "run"};
    for (const auto& k : keys) head.push_back(k);
    for (const char* c : {"setup s", "engine s", "loop s", "particle-steps/s"}) head.push_back(c);
    std::vector<char> align(head.size(), 'r');
    align[0] = 'l';
    MarkdownTable t(head, align);
    for (const auto& s : section.studies)
      for (const auto& r : s.cases) {
        const TransientData& d = r.data<TransientData>();
        std::vector<std::string> row = {
            s.label, std::to_string(r.spec.nodes), std::to_string(r.particles),
            r.stress_points > 0 ? std::to_string(r.stress_points) : "–",
            std::to_string(r.quadrature_points), fmt_sci(d.dt, 3),
            d.dt_critical > 0 ? fmt::format("{:.3f}", d.dt / d.dt_critical) : "–",
            std::to_string(d.steps), fmt_run(d)};
        for (const auto& k : keys) {
          const auto it = r.headline.find(k);
          row.push_back(it == r.headline.end() ? "–" : fmt_headline(k, it->second, d));
        }
        row.push_back(fmt::format("{:.3f}", r.cpu.setup));
        row.push_back(fmt::format("{:.3f}", r.cpu.assembly));
        row.push_back(fmt::format("{:.3f}", r.cpu.solve));
        row.push_back(fmt_particle_steps(r, d));
        t.add_row(row);
      }
    page.errors += t.str() + "\n";
  }
  // Why each unstable run was called so (the criteria of analyses/transient.hpp).
  {
    std::string why;
    for (const auto& s : section.studies)
      for (const auto& r : s.cases)
        if (r.data<TransientData>().instability)
          why += fmt::format("- `{}` n={}: {}\n", s.label, r.spec.nodes, r.data<TransientData>().verdict());
    if (!why.empty())
      page.errors += fmt::format(
          "**Unstable runs.** A run stops at once when its fields go non-finite or "
          "its kinetic energy exceeds {:g} × the energy put in (E₀ + max |W_ext|); "
          "a problem may add its own criterion. Checkpoints after the stop are "
          "\"not reached\"; a peak of a run stopped early is a lower bound (≥).\n\n{}\n",
          kEnergyBound, why);
  }
  // External solvers (docs/external-solvers.md): what ran, and what it said.
  {
    std::string ext;
    auto fenced = [](const std::string& text) {
      std::string t = text;
      while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
      return t.empty() ? std::string("(empty)\n") : fmt::format("```\n{}\n```\n", t);
    };
    for (const auto& s : section.studies)
      for (const auto& r : s.cases)
        if (const auto& e = r.data<TransientData>().external)
          ext += fmt::format("- `{}` n={}: `{}`, {:.2f} s wall, {:.2f} s CPU, {} frames "
                             "(protocol {})\n\n  stdout (tail):\n\n{}\n  stderr (tail):\n\n{}\n",
                             s.label, r.spec.nodes, e->command, e->wall_seconds, e->cpu_seconds,
                             e->frames, kExternalProtocol, fenced(e->stdout_tail),
                             fenced(e->stderr_tail));
    if (!ext.empty())
      page.errors += "**External solvers.** Their frames were replayed through this problem's "
                     "measurements (protocol: docs/external-solvers.md in mfv's sources); the "
                     "energy balance is the solver's own account (frames/energy.csv), not "
                     "measured when it keeps none. Beside mfv's methods: "
                     "[external.md](../external.md).\n\n" + ext + "\n";
  }
  page.errors += frame_comparison(section.studies);

  // Rates of the main error over the resolutions.
  bool several = false;
  for (const auto& s : section.studies) several = several || s.cases.size() > 1;
  if (several) {
    std::string main_error = "the problem's relative L2 error";
    for (const auto& st : section.studies)
      if (!st.cases.empty() && !st.cases.front().data<TransientData>().main_error.empty())
        main_error = st.cases.front().data<TransientData>().main_error;
    page.rates = fmt::format(
        "Of the main error: least-squares slope of ln(error) against "
        "ln(h) and the slopes between successive resolutions (error: {}; "
        "a resolution that did not reach its checkpoint leaves the rate "
        "undefined, \"–\").\n\n",
        main_error);
    MarkdownTable t({"method", "rate", "pairwise"}, {'l', 'r', 'r'});
    for (const auto& s : section.studies)
      t.add_row({s.label, fmt_rate(s.rates.rate("L2")), fmt_rates(s.rates.pairwise_of("L2"))});
    page.rates += t.str() + "\n";
    // The axis says what is plotted: the relative error the problem measures, with units.
    const PlotSpec spec = convergence_plot(
        title + ": main error", section.studies, main_error,
        [](const CaseResult& c) { return c.errors.l2_rel; },
        [](const Rates& r) { return r.rate("L2"); });
    page.plots =
        plot_image(dir, fmt::format("plots/{}-error.svg", base), spec, "error against h", "error");
  }

  // Time histories of the finest case of each study: CSV and plots.
  make_report_subdir(dir, "plots");
  page.plots += studies_plots;
  page.plots +=
      "### Time histories\n\nEnergy balance and probes of the finest case of each "
      "study (CSV beside the plots).\n\n";
  make_report_subdir(dir, "histories");
  for (const auto& s : section.studies) {
    const CaseResult& r = s.cases.back();
    if (r.data<TransientData>().history.empty()) continue;
    const TimeHistory h = history_of(r.data<TransientData>());
    const std::string stem = fmt::format("{}-{}-n{}", base, slug(s.label), r.spec.nodes);
    write_history_csv(dir / "histories" / (stem + ".csv"), h);
    page.plots += fmt::format("- `{}` ({} {}): [CSV]({}histories/{}.csv)", s.label, r.spec.nodes,
                              problem->resolution_name(), kPageUp, stem);
    const std::vector<std::string> energy = {"kinetic", "internal work", "external work",
                                             "energy balance"};
    std::vector<std::string> probes;
    for (std::size_t c = 5; c < h.columns.size(); ++c) probes.push_back(h.columns[c]);
    // Axes in the problem's own units (rod-pulse: ms and mm-kg-ms energies).
    const TransientData& d = r.data<TransientData>();
    const std::string time_axis = fmt::format("time t ({})", d.time_unit);
    const std::string en = fmt::format("plots/{}-energy.svg", stem);
    if (!write_svg_plot(dir / en, history_plot(h, energy, s.label + ": energy",
                                               fmt::format("energy ({})", d.unit_system),
                                               time_axis)))
      page.plots += fmt::format(" · [energy plot]({}{})", kPageUp, en);
    if (!probes.empty()) {
      const std::string pr = fmt::format("plots/{}-probes.svg", stem);
      const std::string img = plot_image(
          dir, pr,
          history_plot(h, probes, s.label + ": probes",
                       fmt::format("probe value ({}; as named)", d.unit_system), time_axis),
          fmt::format("probes of {}", s.label), "probes");
      page.plots += "\n\n  " + img.substr(0, img.find_last_not_of('\n') + 1);
    }
    page.plots += "\n";
  }
  page.plots += "\n";
  page.plots += profile_plots(section.studies, dir, base);

  if (vtk) {
    page.vtk =
        "A time series per case: particles at their current positions with velocity, "
        "displacement, Cauchy stress and the problem's exact values and errors; open a "
        "`.pvd` in ParaView and play it.\n\n";
    for (const auto& s : section.studies)
      for (const auto& r : s.cases) {
        if (r.data<TransientData>().frames.empty()) continue;
        if (section.vtk_finest_only && &r != &s.cases.back()) continue;
        const std::string sub = fmt::format("vtk/{}/{}", base, slug(s.label));
        VtuSeriesWriter w(make_report_subdir(dir, sub), fmt::format("n{}", r.spec.nodes));
        for (const auto& f : r.data<TransientData>().frames) {
          ParticleFrame pf;
          pf.time = f.time;
          pf.x = f.x;
          pf.point_data = f.data;
          w.write(pf);
        }
        w.finish();
        page.vtk += fmt::format("- `{}` n={}: [{}/n{}.pvd]({}{}/n{}.pvd)\n", s.label, r.spec.nodes,
                                sub, r.spec.nodes, kPageUp, sub, r.spec.nodes);
      }
    if (section.vtk_finest_only)
      page.vtk += "\nThe finest resolution of each study only (`--vtk=finest`, the nightly's "
                  "default); `--vtk=all` writes every resolution.\n";
    page.vtk += "\n";
  }
  return section_page(catalogue, *problem, section, title, std::move(page), dir);
}

}  // namespace mfv
