#include "verify/reference_studies.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analyses/norms.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

namespace {

using nlohmann::json;

[[noreturn]] void refuse(const std::filesystem::path& file, const std::string& what) {
  throw InputError(fmt::format("reference studies {}: {}; re-run the script that writes it "
                               "(its 'generator')",
                               file.string(), what));
}

Params params_of(const std::filesystem::path& file, const json& j, const std::string& where) {
  Params p;
  if (j.is_null()) return p;
  if (!j.is_object()) refuse(file, where + " must be an object of name: value");
  for (const auto& [k, v] : j.items()) {
    if (v.is_number()) p.set(k, v.get<double>());
    else if (v.is_string()) p.set(k, v.get<std::string>());
    else refuse(file, fmt::format("{}.{} must be a number or a string", where, k));
  }
  return p;
}

double number_or_nan(const std::filesystem::path& file, const json& c, const char* key,
                     const std::string& where, bool required) {
  const auto it = c.find(key);
  if (it == c.end() || it->is_null()) {
    if (required) refuse(file, fmt::format("{} has no {}", where, key));
    return NAN;
  }
  if (!it->is_number()) refuse(file, fmt::format("{}.{} must be a number", where, key));
  const double v = it->get<double>();
  if (!std::isfinite(v)) refuse(file, fmt::format("{}.{} is not finite", where, key));
  return v;
}

}  // namespace

std::vector<StudyResult> load_reference_studies(const std::filesystem::path& file,
                                                const std::vector<std::string>& labels) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) refuse(file, "not a regular file");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::parse_error& e) {
    refuse(file, fmt::format("not JSON ({})", e.what()));
  }
  if (!doc.is_object() || doc.value("schema", std::string()) != kReferenceSchema)
    refuse(file, fmt::format("its schema is not \"{}\"", kReferenceSchema));
  const std::string problem = doc.value("problem", std::string());
  if (problem.empty()) refuse(file, "it names no problem");
  const Params problem_params = params_of(file, doc.value("problem_params", json()), "problem_params");
  const json studies = doc.value("studies", json::array());
  if (!studies.is_array() || studies.empty()) refuse(file, "it holds no studies");
  std::vector<StudyResult> out;
  std::set<std::string> found;
  for (std::size_t s = 0; s < studies.size(); ++s) {
    const json& js = studies[s];
    const std::string where = fmt::format("studies[{}]", s);
    if (!js.is_object()) refuse(file, where + " must be an object");
    const std::string label = js.value("label", std::string());
    if (label.empty()) refuse(file, where + " has no label");
    if (!labels.empty() && std::find(labels.begin(), labels.end(), label) == labels.end())
      continue;
    found.insert(label);
    StudyResult st;
    st.label = label;
    const json cases = js.value("cases", json::array());
    if (!cases.is_array() || cases.empty()) refuse(file, where + " has no cases");
    for (std::size_t k = 0; k < cases.size(); ++k) {
      const json& jc = cases[k];
      const std::string w = fmt::format("{}.cases[{}]", where, k);
      if (!jc.is_object()) refuse(file, w + " must be an object");
      CaseResult c;
      c.spec.problem = problem;
      c.spec.problem_params = problem_params;
      c.spec.method = js.value("method", std::string());
      if (c.spec.method.empty()) refuse(file, where + " names no method");
      c.spec.method_params = params_of(file, js.value("method_params", json()), where + ".method_params");
      c.spec.nodes = static_cast<int>(number_or_nan(file, jc, "nodes", w, true));
      c.particles = static_cast<int>(number_or_nan(file, jc, "particles", w, false));
      c.h = number_or_nan(file, jc, "h", w, true);
      c.errors.l2 = c.errors.l2_rel = number_or_nan(file, jc, "l2_rel", w, true);
      c.errors.energy = c.errors.energy_rel = number_or_nan(file, jc, "energy_rel", w, false);
      c.errors.h1_semi = c.errors.h1_semi_rel = number_or_nan(file, jc, "h1_semi_rel", w, false);
      c.errors_paper = c.errors;
      c.method_description = fmt::format("independent reference ({})",
                                         doc.value("generator", file.filename().string()));
      st.cases.push_back(std::move(c));
    }
    st.rates = study_rates(st.cases, false);
    st.rates_paper = st.rates;
    out.push_back(std::move(st));
  }
  for (const auto& l : labels)
    if (!found.count(l)) refuse(file, fmt::format("it holds no study labelled '{}'", l));
  return out;
}

}  // namespace mfv
