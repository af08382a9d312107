#include "verify/manifest.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <fcntl.h>
#include <fnmatch.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "methods/core/errors.hpp"
#include "methods/core/names.hpp"

namespace mfv {

namespace detail {

std::string read_text_file(const std::filesystem::path& path, const std::string& what,
                           const std::string& hint) {
  auto fail = [&](const std::string& why) {
    return InputError(fmt::format("cannot read {} {}: {}; {}", what, path.string(), why, hint));
  };
  // O_NONBLOCK: a FIFO named here must be refused, not waited on for ever.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw fail(std::strerror(errno));
  std::unique_ptr<int, void (*)(int*)> close_fd(new int(fd), [](int* p) {
    ::close(*p);
    delete p;
  });
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw fail(std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw fail(fmt::format("it is {}, not a regular file",
                           S_ISDIR(st.st_mode)    ? "a directory"
                           : S_ISFIFO(st.st_mode) ? "a pipe (FIFO)"
                           : S_ISCHR(st.st_mode)  ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "a special file"));
  if (st.st_size > static_cast<off_t>(kMaxTextFileBytes))
    throw fail(fmt::format("it holds {} bytes, more than the {} MiB a text input may have",
                           static_cast<long long>(st.st_size), kMaxTextFileBytes >> 20));
  std::string text;
  char buffer[8192];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw fail(std::strerror(errno));
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    // A file that grows while we read it is bounded too.
    if (text.size() > kMaxTextFileBytes)
      throw fail(fmt::format("it holds more than the {} MiB a text input may have",
                             kMaxTextFileBytes >> 20));
  }
  return text;
}

}  // namespace detail

namespace {

constexpr const char* kSyntaxHint = "fix the TOML syntax (see suites/example.toml)";

/// Builds "<file>:<line>: <what>; <fix>" errors for one manifest.
class Reporter {
 public:
  explicit Reporter(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(int line, const std::string& what, const std::string& fix) const {
    throw InputError(fmt::format("{}:{}: {}; {}", file_, line, what, fix));
  }

 private:
  std::string file_;
};

int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }
int line_of(const toml::key& k) { return static_cast<int>(k.source().begin.line); }

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

/// Refuses keys outside `valid`, naming the closest valid key when it looks like a typo.
void check_keys(const Reporter& r, const toml::table& t, const std::vector<std::string>& valid,
                const std::string& where) {
  for (const auto& [key, value] : t) {
    const std::string k(key.str());
    if (std::find(valid.begin(), valid.end(), k) != valid.end()) continue;
    std::string fix = fmt::format("valid keys: {}", fmt::join(valid, ", "));
    const auto closest = std::min_element(valid.begin(), valid.end(), [&](auto& a, auto& b) {
      return edit_distance(k, a) < edit_distance(k, b);
    });
    if (closest != valid.end() && edit_distance(k, *closest) <= 2)
      fix = fmt::format("did you mean '{}'? {}", *closest, fix);
    const int line = line_of(key) > 0 ? line_of(key) : line_of(value);
    r.fail(line, fmt::format("unknown key '{}' in {}", k, where), fix);
  }
}

std::optional<double> number_of(const toml::node& n) {
  if (auto i = n.as_integer()) return static_cast<double>(i->get());
  if (auto f = n.as_floating_point()) return f->get();
  return std::nullopt;
}

std::string get_string(const Reporter& r, const toml::node& n, const std::string& key,
                       bool allow_empty = false) {
  const auto* s = n.as_string();
  if (!s)
    r.fail(line_of(n), fmt::format("'{}' must be a string, got {}", key, type_name(n)),
           fmt::format("write {} = \"...\"", key));
  if (!allow_empty && s->get().empty())
    r.fail(line_of(n), fmt::format("'{}' is empty", key), "give it a non-empty value");
  return s->get();
}

double get_number(const Reporter& r, const toml::node& n, const std::string& key) {
  const auto v = number_of(n);
  if (!v)
    r.fail(line_of(n), fmt::format("'{}' must be a number, got {}", key, type_name(n)),
           fmt::format("write e.g. {} = 0.05", key));
  if (!std::isfinite(*v))
    r.fail(line_of(n), fmt::format("'{}' must be finite, got {}", key, *v),
           "give a finite number");
  return *v;
}

const toml::node& require(const Reporter& r, const toml::table& t, const std::string& key,
                          const std::string& where, const std::string& example) {
  const toml::node* n = t.get(key);
  if (!n)
    r.fail(line_of(t), fmt::format("{} has no '{}'", where, key),
           fmt::format("add the required key, e.g. {}", example));
  return *n;
}

Params get_params(const Reporter& r, const toml::node& n, const std::string& key) {
  const auto* t = n.as_table();
  if (!t)
    r.fail(line_of(n), fmt::format("'{}' must be a table, got {}", key, type_name(n)),
           fmt::format("write {} = {{ name = value, ... }}", key));
  Params p;
  for (const auto& [k, v] : *t) {
    const std::string name(k.str());
    if (auto d = number_of(v)) {
      p.set(name, *d);
    } else if (auto s = v.as_string()) {
      p.set(name, ParamValue{s->get()});
    } else if (auto b = v.as_boolean()) {
      p.set(name, b->get() ? "true" : "false");
    } else {
      r.fail(line_of(v),
             fmt::format("parameter '{}' in '{}' is {}", name, key, type_name(v)),
             "parameter values must be numbers, strings or booleans");
    }
  }
  return p;
}

std::vector<int> get_nodes(const Reporter& r, const toml::node& n, const std::string& key) {
  const std::string fix = fmt::format("write {} = [21, 41, 81] (increasing integers >= 2)", key);
  const auto* a = n.as_array();
  if (!a) r.fail(line_of(n), fmt::format("'{}' must be an array, got {}", key, type_name(n)), fix);
  if (a->empty()) r.fail(line_of(n), fmt::format("'{}' is empty", key), fix);
  std::vector<int> out;
  for (const auto& e : *a) {
    const int line = line_of(e) > 0 ? line_of(e) : line_of(n);
    const auto* i = e.as_integer();
    if (!i) r.fail(line, fmt::format("'{}' must hold integers, got {}", key, type_name(e)), fix);
    const auto v = i->get();
    // Fewer than 2 particles cannot span the domain: there is no spacing h.
    if (v < 2 || v > std::numeric_limits<int>::max())
      r.fail(line, fmt::format("'{}' holds {}, not a node count >= 2", key, v), fix);
    // The last entry is taken as the finest resolution for the _finest bands.
    if (!out.empty() && v <= out.back())
      r.fail(line, fmt::format("'{}' is not increasing ({} after {})", key, v, out.back()), fix);
    out.push_back(static_cast<int>(v));
  }
  return out;
}

Band get_band(const Reporter& r, const toml::node& n, const std::string& name) {
  const std::string fix =
      fmt::format("write the band as a two-number array [low, high], e.g. {} = [1.9, 2.1]", name);
  const auto* a = n.as_array();
  if (!a)
    r.fail(line_of(n), fmt::format("band '{}' must be an array, got {}", name, type_name(n)), fix);
  if (a->size() != 2)
    r.fail(line_of(n), fmt::format("band '{}' has {} elements, not 2", name, a->size()), fix);
  const auto low = number_of(*a->get(0)), high = number_of(*a->get(1));
  if (!low || !high)
    r.fail(line_of(n), fmt::format("band '{}' must hold two numbers", name), fix);
  if (std::isnan(*low) || std::isnan(*high))
    r.fail(line_of(n), fmt::format("band '{}' holds nan", name),
           "use inf or -inf for a one-sided band");
  if (*low == std::numeric_limits<double>::infinity() ||
      *high == -std::numeric_limits<double>::infinity())
    r.fail(line_of(n), fmt::format("band '{}' = [{}, {}] admits no finite value", name, *low, *high),
           "only the low bound may be -inf and only the high bound inf (a one-sided band)");
  if (*low > *high)
    r.fail(line_of(n), fmt::format("band '{}' has low {} > high {}", name, *low, *high),
           fmt::format("swap them: {} = [{}, {}]", name, *high, *low));
  return Band{*low, *high, line_of(n)};
}

bool has_whitespace(const std::string& s) {
  return std::any_of(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c) != 0; });
}

