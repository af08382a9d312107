#include "methods/core/params.hpp"

#include <algorithm>
#include <cmath>
#include <charconv>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/names.hpp"

namespace mfv {

ParamSpec ParamSpec::number(std::string name, double def, std::string description) {
  return ParamSpec{std::move(name), std::move(description), def};
}

ParamSpec ParamSpec::positive(std::string name, double def, std::string description) {
  ParamSpec s{std::move(name), std::move(description), def};
  s.min = 0.0;
  s.min_exclusive = true;
  return s;
}

ParamSpec ParamSpec::count(std::string name, int def, int min, std::string description) {
  ParamSpec s{std::move(name), std::move(description), static_cast<double>(def)};
  s.min = min;
  s.integer = true;
  return s;
}

ParamSpec ParamSpec::choice(std::string name, std::string def, std::vector<std::string> choices,
                            std::string description) {
  ParamSpec s{std::move(name), std::move(description), std::move(def)};
  s.choices = std::move(choices);
  return s;
}

ParamSpec ParamSpec::numbers(std::string name, std::vector<double> def, std::string description) {
  if (def.empty())
    throw std::logic_error(fmt::format("list parameter '{}' declared with an empty default", name));
  return ParamSpec{std::move(name), std::move(description), std::move(def)};
}

namespace {

/// A nonzero number is kept within [kSmallest, kLargest] in magnitude: the quantities mfv
/// forms from a parameter (energies are squares of velocities and loads, stiffnesses products
/// of moduli and lengths) would otherwise leave the range of a double, and a denormal or
/// overflowing intermediate reads as an error or an instability of the method (issue 26: a load
/// F0 = 1e-300 was reported "unstable" by round-off). The problems are linear in their loads,
/// so a user rescales them.
constexpr double kSmallest = 1e-100, kLargest = 1e100;

template <class Where>
void check_magnitude(double x, Where where) {
  if (x != 0 && (std::abs(x) < kSmallest || std::abs(x) > kLargest))
    throw InputError(fmt::format("{} is {:g}: a nonzero value must lie between {:g} and {:g} in "
                                 "magnitude (its squares and products would leave the range of a "
                                 "double); rescale it (a load or velocity scales the linear "
                                 "response with it)",
                                 where(), x, kSmallest, kLargest));
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

std::optional<double> to_number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  double v = 0;
  const char* first = s.data();
  if (*first == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, s.data() + s.size(), v);
  if (ec != std::errc{} || ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string join_names(const ParamSchema& schema) {
  std::string out;
  for (const auto& s : schema) out += (out.empty() ? "" : ", ") + s.name;
  return out.empty() ? "(none: this plugin takes no parameters)" : out;
}

std::vector<std::string> spec_names(const ParamSchema& schema) {
  std::vector<std::string> out;
  for (const auto& s : schema) out.push_back(s.name);
  return out;
}

/// The spec `key` names, by its name or a deprecated alias; null when none does.
const ParamSpec* find_spec(const ParamSchema& schema, const std::string& key) {
  for (const auto& s : schema)
    if (s.name == key || std::find(s.aliases.begin(), s.aliases.end(), key) != s.aliases.end())
      return &s;
  return nullptr;
}

/// What `v` is, for messages.
std::string kind_of(const ParamValue& v) {
  if (std::holds_alternative<double>(v)) return "a number";
  if (std::holds_alternative<std::string>(v)) return "text";
  return "a list";
}

constexpr const char* kListFix = "give numbers separated by ':' (or ',' inside a quoted manifest "
                                 "string), e.g. {}=0:30:45";

/// A list parameter's value as numbers: one number, a list, or text "0:45" / "0,45", each
/// element a finite number within the spec's bounds.
std::vector<double> list_of(const ParamSpec& spec, const ParamValue& v, const std::string& owner) {
  std::vector<double> out;
  std::string given;
  if (const double* d = std::get_if<double>(&v)) {
    out.push_back(*d);
    given = format_value(v);
  } else if (const auto* list = std::get_if<std::vector<double>>(&v)) {
    out = *list;
    given = format_value(v);
  } else {
    given = std::get<std::string>(v);
    std::string text = given;
    std::replace(text.begin(), text.end(), ',', ':');
    if (!trim(text).empty()) {
      std::size_t start = 0, index = 1;
      while (start <= text.size()) {
        auto end = text.find(':', start);
        if (end == std::string::npos) end = text.size();
        const std::string item = trim(std::string_view(text).substr(start, end - start));
        const auto num = to_number(item);
        if (!num)
          throw InputError(fmt::format(
              "parameter '{}' of {}: element {} of '{}' is {}; {}", spec.name, owner, index, given,
              item.empty() ? "empty" : fmt::format("'{}', not a number", item),
              fmt::format(fmt::runtime(kListFix), spec.name)));
        out.push_back(*num);
        start = end + 1;
        ++index;
      }
    }
  }
  if (out.empty())
    throw InputError(fmt::format("parameter '{}' of {} is an empty list; {}", spec.name, owner,
                                 fmt::format(fmt::runtime(kListFix), spec.name)));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double x = out[i];
    const auto where = [&] {
      return fmt::format("parameter '{}' of {}: element {} of '{}'", spec.name, owner, i + 1,
                         given);
    };
    if (!std::isfinite(x))
      throw InputError(fmt::format("{} is {}, not a finite number; {}", where(), x,
                                   fmt::format(fmt::runtime(kListFix), spec.name)));
    check_magnitude(x, where);
    if (spec.integer && std::abs(x - std::round(x)) > 1e-12)
      throw InputError(fmt::format("{} must be an integer, got {}", where(), x));
    if (spec.min && (spec.min_exclusive ? x <= *spec.min : x < *spec.min))
      throw InputError(fmt::format("{} must be {} {}, got {} ({})", where(),
                                   spec.min_exclusive ? ">" : ">=", *spec.min, x,
                                   spec.description));
    if (spec.max && x > *spec.max)
      throw InputError(fmt::format("{} must be <= {}, got {} ({})", where(), *spec.max, x,
                                   spec.description));
  }
  return out;
}

}  // namespace

Params Params::parse(std::string_view text) {
  Params p;
  std::size_t start = 0;
  while (start <= text.size()) {
    auto end = text.find(',', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string item = trim(text.substr(start, end - start));
    if (!item.empty()) {
      const auto eq = item.find('=');
      if (eq == std::string::npos || eq == 0)
        throw InputError(fmt::format(
            "parameter '{}' is not of the form key=value (write e.g. 'dmax=2.0,kernel=gaussian')",
            item));
      const std::string key = trim(item.substr(0, eq));
      const std::string val = trim(item.substr(eq + 1));
      // A repeated key would silently keep one of two values: refuse it instead.
      if (p.has(key))
        throw InputError(fmt::format("parameter '{}' is given twice in '{}'; give each key once",
                                     key, text));
      if (auto num = to_number(val))
        p.set(key, *num);
      else
        p.set(key, ParamValue{val});
    }
    start = end + 1;
  }
  return p;
}

void Params::set(const std::string& key, ParamValue value) { values_[key] = std::move(value); }

double Params::number(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw InputError(fmt::format("parameter '{}' is not set", key));
  if (auto d = std::get_if<double>(&it->second)) return *d;
  throw InputError(fmt::format("parameter '{}' must be a number, got {} '{}'", key,
                               kind_of(it->second), format_value(it->second)));
}

int Params::integer(const std::string& key) const {
  // Checked before the conversion: lround of a value outside int is undefined behaviour.
  const double v = number(key);
  if (!std::isfinite(v) || std::abs(v) > 2.0e9)
    throw InputError(fmt::format("parameter '{}' = {} is not a usable integer (|value| must be "
                                 "below 2e9)",
                                 key, v));
  return static_cast<int>(std::lround(v));
}

const std::string& Params::text(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw InputError(fmt::format("parameter '{}' is not set", key));
  if (auto s = std::get_if<std::string>(&it->second)) return *s;
  throw InputError(fmt::format("parameter '{}' must be text, got {}", key, kind_of(it->second)));
}

const std::vector<double>& Params::numbers(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw InputError(fmt::format("parameter '{}' is not set", key));
  if (auto l = std::get_if<std::vector<double>>(&it->second)) return *l;
  throw InputError(fmt::format("parameter '{}' must be a list of numbers, got {}", key,
                               kind_of(it->second)));
}

Params Params::resolve(const ParamSchema& schema, const std::string& owner) const {
  std::vector<std::string> names;
  for (const auto& s : schema) {
    names.push_back(s.name);
    for (const auto& a : s.aliases) names.push_back(a);
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j)
      if (names[i] == names[j])
        throw std::logic_error(fmt::format("{} declares parameter '{}' twice", owner, names[i]));
  // Given values by the parameter they set; an alias is renamed, and a parameter set under
  // two of its names is refused rather than one of them silently winning.
  std::map<std::string, std::pair<std::string, ParamValue>> given;
  for (const auto& [key, value] : values_) {
    const ParamSpec* spec = find_spec(schema, key);
    if (!spec)
      throw InputError(fmt::format("unknown parameter '{}' for {}; {}valid parameters: {}",
                                   shown_name(key),
                                   owner, did_you_mean(key, spec_names(schema)),
                                   join_names(schema)));
    auto [it, fresh] = given.try_emplace(spec->name, key, value);
    if (!fresh) {
      const std::string& other = it->second.first;
      const std::string& old_name = key == spec->name ? other : key;
      throw InputError(fmt::format(
          "parameter '{}' of {} is given twice, as '{}' and as '{}' ('{}' is its deprecated "
          "name); give only {}={}",
          spec->name, owner, other, key, old_name, spec->name,
          format_value(key == spec->name ? value : it->second.second)));
    }
  }
  Params out;
  for (const auto& spec : schema) {
    auto it = given.find(spec.name);
    if (it == given.end() && spec.optional) continue;
    ParamValue v = it == given.end() ? spec.default_value : it->second.second;
    if (std::holds_alternative<std::vector<double>>(spec.default_value)) {
      v = list_of(spec, v, owner);
    } else if (std::holds_alternative<double>(spec.default_value)) {
      const double* d = std::get_if<double>(&v);
      if (!d)
        throw InputError(fmt::format("parameter '{}' of {} must be a number, got {} '{}'",
                                     spec.name, owner, kind_of(v), format_value(v)));
      if (!std::isfinite(*d))
        throw InputError(fmt::format("parameter '{}' of {} must be finite", spec.name, owner));
      check_magnitude(*d, [&] { return fmt::format("parameter '{}' of {}", spec.name, owner); });
      if (spec.integer && std::abs(*d - std::round(*d)) > 1e-12)
        throw InputError(fmt::format("parameter '{}' of {} must be an integer, got {}",
                                     spec.name, owner, *d));
      if (spec.min && (spec.min_exclusive ? *d <= *spec.min : *d < *spec.min))
        throw InputError(fmt::format("parameter '{}' of {} must be {} {}, got {} ({})", spec.name,
                                     owner, spec.min_exclusive ? ">" : ">=", *spec.min, *d,
                                     spec.description));
      if (spec.max && *d > *spec.max)
        throw InputError(fmt::format("parameter '{}' of {} must be <= {}, got {} ({})",
                                     spec.name, owner, *spec.max, *d, spec.description));
    } else {
      // Free text (no choices) takes a number or a list as its printed form: angles=45.
      if (spec.choices.empty() && !std::holds_alternative<std::string>(v)) v = format_value(v);
      const std::string* s = std::get_if<std::string>(&v);
      if (!s)
        throw InputError(fmt::format("parameter '{}' of {} must be one of the words below, got {} "
                                     "'{}'; valid: {}",
                                     spec.name, owner, kind_of(v), format_value(v),
                                     fmt::join(spec.choices, ", ")));
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), *s) == spec.choices.end())
        // A parameter with one admissible value says why (wavelet's kernel).
        throw InputError(fmt::format("parameter '{}' of {} has no value '{}'; valid: {}{}",
                                     spec.name, owner, *s, fmt::join(spec.choices, ", "),
                                     spec.choices.size() == 1 ? " (" + spec.description + ")"
                                                              : std::string()));
    }
    out.set(spec.name, v);
  }
  return out;
}

std::string format_value(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) return fmt::format("{:g}", *d);
  if (auto l = std::get_if<std::vector<double>>(&v)) return fmt::format("{:g}", fmt::join(*l, ":"));
  return std::get<std::string>(v);
}

Params forward(
    const Params& parent,
    std::initializer_list<std::pair<std::string_view, std::string_view>> parent_to_child) {
  Params child;
  for (const auto& [from, to] : parent_to_child) {
    const std::string key(from);
    if (!parent.has(key))
      throw std::logic_error(fmt::format("forwarding '{}' to '{}': the parent has no '{}'", from,
                                         to, from));
    child.set(std::string(to), parent.values().at(key));
  }
  return child;
}

std::string Params::to_string() const {
  std::string out;
  for (const auto& [k, v] : values_) out += (out.empty() ? "" : ",") + k + "=" + format_value(v);
  return out;
}

}  // namespace mfv
