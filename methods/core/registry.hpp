/// Registry of plugins by name: an object (never a global), filled by an explicit
/// register_all list (as PETSc's KSPRegisterAll); unknown names throw and list valid ones.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/names.hpp"
#include "methods/core/params.hpp"

namespace mfv {

template <class T>
class Registry {
 public:
  /// Builds a plugin from parameters already resolved against its schema.
  using Factory = std::function<std::unique_ptr<T>(const Params& resolved)>;

  struct Entry {
    std::string name;
    std::string description;
    ParamSchema schema;
    Factory factory;
  };

  explicit Registry(std::string kind) : kind_(std::move(kind)) {}

  void add(std::string name, std::string description, ParamSchema schema, Factory factory) {
    if (entries_.count(name))
      throw std::logic_error(fmt::format("{} '{}' registered twice", kind_, name));
    Entry e{name, std::move(description), std::move(schema), std::move(factory)};
    entries_.emplace(std::move(name), std::move(e));
  }

  bool contains(const std::string& name) const { return entries_.count(name) != 0; }

  const Entry& entry(const std::string& name) const {
    auto it = entries_.find(name);
    if (it == entries_.end())
      throw InputError(fmt::format("unknown {} '{}'; {}valid {}s: {}", kind_, shown_name(name),
                                   did_you_mean(name, keys()), kind_, fmt::join(keys(), ", ")));
    return it->second;
  }

  /// Resolves `params` against the plugin's schema (refusing unknown keys) and builds it.
  std::unique_ptr<T> create(const std::string& name, const Params& params = {}) const {
    const Entry& e = entry(name);
    std::unique_ptr<T> made =
        e.factory(params.resolve(e.schema, fmt::format("{} '{}'", kind_, name)));
    // A plugin's factory that returns null would be dereferenced by every caller.
    if (!made)
      throw InputError(fmt::format("{} '{}': its factory built nothing (a null pointer); a "
                                   "factory returns the object or throws naming what is wrong",
                                   kind_, name));
    return made;
  }

  /// Builds `name` as the derived type U (e.g. a problem as the definition an analysis
  /// reads); InputError naming the plugin when it is not one.
  template <class U>
  std::unique_ptr<U> create_as(const std::string& name, const Params& params = {}) const {
    std::unique_ptr<T> p = create(name, params);
    if (auto* u = dynamic_cast<U*>(p.get())) {
      p.release();
      return std::unique_ptr<U>(u);
    }
    throw InputError(fmt::format("{} '{}' is not of the kind asked for here", kind_, name));
  }

  Params resolve(const std::string& name, const Params& params) const {
    const Entry& e = entry(name);
    return params.resolve(e.schema, fmt::format("{} '{}'", kind_, name));
  }

  std::vector<std::string> keys() const {
    std::vector<std::string> out;
    for (const auto& [k, v] : entries_) out.push_back(k);
    return out;
  }

  const std::string& kind() const { return kind_; }

 private:
  std::string kind_;
  std::map<std::string, Entry> entries_;
};

}  // namespace mfv