ManifestCase parse_case(const Reporter& r, const toml::table& t) {
  static const std::vector<std::string> kKeys = {
      "id",    "problem",    "problem_params", "method", "method_params", "nodes",
      "full_nodes", "perturbation", "labels", "bands", "drift_tolerance", "expect", "analysis",
      "full_only"};
  ManifestCase c;
  c.line = line_of(t);
  c.id = get_string(r, require(r, t, "id", "[[case]]", "id = \"laplace-tanh/fem\""), "id");
  const std::string where = fmt::format("[[case]] '{}'", c.id);
  if (has_whitespace(c.id))
    r.fail(line_of(*t.get("id")), fmt::format("case id '{}' contains white space", c.id),
           "ids are CTest names: use e.g. '-', '_' or '/' instead");
  check_keys(r, t, kKeys, where);
  c.problem = get_string(r, require(r, t, "problem", where, "problem = \"laplace-tanh\""),
                         "problem");
  c.method = get_string(r, require(r, t, "method", where, "method = \"fem\""), "method");
  if (auto n = t.get("analysis")) c.analysis = get_string(r, *n, "analysis");
  c.nodes = get_nodes(r, require(r, t, "nodes", where, "nodes = [21, 41, 81]"), "nodes");
  c.full_nodes = t.get("full_nodes") ? get_nodes(r, *t.get("full_nodes"), "full_nodes") : c.nodes;
  if (auto n = t.get("problem_params")) c.problem_params = get_params(r, *n, "problem_params");
  if (auto n = t.get("method_params")) c.method_params = get_params(r, *n, "method_params");
  if (auto n = t.get("perturbation")) {
    c.perturbation = get_number(r, *n, "perturbation");
    if (c.perturbation < 0)
      r.fail(line_of(*n), fmt::format("perturbation {} is negative", c.perturbation),
             "give a fraction of the particle spacing >= 0");
  }
  if (auto n = t.get("drift_tolerance")) {
    c.drift_tolerance = get_number(r, *n, "drift_tolerance");
    if (*c.drift_tolerance <= 0)
      r.fail(line_of(*n), fmt::format("drift_tolerance {} is not positive", *c.drift_tolerance),
             "give a relative tolerance > 0, or leave it out to use the suite's");
  }
  if (auto n = t.get("expect")) {
    const std::string e = get_string(r, *n, "expect");
    if (e != "stable" && e != "unstable")
      r.fail(line_of(*n), fmt::format("expect = \"{}\" is neither \"stable\" nor \"unstable\"", e),
             "write expect = \"unstable\" for a transient case meant to blow up, or leave it out");
    c.expect_unstable = e == "unstable";
  }
  if (auto n = t.get("full_only")) {
    const auto* b = n->as_boolean();
    if (!b)
      r.fail(line_of(*n), fmt::format("'full_only' must be true or false, got {}", type_name(*n)),
             "write full_only = true for a case that runs only with --full");
    c.full_only = b->get();
  }
  if (auto n = t.get("labels")) {
    const auto* a = n->as_array();
    if (!a)
      r.fail(line_of(*n), fmt::format("'labels' must be an array, got {}", type_name(*n)),
             "write labels = [\"fast\"]");
    for (const auto& e : *a) {
      c.labels.push_back(get_string(r, e, "labels"));
      // A CTest label list is ';'-separated: "a;b" would become two labels.
      const std::string& l = c.labels.back();
      if (l.empty() || l.find(';') != std::string::npos || has_whitespace(l))
        r.fail(line_of(e), fmt::format("label '{}' is empty or holds ';' or white space", l),
               "write one word per label, e.g. labels = [\"fast\", \"2d\"]");
    }
  }
  if (auto n = t.get("bands")) {
    const auto* b = n->as_table();
    if (!b)
      r.fail(line_of(*n), fmt::format("'bands' must be a table, got {}", type_name(*n)),
             "write the bands under a [case.bands] header");
    std::vector<std::string> valid = band_metrics();
    valid.push_back("headline");
    check_keys(r, *b, valid, fmt::format("[case.bands] of '{}'", c.id));
    for (const auto& metric : band_metrics())
      if (auto v = b->get(metric)) c.bands[metric] = get_band(r, *v, metric);
    if (auto h = b->get("headline")) {
      const auto* ht = h->as_table();
      if (!ht)
        r.fail(line_of(*h), fmt::format("'headline' must be a table, got {}", type_name(*h)),
               "write headline = { \"<headline name>\" = [low, high] }");
      for (const auto& [k, v] : *ht) c.headline_bands[std::string(k.str())] =
          get_band(r, v, fmt::format("headline '{}'", k.str()));
    }
    // A rate is a slope: it needs two resolutions in every mode the case can run in.
    const bool has_rate =
        c.bands.count("l2_rate") || c.bands.count("h1_rate") || c.bands.count("energy_rate");
    if (has_rate && std::min(c.nodes.size(), c.full_nodes.size()) < 2)
      r.fail(c.line, fmt::format("case '{}' has a rate band but fewer than 2 resolutions", c.id),
             "list at least two resolutions in nodes (and full_nodes)");
  }
  return c;
}

