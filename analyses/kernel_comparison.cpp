/// The kernel comparison page (analyses/kernel_comparison.hpp).
#include "analyses/kernel_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

namespace mfv {

namespace {

/// Method parameters that belong to the kernel choice: a comparison varies these and holds
/// the rest.
bool kernel_key(const std::string& key) {
  return key == "kernel" || key == "dmax" || key == "radius" || key.starts_with("kernel-");
}

/// The headlines a kernel comparison shows besides the error: what the catalogue's problems
/// measure that a kernel moves (a period, the stable prestress range, energy conservation,
/// an instability). Matched by name, so a new problem's headline of that kind shows too.
bool compared_headline(const std::string& name) {
  for (const char* part : {"period /", "limit (sigma bar)", "energy drift", "unstable at"})
    if (name.find(part) != std::string::npos) return true;
  return false;
}

std::string number(double v) {
  return std::isfinite(v) ? fmt::format("{:.4g}", v) : std::string("–");
}

}  // namespace

std::vector<KernelComparison> kernel_comparisons(const std::vector<ReportSection>& sections) {
  std::vector<KernelComparison> out;
  for (const ReportSection& section : sections) {
    // Group the section's studies by method and the parameters that are not the kernel's.
    std::map<std::string, std::vector<const StudyResult*>> groups;
    std::vector<std::string> order;
    for (const StudyResult& s : section.studies) {
      if (s.cases.empty() || !s.cases.front().method_params.has("kernel")) continue;
      const CaseSpec& spec = s.cases.front().spec;
      std::string key = spec.method;
      for (const auto& [k, v] : spec.method_params.values())
        if (!kernel_key(k)) key += fmt::format(" {}={}", k, format_value(v));
      if (spec.perturbation > 0) key += fmt::format(" perturbation={:g}", spec.perturbation);
      if (!groups.contains(key)) order.push_back(key);
      groups[key].push_back(&s);
    }
    for (const std::string& key : order) {
      const auto& studies = groups[key];
      std::set<std::string> kernels;
      for (const StudyResult* s : studies)
        kernels.insert(s->cases.front().method_params.text("kernel"));
      if (kernels.size() < 2) continue;
      // The finest resolution every study of the group reached: errors compare there.
      std::set<int> common;
      for (std::size_t i = 0; i < studies.size(); ++i) {
        std::set<int> mine;
        for (const CaseResult& c : studies[i]->cases) mine.insert(c.spec.nodes);
        if (i == 0) {
          common = mine;
        } else {
          std::set<int> both;
          std::set_intersection(common.begin(), common.end(), mine.begin(), mine.end(),
                                std::inserter(both, both.begin()));
          common = std::move(both);
        }
      }
      const int at = common.empty() ? 0 : *common.rbegin();
      auto case_at = [at](const StudyResult& s) -> const CaseResult& {
        for (const CaseResult& c : s.cases)
          if (c.spec.nodes == at) return c;
        return s.cases.back();
      };
      // The compared headlines every study of the group measured at that resolution.
      std::vector<std::string> headlines;
      for (const auto& [name, v] : case_at(*studies.front()).headline)
        if (compared_headline(name) &&
            std::all_of(studies.begin(), studies.end(), [&](const StudyResult* s) {
              return case_at(*s).headline.contains(name);
            }))
          headlines.push_back(name);
      // An error that is missing, not finite or exactly 0 is nothing measured (a dispersion
      // case has no error; no floating-point solution is exact), as in the rankings.
      const auto measured = [&](const StudyResult* s) {
        const double e = case_at(*s).errors.l2_rel;
        return std::isfinite(e) && e > 0;
      };
      const bool errors = std::any_of(studies.begin(), studies.end(), measured);

      KernelComparison k{section.problem, key, {}};
      k.table.head = {"kernel", "support (dmax)"};
      if (errors) {
        k.table.head.push_back(at > 0 ? fmt::format("error at {}", at) : "error at the finest");
        k.table.head.push_back("rate");
      }
      for (const auto& h : headlines) k.table.head.push_back(h);
      k.table.head.push_back("CPU s");
      std::vector<const StudyResult*> sorted = studies;
      // Best error first; without errors, in the run's order.
      if (errors)
        std::stable_sort(sorted.begin(), sorted.end(), [&](const StudyResult* a, const StudyResult* b) {
          if (measured(a) != measured(b)) return measured(a);
          return measured(a) && case_at(*a).errors.l2_rel < case_at(*b).errors.l2_rel;
        });
      for (const StudyResult* s : sorted) {
        const CaseResult& c = case_at(*s);
        const Params& mp = c.method_params;
        std::vector<std::string> row{
            mp.text("kernel"),
            mp.has("radius") && mp.number("radius") > 0
                ? fmt::format("radius {:g}", mp.number("radius"))
                : mp.has("dmax") ? fmt::format("{:g}", mp.number("dmax")) : std::string("–")};
        for (const auto& [k2, v] : mp.values())
          if (k2.starts_with("kernel-")) row[0] += fmt::format(" {}={}", k2.substr(7), format_value(v));
        if (errors) {
          row.push_back(number(c.errors.l2_rel));
          row.push_back(number(
              judge_study(*s, [](const CaseResult& r) { return r.errors.l2_rel; }).fitted_rate));
        }
        for (const auto& h : headlines) row.push_back(number(c.headline.at(h)));
        row.push_back(fmt::format("{:.3g}", c.cpu.total()));
        k.table.rows.push_back(std::move(row));
      }
      out.push_back(std::move(k));
    }
  }
  return out;
}

std::string kernel_comparison_page(const std::vector<KernelComparison>& all) {
  if (all.empty()) return "";
  std::string md =
      "# Kernels compared\n\n[Back to the report](index.md)\n\n"
      "Each table holds the studies of one problem and one method that differ only in the "
      "kernel W and its support (dmax: the support radius over the particle spacing, as "
      "resolved), best error first. Error: the problem's main relative L2 error at the finest "
      "resolution every study of the table reached; rate: least-squares slope over the "
      "study; then what the problem measures that a kernel moves (a period, the stable "
      "prestress range, the energy balance), at that resolution; CPU s of that case. The "
      "kernels are defined in `mfv list kernels`; a method divides the kernel by its integral "
      "`Kernel::integral(dim)` in the problem's dimension, so a kernel's `dim` constant does "
      "not change a result.\n\n";
  for (const KernelComparison& k : all)
    md += fmt::format("## {}: {}\n\n{}\n", k.problem, k.method, k.table.markdown());
  return md;
}

}  // namespace mfv
