#include "methods/core/names.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace mfv {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Optimal string alignment: Levenshtein plus the swap of two neighbours as one edit ("fme"
  // is one slip from "fem", not two). Three rows: the swap looks two back.
  const std::size_t m = b.size();
  std::vector<std::size_t> before(m + 1), prev(m + 1), row(m + 1);
  for (std::size_t j = 0; j <= m; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] != b[j - 1] ? 1 : 0;
      row[j] = std::min({prev[j] + 1, row[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, prev);
    std::swap(prev, row);
  }
  return prev[m];
}

std::vector<std::string> near_matches(std::string_view name, const std::vector<std::string>& valid,
                                      std::size_t limit) {
  if (name.empty()) return {};
  // One edit for a short name ("efh" is not "sph"), two for the usual slips of a longer one
  // (a swapped pair, a missing dash), a third of the length for long ones, so
  // "rubber-rign/kbm-si-eulerian" still finds its case.
  const std::size_t reach =
      name.size() <= 4 ? 1 : std::max<std::size_t>(2, name.size() / 3);
  std::vector<std::pair<std::size_t, std::string>> near;
  for (const auto& v : valid) {
    const std::size_t d = edit_distance(name, v);
    const bool prefix = name.size() >= 3 && v.size() > name.size() && v.starts_with(name);
    if (d <= reach || prefix) near.emplace_back(prefix ? std::min(d, reach) : d, v);
  }
  std::stable_sort(near.begin(), near.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < near.size() && out.size() < limit; ++i) out.push_back(near[i].second);
  return out;
}

std::string shown_name(std::string_view name) {
  if (name.size() <= 120) return std::string(name);
  // Cut at a character boundary: a UTF-8 continuation byte is 10xxxxxx.
  std::size_t cut = 60;
  while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;
  return fmt::format("{}… ({} characters)", name.substr(0, cut), name.size());
}

std::string did_you_mean(std::string_view name, const std::vector<std::string>& valid) {
  const auto near = near_matches(name, valid, 2);
  if (near.empty()) return {};
  if (near.size() == 1) return fmt::format("did you mean '{}'? ", near[0]);
  return fmt::format("did you mean '{}' or '{}'? ", near[0], near[1]);
}

}  // namespace mfv