/// A suite name becomes a directory under runs/: a name, never a path.
bool is_plain_name(const std::string& s) {
  if (s.empty() || s.size() > 100 || !std::isalnum(static_cast<unsigned char>(s.front())))
    return false;
  for (char ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '.' && ch != '_' && ch != '-')
      return false;
  return s.find("..") == std::string::npos;
}

void parse_suite(const Reporter& r, const toml::node& n, Manifest& m) {
  static const std::vector<std::string> kKeys = {"name", "description", "baseline",
                                                 "drift_tolerance", "drift_floor", "ledger",
                                                 "plugins", "timing_gate",
                                                 "timing_floor_seconds"};
  const auto* t = n.as_table();
  if (!t)
    r.fail(line_of(n), fmt::format("'suite' must be a table, got {}", type_name(n)),
           "write the suite settings under a [suite] header");
  check_keys(r, *t, kKeys, "[suite]");
  if (auto v = t->get("name")) {
    m.name = get_string(r, *v, "name");
    if (!is_plain_name(m.name))
      r.fail(line_of(*v), fmt::format("suite name '{}' is not a plain name", m.name),
             "a suite name names the report directory runs/<name>: use letters, digits, '.', "
             "'_' and '-', starting with a letter or digit (no '/' or '..')");
  }
  if (auto v = t->get("description")) m.description = get_string(r, *v, "description", true);
  if (auto v = t->get("baseline")) {
    const std::filesystem::path b = get_string(r, *v, "baseline");
    m.baseline = b.is_absolute() ? b : m.path.parent_path() / b;
  }
  if (auto v = t->get("ledger")) {
    const std::filesystem::path l = get_string(r, *v, "ledger");
    m.ledger = l.is_absolute() ? l : m.path.parent_path() / l;
  }
  if (auto v = t->get("plugins")) {
    const auto* a = v->as_array();
    if (!a)
      r.fail(line_of(*v), fmt::format("'plugins' must be an array of paths, got {}", type_name(*v)),
             "write plugins = [\"path/to/libplugin.so\"]");
    for (const auto& e : *a) {
      const std::filesystem::path p = get_string(r, e, "plugins entry");
      m.plugins.push_back(p.is_absolute() ? p : m.path.parent_path() / p);
    }
  }
  if (auto v = t->get("drift_tolerance")) {
    m.drift_tolerance = get_number(r, *v, "drift_tolerance");
    if (m.drift_tolerance <= 0)
      r.fail(line_of(*v), fmt::format("drift_tolerance {} is not positive", m.drift_tolerance),
             "give a relative tolerance > 0, e.g. drift_tolerance = 0.05 for 5%");
  }
  if (auto v = t->get("timing_gate")) {
    const auto* b = v->as_boolean();
    if (!b)
      r.fail(line_of(*v), fmt::format("'timing_gate' must be true or false, got {}", type_name(*v)),
             "write timing_gate = true to fail the run on a timing regression");
    m.timing_gate = b->get();
  }
  if (auto v = t->get("timing_floor_seconds")) {
    m.timing_floor_seconds = get_number(r, *v, "timing_floor_seconds");
    if (!(m.timing_floor_seconds >= 0) || !std::isfinite(m.timing_floor_seconds))
      r.fail(line_of(*v),
             fmt::format("timing_floor_seconds {} is not a finite number >= 0",
                         m.timing_floor_seconds),
             "give the seconds a short case's CPU may wander, e.g. timing_floor_seconds = 2");
  }
  if (auto v = t->get("drift_floor")) {
    m.drift_floor = get_number(r, *v, "drift_floor");
    if (m.drift_floor < 0)
      r.fail(line_of(*v), fmt::format("drift_floor {} is negative", m.drift_floor),
             "give an absolute error floor >= 0, e.g. drift_floor = 1e-12");
  }
}

}  // namespace

