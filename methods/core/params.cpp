#include "methods/core/params.hpp"

#include <algorithm>
#include <cmath>
#include <charconv>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

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

namespace {

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
  throw InputError(fmt::format("parameter '{}' must be a number, got '{}'", key,
                               std::get<std::string>(it->second)));
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
  throw InputError(fmt::format("parameter '{}' must be text, got a number", key));
}

Params Params::resolve(const ParamSchema& schema, const std::string& owner) const {
  Params out;
  for (std::size_t i = 0; i < schema.size(); ++i)
    for (std::size_t j = i + 1; j < schema.size(); ++j)
      if (schema[i].name == schema[j].name)
        throw std::logic_error(fmt::format("{} declares parameter '{}' twice", owner,
                                           schema[i].name));
  for (const auto& [key, value] : values_) {
    bool known = false;
    for (const auto& s : schema) known = known || s.name == key;
    if (!known)
      throw InputError(fmt::format("unknown parameter '{}' for {}; valid parameters: {}", key,
                                   owner, join_names(schema)));
  }
  for (const auto& spec : schema) {
    auto it = values_.find(spec.name);
    ParamValue v = it == values_.end() ? spec.default_value : it->second;
    const bool wants_number = std::holds_alternative<double>(spec.default_value);
    if (wants_number) {
      const double* d = std::get_if<double>(&v);
      if (!d)
        throw InputError(fmt::format("parameter '{}' of {} must be a number, got '{}'",
                                     spec.name, owner, std::get<std::string>(v)));
      if (!std::isfinite(*d))
        throw InputError(fmt::format("parameter '{}' of {} must be finite", spec.name, owner));
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
      // Free text (no choices) takes a number as its printed form: angles=45.
      if (spec.choices.empty() && std::holds_alternative<double>(v)) v = format_value(v);
      const std::string* s = std::get_if<std::string>(&v);
      if (!s)
        throw InputError(fmt::format("parameter '{}' of {} must be one of the words below, got a "
                                     "number; valid: {}",
                                     spec.name, owner, fmt::join(spec.choices, ", ")));
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), *s) == spec.choices.end())
        throw InputError(fmt::format("parameter '{}' of {} has no value '{}'; valid: {}",
                                     spec.name, owner, *s, fmt::join(spec.choices, ", ")));
    }
    out.set(spec.name, v);
  }
  return out;
}

std::string format_value(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) return fmt::format("{:g}", *d);
  return std::get<std::string>(v);
}

std::string Params::to_string() const {
  std::string out;
  for (const auto& [k, v] : values_) out += (out.empty() ? "" : ",") + k + "=" + format_value(v);
  return out;
}

}  // namespace mfv
