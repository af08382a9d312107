/// What a finding's check needs to read and judge studies: the last resolution's headline
/// values and a tally of the studies that pass a criterion (reproduced when all do, partly when
/// some do, not reproduced when none does), with the numbers behind each.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "problems/problem.hpp"

namespace mfv::finding {

/// The finest resolution's headline `key` of a study; NaN when it was not measured.
inline double last(const StudySummary& s, const std::string& key) {
  if (s.headlines.empty()) return NAN;
  const auto& h = s.headlines.back();
  const auto it = h.find(key);
  return it == h.end() ? NAN : it->second;
}

/// A number for a verdict's text, or "–" when it was not measured.
inline std::string fmt_or_dash(double v, const char* spec = "{:.3g}") {
  return std::isnan(v) ? "–" : fmt::format(fmt::runtime(spec), v);
}

/// The studies that measured something with kernel `frame` (and method `method`, any when
/// empty), in their order.
inline std::vector<const StudySummary*> studies_in_frame(const std::vector<StudySummary>& all,
                                                         const std::string& frame,
                                                         const std::string& method = "") {
  std::vector<const StudySummary*> out;
  for (const auto& s : all) {
    if (s.headlines.empty()) continue;
    if (!method.empty() && s.method != method) continue;
    if (s.problem_resolved.text("frame") != frame) continue;
    out.push_back(&s);
  }
  return out;
}

/// Studies that pass a criterion and that do not, with their numbers.
struct Tally {
  int yes = 0, no = 0;
  std::string text;
  /// One judged part, `what` its numbers.
  void add(bool ok, const std::string& what) {
    (ok ? yes : no) += 1;
    text += (text.empty() ? "" : "; ") + what;
  }
  /// One study, named by its label and kernel frame.
  void add(const StudySummary& s, bool ok, const std::string& numbers) {
    add(ok, fmt::format("{} ({}): {}", s.label, s.problem_resolved.text("frame"), numbers));
  }
  /// Every study passes (reproduced), none (not reproduced), some (partly); "not run" with
  /// `missing` when there is no study.
  Verdict verdict(const std::string& missing) const {
    if (yes + no == 0) return {"not run", missing};
    return {no == 0 ? "reproduced" : yes == 0 ? "not reproduced" : "partly", text};
  }
};

}  // namespace mfv::finding