const std::vector<std::string>& band_metrics() {
  static const std::vector<std::string> kMetrics = {
      "l2_rate",       "h1_rate",       "l2_finest",        "h1_finest",
      "l2_rel_finest", "h1_rel_finest", "energy_rate",      "energy_rel_finest"};
  return kMetrics;
}

const ManifestCase& Manifest::find(const std::string& id) const {
  for (const auto& c : cases)
    if (c.id == id) return c;
  std::vector<std::string> ids;
  for (const auto& c : cases) ids.push_back(c.id);
  throw InputError(fmt::format("no case '{}' in manifest {}; {}{} cases: `mfv verify {} --list` "
                               "names them",
                               id, path.string(), did_you_mean(id, ids), ids.size(),
                               path.string()));
}

std::vector<const ManifestCase*> Manifest::select(const std::string& pattern) const {
  std::vector<const ManifestCase*> out;
  // An id that is itself a case wins over reading it as a pattern (ids may hold '[').
  for (const auto& c : cases)
    if (c.id == pattern) return {&c};
  const bool glob = pattern.find_first_of("*?[") != std::string::npos;
  if (glob)
    for (const auto& c : cases)
      if (::fnmatch(pattern.c_str(), c.id.c_str(), 0) == 0) out.push_back(&c);
  if (!out.empty()) return out;
  std::vector<std::string> ids;
  for (const auto& c : cases) ids.push_back(c.id);
  const auto near = near_matches(pattern, ids, 5);
  std::string hint;
  if (!near.empty()) hint = fmt::format("near ones: {}; ", fmt::join(near, ", "));
  throw InputError(fmt::format("{} '{}' matches no case of manifest {}; {}{} cases: `mfv verify "
                               "{} --list` names them{}",
                               glob ? "the pattern" : "the id", pattern, path.string(), hint,
                               ids.size(), path.string(),
                               glob ? "" : " (a pattern takes *, ? and [...], e.g. 'rod-pulse/*')"));
}

