/// The external-solver comparison page (analyses/external_comparison.hpp).
#include "analyses/external_comparison.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>

namespace mfv {

namespace {

/// The headlines that compare a run with its closed form or exact solution, matched by name
/// so that a new problem's of that kind shows too: a ratio to a reference ("period /
/// thin-plate period"), an error at a time ("velocity error at L/c", not its variants in
/// parentheses, which the problem page lists), and the energy balance.
bool compared_headline(const std::string& name) {
  if (name.find(" / ") != std::string::npos && name.find("critical") == std::string::npos)
    return true;
  return name.find("error at") != std::string::npos && name.find('(') == std::string::npos;
}

std::string number(double v) {
  if (!std::isfinite(v)) return "–";
  return std::abs(v) < 1e-3 && v != 0 ? fmt::format("{:.2e}", v) : fmt::format("{:.4g}", v);
}

}  // namespace

TextTable external_comparison(const std::vector<ReportSection>& sections) {
  TextTable t;
  t.head = {"problem", "n", "method", "against the closed form", "energy drift",
            "particle-steps/s", "CPU s"};
  t.align = {'l', 'r', 'l', 'l', 'r', 'r', 'r'};
  for (const ReportSection& section : sections) {
    std::set<int> external_n;
    for (const StudyResult& s : section.studies)
      for (const CaseResult& c : s.cases)
        if (const TransientData* d = c.find<TransientData>(); d && d->external)
          external_n.insert(c.spec.nodes);
    for (int n : external_n)
      for (const StudyResult& s : section.studies)
        for (const CaseResult& c : s.cases) {
          const TransientData* d = c.find<TransientData>();
          if (!d || c.spec.nodes != n) continue;
          std::string measured;
          for (const auto& [name, v] : c.headline)
            if (compared_headline(name))
              measured += fmt::format("{}{} {}", measured.empty() ? "" : "; ", name, number(v));
          if (d->instability) measured += (measured.empty() ? "" : "; ") + d->verdict();
          const auto drift = c.headline.find("energy drift");
          t.rows.push_back({section.problem, std::to_string(n), s.label,
                            measured.empty() ? "–" : measured,
                            drift == c.headline.end() ? "not measured" : number(drift->second),
                            fmt_particle_steps(c, *d), fmt::format("{:.3g}", c.cpu.total())});
        }
  }
  return t;
}

std::string external_comparison_page(const TextTable& table) {
  if (table.rows.empty()) return "";
  return "# External solvers beside mfv\n\n[Back to the report](index.md)\n\n"
         "Every problem an external solver ran (`-m external:<name>`, protocol "
         "`mfv-external-1`, docs/external-solvers.md in mfv's sources), with every method of "
         "the report at the resolutions the solver ran. *Against the closed form*: what the "
         "problem measures against its exact or analytic solution (the rod pulse's relative "
         "L2 velocity errors against d'Alembert's solution, the plate's period and amplitude "
         "over thin-plate theory's), measured on the solver's frames by the problem's own "
         "code. *Energy drift*: the largest |K + W_int − W_ext − E₀| over the run's energy "
         "scale; an external solver's is its own account (frames/energy.csv), \"not "
         "measured\" when it keeps none. *Particle-steps/s*: particles × the solver's steps "
         "over its CPU seconds. Timings compare only within one run on one machine.\n\n" +
         table.markdown();
}

}  // namespace mfv
