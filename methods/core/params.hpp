/// Named, typed plugin parameters with a declared schema: unknown keys and out-of-range
/// values are refused with the list of valid ones (as PySPH's Scheme.configure).
#pragma once
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace mfv {

/// A number, a text, or a list of numbers (resolved against a `ParamSpec::numbers` entry).
using ParamValue = std::variant<double, std::string, std::vector<double>>;

/// One declared parameter: name, meaning, default and admissible range or choices. The kind
/// follows the default: a number, a text, or a list of numbers (each element checked against
/// min/max).
struct ParamSpec {
  std::string name;
  std::string description;
  ParamValue default_value;
  std::optional<double> min{};        ///< inclusive lower bound unless min_exclusive
  bool min_exclusive = false;
  std::optional<double> max{};        ///< inclusive upper bound
  std::vector<std::string> choices{}; ///< admissible text values (empty: any)
  bool integer = false;               ///< the number must be integral
  /// Deprecated names that still parse and resolve to `name` (old manifests keep working).
  std::vector<std::string> aliases{};
  /// No default: absent from the resolved set unless given (a kernel parameter forwarded
  /// by a method, which the kernel defaults itself); `default_value` gives only the kind.
  bool optional = false;

  static ParamSpec number(std::string name, double def, std::string description);
  static ParamSpec positive(std::string name, double def, std::string description);
  static ParamSpec count(std::string name, int def, int min, std::string description);
  static ParamSpec choice(std::string name, std::string def, std::vector<std::string> choices,
                          std::string description);
  /// A list of finite numbers, given as "0:45", "0,45" (a manifest string; the key=value
  /// syntax splits at commas) or one number. `def` must not be empty.
  static ParamSpec numbers(std::string name, std::vector<double> def, std::string description);
};

using ParamSchema = std::vector<ParamSpec>;

/// `spec` with an inclusive upper bound: counts that size a sweep or a patch are capped where
/// a larger value could only run for ever or exhaust memory.
inline ParamSpec capped(ParamSpec spec, double max) {
  spec.max = max;
  return spec;
}

/// `spec` that also answers to the deprecated name `old_name`, resolved to `spec.name`.
inline ParamSpec aliased(ParamSpec spec, std::string old_name) {
  spec.aliases.push_back(std::move(old_name));
  return spec;
}

/// A set of parameter values. `resolve` checks it against a schema and fills defaults.
class Params {
 public:
  Params() = default;
  /// Parses "key=value,key=value"; numbers become doubles, anything else text.
  static Params parse(std::string_view text);

  void set(const std::string& key, ParamValue value);
  void set(const std::string& key, double value) { set(key, ParamValue{value}); }
  void set(const std::string& key, const char* value) { set(key, ParamValue{std::string(value)}); }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  const std::map<std::string, ParamValue>& values() const { return values_; }

  double number(const std::string& key) const;
  int integer(const std::string& key) const;
  const std::string& text(const std::string& key) const;
  /// The list of a resolved `ParamSpec::numbers` parameter.
  const std::vector<double>& numbers(const std::string& key) const;

  /// Checks every key against `schema` (unknown keys throw InputError listing the valid
  /// ones; a deprecated alias is renamed to its parameter), checks ranges and choices, and
  /// returns a copy with defaults filled in.
  /// `owner` names the plugin in messages ("method 'efg'").
  Params resolve(const ParamSchema& schema, const std::string& owner) const;

  /// "key=value,..." in key order; numbers printed compactly. Stable: used as an id.
  std::string to_string() const;

 private:
  std::map<std::string, ParamValue> values_;
};

/// A value as text: numbers compactly ({:g}), lists as their elements joined by ':'.
std::string format_value(const ParamValue& v);

/// The parameters a plugin hands to a child plugin, declared as (parent key, child key) pairs:
/// each value is copied as it is (number, text or list). A parent key that is not set is a
/// programming error (the parent's schema does not declare it) and throws std::logic_error.
Params forward(
    const Params& parent,
    std::initializer_list<std::pair<std::string_view, std::string_view>> parent_to_child);

}  // namespace mfv