Manifest load_manifest(const std::filesystem::path& path) {
  const Reporter r(path.string());
  const std::string text =
      detail::read_text_file(path, "manifest", "check the path (e.g. suites/default.toml)");
  toml::table root;
  try {
    root = toml::parse(text, path.string());
  } catch (const toml::parse_error& e) {
    r.fail(static_cast<int>(e.source().begin.line), std::string(e.description()), kSyntaxHint);
  }

  Manifest m;
  m.path = path;
  m.name = path.stem().string();
  check_keys(r, root, {"suite", "case"}, "the manifest's top level");
  if (auto s = root.get("suite")) parse_suite(r, *s, m);
  if (!is_plain_name(m.name))
    r.fail(1, fmt::format("the suite has no plain name (the file name gives '{}')", m.name),
           "set [suite] name = \"...\" with letters, digits, '.', '_' and '-'");

  const toml::node* cases = root.get("case");
  if (!cases)
    r.fail(1, "the manifest has no [[case]] entries", "add at least one [[case]] table");
  const auto* list = cases->as_array();
  if (!list || !list->is_array_of_tables())
    r.fail(line_of(*cases), "'case' must be an array of tables",
           "start each case with a [[case]] header (double brackets)");
  std::map<std::string, int> seen;
  for (const auto& node : *list) {
    ManifestCase c = parse_case(r, *node.as_table());
    if (auto it = seen.find(c.id); it != seen.end())
      r.fail(c.line, fmt::format("duplicate case id '{}' (first defined at line {})", c.id,
                                 it->second),
             "give every case a unique id");
    seen[c.id] = c.line;
    m.cases.push_back(std::move(c));
  }
  return m;
}

std::vector<int> resolutions(const ManifestCase& c, bool full) {
  return full ? c.full_nodes : c.nodes;
}

namespace {

/// The value with 4 significant digits, or as many more as it takes for the printed value to
/// be visibly outside the band (1.9 printed for 1.89996 would contradict the message).
std::string show_outside(double v, const Band& b) {
  for (int digits = 4; digits < 17; ++digits) {
    const std::string s = fmt::format("{:.{}g}", v, digits);
    const double shown = std::strtod(s.c_str(), nullptr);
    if (!(shown >= b.low && shown <= b.high)) return s;
  }
  return fmt::format("{:.17g}", v);
}

std::string show_band(const Band& b) { return fmt::format("[{}, {}]", b.low, b.high); }

}  // namespace

