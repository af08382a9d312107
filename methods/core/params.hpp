/// Named, typed plugin parameters with a declared schema: unknown keys and out-of-range
/// values are refused with the list of valid ones (as PySPH's Scheme.configure).
#pragma once
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace mfv {

using ParamValue = std::variant<double, std::string>;

/// One declared parameter: name, meaning, default and admissible range or choices.
struct ParamSpec {
  std::string name;
  std::string description;
  ParamValue default_value;
  std::optional<double> min{};        ///< inclusive lower bound unless min_exclusive
  bool min_exclusive = false;
  std::optional<double> max{};        ///< inclusive upper bound
  std::vector<std::string> choices{}; ///< admissible text values (empty: any)
  bool integer = false;               ///< the number must be integral

  static ParamSpec number(std::string name, double def, std::string description);
  static ParamSpec positive(std::string name, double def, std::string description);
  static ParamSpec count(std::string name, int def, int min, std::string description);
  static ParamSpec choice(std::string name, std::string def, std::vector<std::string> choices,
                          std::string description);
};

using ParamSchema = std::vector<ParamSpec>;

/// `spec` with an inclusive upper bound: counts that size a sweep or a patch are capped where
/// a larger value could only run for ever or exhaust memory.
inline ParamSpec capped(ParamSpec spec, double max) {
  spec.max = max;
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

  /// Checks every key against `schema` (unknown keys throw InputError listing the valid
  /// ones), checks ranges and choices, and returns a copy with defaults filled in.
  /// `owner` names the plugin in messages ("method 'efg'").
  Params resolve(const ParamSchema& schema, const std::string& owner) const;

  /// "key=value,..." in key order; numbers printed compactly. Stable: used as an id.
  std::string to_string() const;

 private:
  std::map<std::string, ParamValue> values_;
};

std::string format_value(const ParamValue& v);

}  // namespace mfv
