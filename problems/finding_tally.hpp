/// What a finding's check needs to read and judge studies: the last resolution's headline
/// values and a tally of the studies that pass a criterion (reproduced when all do, partly when
/// some do, not reproduced when none does), with the numbers behind each.
#pragma once
#include <cmath>
#include <initializer_list>
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

/// "sph (lagrangian): what": a number's name, unique per study and frame (the frame left out
/// for a problem that has none).
inline std::string number_name(const StudySummary& s, const std::string& what) {
  if (!s.problem_resolved.has("frame")) return fmt::format("{}: {}", s.label, what);
  return fmt::format("{} ({}): {}", s.label, s.problem_resolved.text("frame"), what);
}

/// A number read at the study's finest resolution only (a transient finding's): one level.
inline FindingNumber at_finest(const StudySummary& s, const std::string& what, double v) {
  return {number_name(s, what), {s.h.empty() ? NAN : s.h.back()}, {v}};
}

/// A number at every resolution of the study (`values` coarsest first, as s.h).
inline FindingNumber per_resolution(const StudySummary& s, const std::string& what,
                                    std::vector<double> values, double order = NAN) {
  std::vector<double> h = s.h;
  h.resize(values.size(), NAN);
  return {number_name(s, what), std::move(h), std::move(values), order};
}

/// The headline `key` at every resolution of the study (NaN where not measured).
inline FindingNumber headline_per_resolution(const StudySummary& s, const std::string& key) {
  std::vector<double> v;
  for (const auto& h : s.headlines) {
    const auto it = h.find(key);
    v.push_back(it == h.end() ? NAN : it->second);
  }
  return per_resolution(s, key, std::move(v));
}

/// The relative L2 error (common rule) at every resolution; formal order `order`.
inline FindingNumber l2_per_resolution(const StudySummary& s, double order = NAN) {
  return per_resolution(s, "relative L2 error", s.l2_rel, order);
}

/// The pairwise L2 rates, each at the geometric mean spacing of its pair (the sequence the
/// asymptotic order is the limit of, as the ledger's rate rows read it).
inline FindingNumber l2_rate_per_pair(const StudySummary& s) {
  FindingNumber n{number_name(s, "L2 rate (pairwise)"), {}, {}};
  const auto& pw = s.l2_trend.pairwise;
  for (std::size_t k = 0; k < pw.size() && k + 1 < s.h.size(); ++k) {
    n.h.push_back(std::sqrt(s.h[k] * s.h[k + 1]));
    n.values.push_back(pw[k]);
  }
  return n;
}

/// Studies that pass a criterion and that do not, with their numbers.
struct Tally {
  int yes = 0, no = 0;
  std::string text;
  std::vector<FindingNumber> numbers;  ///< what the parts were decided on
  /// One study judged on its headlines `keys`: each recorded at every resolution for the
  /// ledger's uncertainty (one level when the study has one resolution).
  void add_headlines(const StudySummary& s, bool ok, const std::string& text_numbers,
                     std::initializer_list<const char*> keys) {
    add(s, ok, text_numbers);
    for (const char* k : keys) numbers.push_back(headline_per_resolution(s, k));
  }
  /// One study judged on `decided_on` (at_finest, per_resolution, …).
  void add_numbers(const StudySummary& s, bool ok, const std::string& text_numbers,
                   std::vector<FindingNumber> decided_on) {
    add(s, ok, text_numbers);
    for (auto& n : decided_on) numbers.push_back(std::move(n));
  }
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
    return {no == 0 ? "reproduced" : yes == 0 ? "not reproduced" : "partly", text, numbers};
  }
};

}  // namespace mfv::finding