std::vector<BandViolation> check_bands(const ManifestCase& c, const StudyResult& s,
                                       const std::string& manifest_file) {
  std::vector<BandViolation> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // The finest of `nodes`: a --full study runs more resolutions, but the _finest and headline
  // bands were written for the default finest one, which full_nodes normally contains.
  const CaseResult* finest = s.cases.empty() ? nullptr : &s.cases.back();
  if (!c.nodes.empty())
    for (const auto& r : s.cases)
      if (r.spec.nodes == c.nodes.back()) finest = &r;
  auto where = [&](const Band& b) { return fmt::format("({}:{})", manifest_file, b.line); };

  auto check = [&](const std::string& metric, const std::string& shown_name, double value,
                   const Band& band, const std::string& why_nan) {
    // A non-finite value is outside every band, [0, inf] included.
    if (std::isfinite(value) && value >= band.low && value <= band.high) return;
    std::string msg;
    if (std::isnan(value))
      msg = fmt::format("{}: {} is not a number ({}), so it cannot be inside the band {} {}",
                        c.id, shown_name, why_nan, show_band(band), where(band));
    else
      msg = fmt::format("{}: {} = {} is outside the band {} {}", c.id, shown_name,
                        show_outside(value, band), show_band(band), where(band));
    out.push_back(BandViolation{c.id, metric, value, band, std::move(msg)});
  };

  for (const auto& metric : band_metrics()) {
    const auto it = c.bands.find(metric);
    if (it == c.bands.end()) continue;
    double value = nan;
    std::string why = "the run produced NaN";
    if (metric == "l2_rate" || metric == "h1_rate" || metric == "energy_rate") {
      if (s.cases.size() < 2)
        why = fmt::format("a rate needs at least 2 resolutions, the study has {}", s.cases.size());
      else
        value = metric == "l2_rate"   ? s.rates.rate("L2")
                : metric == "h1_rate" ? s.rates.rate("H1-semi")
                                      : s.rates.rate("energy");
    } else if (!finest) {
      why = "the study has no resolutions";
    } else {
      const ErrorNorms& e = finest->errors;
      if (metric == "l2_finest") value = e.l2;
      else if (metric == "h1_finest") value = e.h1_semi;
      else if (metric == "l2_rel_finest") value = e.l2_rel;
      else if (metric == "h1_rel_finest") value = e.h1_semi_rel;
      else if (metric == "energy_rel_finest") value = e.energy_rel;
    }
    check(metric, metric, value, it->second, why);
  }

  for (const auto& [name, band] : c.headline_bands) {
    const std::string metric = "headline:" + name;
    const std::string shown = fmt::format("headline '{}'", name);
    if (!finest) {
      check(metric, shown, nan, band, "the study has no resolutions");
      continue;
    }
    const auto it = finest->headline.find(name);
    if (it == finest->headline.end()) {
      std::vector<std::string> names;
      for (const auto& [n, v] : finest->headline) names.push_back("'" + n + "'");
      const std::string available =
          names.empty() ? "the problem computes no headline quantities"
                        : fmt::format("the problem computes {}", fmt::join(names, ", "));
      out.push_back(BandViolation{
          c.id, metric, nan, band,
          fmt::format("{}: {} was not computed; {}; fix the name in the manifest {}", c.id, shown,
                      available, where(band))});
      continue;
    }
    check(metric, shown, it->second, band, "the run produced NaN");
  }
  return out;
}

std::vector<std::string> check_stability(const ManifestCase& c, const StudyResult& s) {
  std::vector<std::string> out;
  const bool transient = std::any_of(s.cases.begin(), s.cases.end(),
                                     [](const CaseResult& r) { return r.find<TransientData>() != nullptr; });
  if (!transient) {
    if (c.expect_unstable)
      out.push_back(fmt::format("{}: expect = \"unstable\" applies to transient runs; problem '{}' "
                                "has none: remove the key",
                                c.id, c.problem));
    return out;
  }
  for (const CaseResult& r : s.cases) {
    const TransientData& t = r.data<TransientData>();
    if (t.instability && !c.expect_unstable)
      out.push_back(fmt::format("{}: {} nodes: {}", c.id, r.spec.nodes, t.verdict()));
    else if (!t.instability && c.expect_unstable)
      out.push_back(fmt::format("{}: {} nodes: expected unstable (expect = \"unstable\"), but the "
                                "run stayed stable for {} steps to t = {:.6g}",
                                c.id, r.spec.nodes, t.steps, t.end_time));
  }
  return out;
}

}  // namespace mfv
