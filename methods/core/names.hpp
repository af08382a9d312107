/// "Did you mean": near matches of a mistyped name among the valid ones, for every message
/// that refuses a name or a key (registries, parameters, manifest keys, case ids, subcommands;
/// as Python's difflib.get_close_matches serves PySPH's Scheme.configure).
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace mfv {

/// Edit distance: insertions, deletions, substitutions and swaps of two neighbours, each 1
/// (optimal string alignment).
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The valid names within a typo's distance of `name` (1 edit up to 4 characters, else
/// max(2, |name|/3) edits; or `name`, 3 characters or more, a prefix of them), closest first,
/// at most `limit`; empty when none is near.
std::vector<std::string> near_matches(std::string_view name, const std::vector<std::string>& valid,
                                      std::size_t limit = 3);

/// A refused name as a message shows it: whole up to 120 characters, else its first 60 and
/// how long it was ("xxxx… (10000 characters)"), so that a 10 kB name does not make a 10 kB
/// message (issue 45, F16).
std::string shown_name(std::string_view name);

/// "did you mean 'x'? " or "did you mean 'x' or 'y'? " (with the trailing space), or "" when
/// no valid name is near: the prefix of a refusal's fix.
std::string did_you_mean(std::string_view name, const std::vector<std::string>& valid);

}  // namespace mfv
