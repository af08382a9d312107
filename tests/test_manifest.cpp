// Unit tests of the verification manifest (verify/manifest.hpp) and the baseline file
// (verify/baseline.hpp): parsing, the "<file>:<line>: <what>; <fix>" errors, band checks and
// drift checks. No numerics: studies are built by hand. Most cases are rows of a table (one
// test per row, named by the row); what fits no table is a test of its own.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <fstream>

#include "methods/core/errors.hpp"
#include "tests/temp_files.hpp"
#include "verify/baseline.hpp"
#include "verify/manifest.hpp"

namespace fs = std::filesystem;
using namespace mfv;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A fresh directory per test (tests/temp_files.hpp) and the files written into it.
class Files : public ::testing::Test {
 protected:
  /// Writes `text` to dir/name and returns the path. Line 1 is the first line of `text`.
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_.path() / name;
    test::write_text(p, text);
    EXPECT_EQ(test::read_file(p), text) << "cannot write " << p;
    return p;
  }

  test::TempDir dir_{"mfv-test-manifest"};
};

/// A table's fixture: a fresh directory and one row of the table.
template <class Row>
class TableTest : public Files, public ::testing::WithParamInterface<Row> {};

/// Names a table's tests by the rows' `name`.
struct RowName {
  template <class Row>
  std::string operator()(const ::testing::TestParamInfo<Row>& info) const {
    return info.param.name;
  }
};

/// A failed row prints as its name rather than as bytes.
template <class Row>
  requires requires(const Row& r) { r.name; }
void PrintTo(const Row& row, std::ostream* os) {
  *os << row.name;
}

/// The InputError message of `load()`; a test failure if it does not throw one.
template <class F>
std::string error_of(F&& load) {
  try {
    load();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

std::string manifest_error(const fs::path& p) { return error_of([&] { load_manifest(p); }); }
std::string baseline_error(const fs::path& p) { return error_of([&] { load_baseline(p); }); }

/// `msg` has the "<file>:<line>: " prefix and a "; <fix>" part.
::testing::AssertionResult AtLine(const std::string& msg, const fs::path& file, int line) {
  const std::string prefix = file.string() + ":" + std::to_string(line) + ": ";
  if (msg.rfind(prefix, 0) != 0)
    return ::testing::AssertionFailure() << "expected prefix '" << prefix << "' in: " << msg;
  if (msg.find("; ", prefix.size()) == std::string::npos)
    return ::testing::AssertionFailure() << "no '; <fix>' part in: " << msg;
  return ::testing::AssertionSuccess();
}

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

/// `msg` holds every one of `contains` and none of `lacks`.
void ExpectMessage(const std::string& msg, const std::vector<std::string>& contains,
                   const std::vector<std::string>& lacks = {}) {
  for (const auto& s : contains) EXPECT_TRUE(Contains(msg, s)) << "no '" << s << "' in: " << msg;
  for (const auto& s : lacks) EXPECT_FALSE(Contains(msg, s)) << "'" << s << "' in: " << msg;
}

/// An expected number of a table row: unchecked when empty, "is NaN" for NaN, else equal to
/// within `tol` (0: EXPECT_DOUBLE_EQ).
struct Num {
  std::optional<double> value;
  double tol = 0;
};
Num eq(double v) { return {v}; }
Num near(double v, double tol) { return {v, tol}; }
const Num kIsNaN{kNaN};

void ExpectNum(const char* what, double actual, const Num& e) {
  if (!e.value) return;
  if (std::isnan(*e.value))
    EXPECT_TRUE(std::isnan(actual)) << what << " = " << actual;
  else if (e.tol > 0)
    EXPECT_NEAR(actual, *e.value, e.tol) << what;
  else
    EXPECT_DOUBLE_EQ(actual, *e.value) << what;
}

/// `x` after `edit`: a table row's variation of a shared study or baseline case.
template <class T, class F>
T edited(T x, F&& edit) {
  edit(x);
  return x;
}

/// A valid case whose header is on the first line; `extra` lines (from line 6) follow `nodes`.
std::string a_case(const std::string& id, const std::string& extra = "") {
  return "[[case]]\n"
         "id = \"" + id + "\"\n"
         "problem = \"laplace-tanh\"\n"
         "method = \"fem\"\n"
         "nodes = [21, 41, 81]\n" + extra;
}

/// A case with the given `nodes` value on its fifth line.
std::string case_with_nodes(const std::string& nodes) {
  return "[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\nnodes = " + nodes + "\n";
}

/// A case with one [case.bands] line (line 7).
std::string a_band(const std::string& band) { return a_case("a", "[case.bands]\n" + band + "\n"); }

// ---------------------------------------------------------------------------------------------
// Parsing a valid manifest

using ManifestTest = Files;

const char* kValid =
    "[suite]\n"                                                      // 1
    "name = \"nightly\"\n"                                           // 2
    "description = \"nightly 1D verification\"\n"                   // 3
    "baseline = \"../baselines/nightly.toml\"\n"                     // 4
    "drift_tolerance = 0.1\n"                                        // 5
    "drift_floor = 1e-10\n"                                          // 6
    "\n"                                                             // 7
    "[[case]]\n"                                                     // 8
    "id = \"laplace-tanh/fem\"\n"                                    // 9
    "problem = \"laplace-tanh\"\n"                                   // 10
    "problem_params = { s = 10 }\n"                                  // 11
    "method = \"fem\"\n"                                             // 12
    "method_params = { quad = 10, exact = true, name = \"x\" }\n"    // 13
    "nodes = [21, 41, 81]\n"                                         // 14
    "full_nodes = [21, 41, 81, 161]\n"                               // 15
    "perturbation = 0.25\n"                                          // 16
    "labels = [\"fast\", \"fem\"]\n"                                 // 17
    "[case.bands]\n"                                                 // 18
    "l2_rate = [1.9, 2.1]\n"                                         // 19
    "h1_rate = [0.9, 1.1]\n"                                         // 20
    "l2_finest = [0.0, 2e-3]\n"                                      // 21
    "h1_finest = [0, 0.3]\n"                                         // 22
    "l2_rel_finest = [0.0, 1e-2]\n"                                  // 23
    "h1_rel_finest = [-inf, inf]\n"                                  // 24
    "headline = { \"peak du/dx at x=3\" = [9.7, 9.9] }\n"            // 25
    "\n"                                                             // 26
    "[[case]]\n"                                                     // 27
    "id = \"advection-diffusion/rkpm\"\n"                            // 28
    "problem = \"advection-diffusion\"\n"                            // 29
    "problem_params = { a = 0 }\n"                                   // 30
    "method = \"rkpm\"\n"                                            // 31
    "method_params = { kernel = \"gaussian\", j = 1, rule = \"eq6.10\" }\n"  // 32
    "nodes = [31, 61]\n";                                            // 33

TEST_F(ManifestTest, ValidManifestParsesEveryKey) {
  const fs::path p = write("suites/nightly-file.toml", kValid);
  const Manifest m = load_manifest(p);

  EXPECT_EQ(m.path, p);
  EXPECT_EQ(m.name, "nightly");
  EXPECT_EQ(m.description, "nightly 1D verification");
  EXPECT_EQ(fs::weakly_canonical(m.baseline),
            fs::weakly_canonical(dir_.path() / "baselines/nightly.toml"));
  EXPECT_EQ(m.baseline, p.parent_path() / "../baselines/nightly.toml");
  EXPECT_DOUBLE_EQ(m.drift_tolerance, 0.1);
  EXPECT_DOUBLE_EQ(m.drift_floor, 1e-10);
  ASSERT_EQ(m.cases.size(), 2u);

  const ManifestCase& a = m.cases[0];
  EXPECT_EQ(a.id, "laplace-tanh/fem");
  EXPECT_EQ(a.line, 8);
  EXPECT_EQ(a.problem, "laplace-tanh");
  EXPECT_EQ(a.method, "fem");
  EXPECT_DOUBLE_EQ(a.problem_params.number("s"), 10.0);
  EXPECT_EQ(a.problem_params.values().size(), 1u);
  EXPECT_EQ(a.method_params.integer("quad"), 10);
  EXPECT_EQ(a.method_params.text("exact"), "true");  // booleans become text
  EXPECT_EQ(a.method_params.text("name"), "x");
  EXPECT_EQ(a.method_params.values().size(), 3u);
  EXPECT_EQ(a.nodes, (std::vector<int>{21, 41, 81}));
  EXPECT_EQ(a.full_nodes, (std::vector<int>{21, 41, 81, 161}));
  EXPECT_DOUBLE_EQ(a.perturbation, 0.25);
  EXPECT_EQ(a.labels, (std::vector<std::string>{"fast", "fem"}));

  ASSERT_EQ(a.bands.size(), 6u);  // every 1D metric; energy bands: GoodManifests/EnergyBands
  const struct {
    const char* name;
    double low, high;
    int line;
  } expected[] = {{"l2_rate", 1.9, 2.1, 19},      {"h1_rate", 0.9, 1.1, 20},
                  {"l2_finest", 0.0, 2e-3, 21},   {"h1_finest", 0.0, 0.3, 22},
                  {"l2_rel_finest", 0.0, 1e-2, 23}, {"h1_rel_finest", -kInf, kInf, 24}};
  for (const auto& e : expected) {
    SCOPED_TRACE(e.name);
    ASSERT_EQ(a.bands.count(e.name), 1u);
    const Band& b = a.bands.at(e.name);
    EXPECT_EQ(b.low, e.low);
    EXPECT_EQ(b.high, e.high);
    EXPECT_EQ(b.line, e.line);
  }
  ASSERT_EQ(a.headline_bands.size(), 1u);
  const Band& h = a.headline_bands.at("peak du/dx at x=3");
  EXPECT_DOUBLE_EQ(h.low, 9.7);
  EXPECT_DOUBLE_EQ(h.high, 9.9);
  EXPECT_EQ(h.line, 25);

  const ManifestCase& b = m.cases[1];
  EXPECT_EQ(b.id, "advection-diffusion/rkpm");
  EXPECT_EQ(b.line, 27);
  EXPECT_EQ(b.problem, "advection-diffusion");
  EXPECT_DOUBLE_EQ(b.problem_params.number("a"), 0.0);
  EXPECT_EQ(b.method, "rkpm");
  EXPECT_EQ(b.method_params.text("kernel"), "gaussian");
  EXPECT_EQ(b.method_params.integer("j"), 1);
  EXPECT_EQ(b.method_params.text("rule"), "eq6.10");
  EXPECT_EQ(b.nodes, (std::vector<int>{31, 61}));
  EXPECT_EQ(b.full_nodes, b.nodes);  // default
  EXPECT_EQ(b.perturbation, 0.0);
  EXPECT_TRUE(b.labels.empty());
  EXPECT_TRUE(b.bands.empty());
  EXPECT_TRUE(b.headline_bands.empty());

  EXPECT_EQ(resolutions(a, false), a.nodes);
  EXPECT_EQ(resolutions(a, true), a.full_nodes);
  EXPECT_EQ(resolutions(b, true), b.nodes);
}

TEST_F(ManifestTest, AbsoluteBaselinePathIsKept) {
  const fs::path abs = dir_.path() / "elsewhere" / "b.toml";
  const fs::path p = write("sub/m.toml", "[suite]\nbaseline = \"" + abs.string() + "\"\n" +
                                             case_with_nodes("[21, 41]"));
  EXPECT_EQ(load_manifest(p).baseline, abs);
}

TEST_F(ManifestTest, ExampleManifestLoads) {
  const fs::path p = fs::path(MFV_SOURCE_DIR) / "suites" / "example.toml";
  ASSERT_TRUE(fs::exists(p)) << p;
  Manifest m;
  ASSERT_NO_THROW(m = load_manifest(p));
  EXPECT_FALSE(m.name.empty());
  EXPECT_FALSE(m.description.empty());
  EXPECT_FALSE(m.baseline.empty());
  EXPECT_GE(m.cases.size(), 2u);
  // The example exercises every key: every band metric, a headline band, both param tables,
  // full_nodes, perturbation, labels and expect appear somewhere.
  std::set<std::string> metrics;
  bool headline = false, problem_params = false, method_params = false, full_nodes = false,
       perturbation = false, labels = false, expect_unstable = false;
  for (const auto& c : m.cases) {
    expect_unstable |= c.expect_unstable;
    for (const auto& [name, band] : c.bands) metrics.insert(name);
    headline |= !c.headline_bands.empty();
    problem_params |= !c.problem_params.values().empty();
    method_params |= !c.method_params.values().empty();
    full_nodes |= c.full_nodes != c.nodes;
    perturbation |= c.perturbation > 0;
    labels |= !c.labels.empty();
  }
  EXPECT_EQ(metrics, std::set<std::string>(band_metrics().begin(), band_metrics().end()));
  EXPECT_TRUE(headline);
  EXPECT_TRUE(problem_params);
  EXPECT_TRUE(method_params);
  EXPECT_TRUE(full_nodes);
  EXPECT_TRUE(perturbation);
  EXPECT_TRUE(labels);
  EXPECT_TRUE(expect_unstable);
  EXPECT_NO_THROW(m.find("laplace-tanh/fem"));
  EXPECT_EQ(m.find("laplace-tanh/fem").headline_bands.count("peak du/dx at x=3"), 1u);
}

/// Issue 28: a miss names the near ids and how to list them all, never every id (a 388-case
/// manifest made one 4,837-character line).
TEST_F(ManifestTest, FindReturnsCaseOrNamesTheNearIds) {
  const Manifest m = load_manifest(write("m.toml", kValid));
  EXPECT_EQ(m.find("advection-diffusion/rkpm").problem, "advection-diffusion");
  ExpectMessage(error_of([&] { m.find("laplace-tanh/efg"); }),
                {"laplace-tanh/efg", "m.toml", "did you mean 'laplace-tanh/fem'", "2 cases",
                 "--list"},
                {"advection-diffusion/rkpm"});
  EXPECT_EQ(m.select("*/fem").size(), 1u);
  EXPECT_EQ(m.select("*").size(), 2u);
  ExpectMessage(error_of([&] { m.select("nothing/*"); }), {"the pattern 'nothing/*'", "2 cases"});
}

TEST(BandMetrics, NamesInReportOrder) {
  EXPECT_EQ(band_metrics(),
            (std::vector<std::string>{"l2_rate", "h1_rate", "l2_finest", "h1_finest",
                                      "l2_rel_finest", "h1_rel_finest", "energy_rate",
                                      "energy_rel_finest"}));
}

/// A small valid manifest and what it must parse to.
struct GoodManifest {
  std::string name, file, text;
  std::function<void(const Manifest&)> check;
};

using GoodManifests = TableTest<GoodManifest>;

TEST_P(GoodManifests, Parses) {
  const Manifest m = load_manifest(write(GetParam().file, GetParam().text));
  GetParam().check(m);
}

INSTANTIATE_TEST_SUITE_P(
    Manifest, GoodManifests,
    ::testing::Values(
        GoodManifest{"DefaultsWithoutSuiteTable", "my-suite.toml",
                     "[[case]]\nid = \"a\"\nproblem = \"laplace-tanh\"\nmethod = \"fem\"\n"
                     "nodes = [2, 3]\n",
                     [](const Manifest& m) {
                       EXPECT_EQ(m.name, "my-suite");  // the file stem
                       EXPECT_EQ(m.description, "");
                       EXPECT_TRUE(m.baseline.empty());
                       EXPECT_DOUBLE_EQ(m.drift_tolerance, 0.05);
                       EXPECT_DOUBLE_EQ(m.drift_floor, 1e-12);
                       ASSERT_EQ(m.cases.size(), 1u);
                       EXPECT_EQ(m.cases[0].full_nodes, m.cases[0].nodes);
                       EXPECT_TRUE(m.cases[0].problem_params.values().empty());
                       EXPECT_TRUE(m.cases[0].method_params.values().empty());
                     }},
        // An empty description and a zero drift_floor are allowed.
        GoodManifest{"SuiteNameDefaultsToStemWhenSuiteHasNoName", "weekly.toml",
                     "[suite]\ndescription = \"\"\ndrift_floor = 0\n" + case_with_nodes("[21]"),
                     [](const Manifest& m) {
                       EXPECT_EQ(m.name, "weekly");
                       EXPECT_EQ(m.drift_floor, 0.0);
                     }},
        GoodManifest{"EnergyBands", "e.toml",
                     "[suite]\nname = \"e\"\n[[case]]\nid = \"c\"\nproblem = \"cantilever\"\n"
                     "method = \"fem\"\nnodes = [5, 9]\n[case.bands]\n"
                     "energy_rate = [0.9, 1.2]\n"  // 9
                     "energy_rel_finest = [0.0, 0.1]\n",
                     [](const Manifest& m) {
                       ASSERT_EQ(m.cases.size(), 1u);
                       EXPECT_EQ(m.cases[0].bands.at("energy_rate").low, 0.9);
                       EXPECT_EQ(m.cases[0].bands.at("energy_rel_finest").high, 0.1);
                       EXPECT_EQ(m.cases[0].bands.at("energy_rate").line, 9);
                     }},
        GoodManifest{"ExpectUnstableOrStable", "m.toml",
                     a_case("a", "expect = \"unstable\"\n") +
                         a_case("b", "expect = \"stable\"\n") + a_case("c"),
                     [](const Manifest& m) {
                       EXPECT_TRUE(m.cases.at(0).expect_unstable);
                       EXPECT_FALSE(m.cases.at(1).expect_unstable);
                       EXPECT_FALSE(m.cases.at(2).expect_unstable);
                     }}),
    RowName());

// ---------------------------------------------------------------------------------------------
// Manifest errors: file, line, what, fix

/// A manifest that load_manifest refuses, the line its message names and what it says.
struct BadManifest {
  std::string name, text;
  int line;
  std::vector<std::string> contains;
  std::vector<std::string> lacks = {};
};

using BadManifests = TableTest<BadManifest>;

TEST_P(BadManifests, RefusedWithFileLineAndFix) {
  const fs::path p = write("m.toml", GetParam().text);
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, GetParam().line));
  ExpectMessage(msg, GetParam().contains, GetParam().lacks);
}

/// A manifest whose second case (header on line 7) lacks one required key.
std::string second_case(const std::string& text) { return a_case("first") + "\n" + text; }

/// A [suite] table with one `setting` (line 3).
std::string suite_with(const std::string& setting) {
  return "[suite]\nname = \"s\"\n" + setting + "\n" + a_case("a");
}

const std::vector<BadManifest> kBadManifests = {
    {"UnknownBandKeySuggestsTheClosest",
     a_case("a", "[case.bands]\nl2_rate = [1, 3]\nl2_rte = [1, 3]\n"), 8,
     {"unknown key 'l2_rte'", "did you mean 'l2_rate'?", "h1_rel_finest", "headline"}},
    {"UnknownCaseKey", a_case("a", "nodez_full = [1]\n"), 6,
     {"unknown key 'nodez_full'", "[[case]] 'a'"}},
    // Issue 26: a CTest label list is ';'-separated, so "a;b" would become two labels.
    {"LabelWithSemicolon", a_case("a", "labels = [\"fast;slow\"]\n"), 6,
     {"label 'fast;slow' is empty or holds ';' or white space"}},
    {"FullOnlyNotBoolean", a_case("a", "full_only = 1\n"), 6, {"'full_only' must be true or false"}},
    {"UnknownCaseKeySuggestsTheClosest", a_case("a", "perturbaton = 0.1\n"), 6,
     {"did you mean 'perturbation'?", "[[case]] 'a'"}},
    {"UnknownKeyWithoutCloseMatchListsValidKeys", "[suite]\ncolour = \"blue\"\n" + a_case("a"), 2,
     {"unknown key 'colour' in [suite]",
      "valid keys: name, description, baseline, drift_tolerance, drift_floor"},
     {"did you mean"}},
    {"UnknownTopLevelKey", a_case("a") + "[[cases]]\nid = \"b\"\n", 6,
     {"unknown key 'cases'", "did you mean 'case'?"}},
    {"MissingId", second_case("[[case]]\nproblem = \"p\"\nmethod = \"m\"\nnodes = [21, 41]\n"), 7,
     {"has no 'id'", "add the required key"}},
    {"MissingProblem", second_case("[[case]]\nid = \"a\"\nmethod = \"m\"\nnodes = [21, 41]\n"), 7,
     {"has no 'problem'", "add the required key"}},
    {"MissingMethod", second_case("[[case]]\nid = \"a\"\nproblem = \"p\"\nnodes = [21, 41]\n"), 7,
     {"has no 'method'", "add the required key"}},
    {"MissingNodes", second_case("[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"), 7,
     {"has no 'nodes'", "add the required key"}},
    {"NoCases", "[suite]\nname = \"x\"\n", 1, {"[[case]]"}},
    {"CaseMustBeArrayOfTables", "case = \"laplace\"\n", 1, {"array of tables"}},
    {"DuplicateId", a_case("same") + "\n" + a_case("other") + "\n" + a_case("same"), 13,
     {"duplicate case id 'same'", "line 1", "unique"}},
    {"IdWithSpace", "\n" + a_case("laplace tanh"), 3, {"white space"}},
    {"IdWithTab", "\n" + a_case("a\\tb"), 3, {"white space"}},
    {"IdWithLeadingSpace", "\n" + a_case(" lead"), 3, {"white space"}},
    {"EmptyId", a_case(""), 2, {"'id' is empty"}},
    {"WrongTypeNamesTheType",
     "[[case]]\nid = \"a\"\nproblem = 3\nmethod = \"m\"\nnodes = [21, 41]\n", 3,
     {"'problem' must be a string, got an integer"}},
    {"NodesNotIncreasing", case_with_nodes("[\n  21,\n  41,\n  41,\n]"), 8,  // the second 41
     {"'nodes' is not increasing (41 after 41)", "increasing integers >= 2"}},
    {"FullNodesDecreasing", a_case("a", "full_nodes = [81, 41]\n"), 6,
     {"'full_nodes' is not increasing (41 after 81)"}},
    {"NodesOne", "\n\n" + case_with_nodes("[1, 21]"), 7, {"not a node count >= 2"}},
    {"NodesZero", "\n\n" + case_with_nodes("[0]"), 7, {"not a node count >= 2"}},
    {"NodesNegative", "\n\n" + case_with_nodes("[-5, 21]"), 7, {"not a node count >= 2"}},
    {"NodesEmpty", case_with_nodes("[]"), 5, {"'nodes' is empty"}},
    {"NodesNotIntegers", case_with_nodes("[21, 41.0]"), 5,
     {"'nodes' must hold integers, got a number"}},
    {"NodesNotAnArray", case_with_nodes("21"), 5, {"'nodes' must be an array, got an integer"}},
    {"BandLowAboveHigh", a_case("a", "[case.bands]\nl2_rate = [1.9, 2.1]\nh1_rate = [1.1, 0.9]\n"),
     8, {"band 'h1_rate' has low 1.1 > high 0.9", "swap them"}},
    {"HeadlineBandLowAboveHigh", a_band("headline = { \"peak\" = [2, 1] }"), 7,
     {"peak", "low 2 > high 1"}},
    {"BandOfOneNumber", a_band("l2_finest = [0.1]"), 7, {"has 1 elements, not 2"}},
    {"BandOfThreeNumbers", a_band("l2_finest = [0, 1, 2]"), 7, {"has 3 elements, not 2"}},
    {"BandNotAnArray", a_band("l2_finest = 0.1"), 7, {"must be an array, got a number"}},
    {"BandOfAString", a_band("l2_finest = [0, \"x\"]"), 7, {"must hold two numbers"}},
    {"BandHoldsNan", a_band("l2_finest = [nan, 1]"), 7, {"holds nan"}},
    {"HeadlineNotATable", a_band("headline = [1, 2]"), 7, {"'headline' must be a table"}},
    // Every value of these is inf or NaN, which never pass.
    {"BandAdmitsOnlyInf", a_band("l2_finest = [inf, inf]"), 7, {"l2_finest"}},
    {"BandAdmitsOnlyMinusInf", a_band("l2_finest = [-inf, -inf]"), 7, {"l2_finest"}},
    {"BandFromNan", a_band("l2_finest = [nan, 1.0]"), 7, {"l2_finest"}},
    // Named at the case header (line 2 and 1).
    {"RateBandNeedsTwoResolutions",
     "\n" + case_with_nodes("[21]") + "[case.bands]\nl2_rate = [1, 3]\n",
     2, {"rate band", "at least two resolutions"}},
    {"RateBandNeedsTwoFullResolutions",
     a_case("a", "full_nodes = [81]\n[case.bands]\nh1_rate = [1, 3]\n"), 1,
     {"rate band", "at least two resolutions"}},
    {"TomlSyntaxError",
     "[[case]]\nid = \"a\"\nproblem = laplace-tanh\nmethod = \"m\"\nnodes = [21, 41]\n", 3,
     {"fix the TOML syntax"}},
    {"TomlSyntaxErrorDuplicateKey", a_case("a", "method = \"efg\"\n"), 6, {"TOML syntax"}},
    {"NegativePerturbation", a_case("a", "perturbation = -0.1\n"), 6,
     {"perturbation -0.1 is negative", ">= 0"}},
    {"InfinitePerturbation", a_case("a", "perturbation = inf\n"), 6, {"finite"}},
    {"DriftToleranceZero", suite_with("drift_tolerance = 0"), 3,
     {"drift_tolerance", "not positive"}},
    {"DriftToleranceZeroPointZero", suite_with("drift_tolerance = 0.0"), 3,
     {"drift_tolerance", "not positive"}},
    {"DriftToleranceNegative", suite_with("drift_tolerance = -0.05"), 3,
     {"drift_tolerance", "not positive"}},
    {"DriftFloorNegative", "[suite]\ndrift_floor = -1e-12\n" + a_case("a"), 2,
     {"drift_floor", "negative"}},
    {"ParameterOfUnsupportedType", a_case("a", "method_params = { list = [1, 2] }\n"), 6,
     {"parameter 'list' in 'method_params' is an array"}},
    {"ExpectOtherWord", a_case("a", "expect = \"blows up\"\n"), 6, {"expect"}},
    {"ExpectBoolean", a_case("a", "expect = true\n"), 6, {"expect"}},
};

INSTANTIATE_TEST_SUITE_P(Manifest, BadManifests, ::testing::ValuesIn(kBadManifests), RowName());

TEST_F(ManifestTest, TwoUnknownCaseKeysNameTheLineOfTheOneReported) {
  // Either key may be reported first (table order), but the line must match the key.
  const fs::path p = write("m.toml", a_case("a") + "nodez_full = [1]\n" + "perturbaton = 0.1\n");
  const std::string msg = manifest_error(p);
  if (Contains(msg, "perturbaton")) {
    EXPECT_TRUE(AtLine(msg, p, 7));
    ExpectMessage(msg, {"did you mean 'perturbation'?", "[[case]] 'a'"});
  } else {
    EXPECT_TRUE(AtLine(msg, p, 6));
    ExpectMessage(msg, {"unknown key 'nodez_full'", "[[case]] 'a'"});
  }
}

TEST_F(ManifestTest, MissingFileNamesThePath) {
  const fs::path p = dir_.path() / "no-such-manifest.toml";
  ExpectMessage(manifest_error(p),
                {p.string(), "cannot read manifest", std::strerror(ENOENT), "; "});
}

TEST_F(ManifestTest, ReadTextFileReadsWholeFileAndNamesMissingPath) {
  std::string big(20000, 'x');  // more than one read buffer
  big += "\nend";
  const fs::path p = write("text.txt", big);
  EXPECT_EQ(detail::read_text_file(p, "thing", "hint"), big);
  fs::remove(p);
  ExpectMessage(error_of([&] { detail::read_text_file(p, "thing", "do this"); }),
                {"cannot read thing " + p.string(), "; do this"});
}

/// Issue 26: manifests, baselines and ledgers must be regular files of bounded size; a FIFO
/// is refused at once (never waited on), a device or directory is named, and /dev/zero as a
/// baseline does not grow memory without bound.
TEST_F(ManifestTest, ReadTextFileRefusesSpecialAndHugeFiles) {
  const fs::path fifo = dir_.path() / "fifo.toml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  ExpectMessage(manifest_error(fifo), {fifo.string(), "a pipe (FIFO), not a regular file"});
  ExpectMessage(error_of([] { load_baseline("/dev/zero"); }),
                {"/dev/zero", "a character device, not a regular file"});
  ExpectMessage(error_of([&] { detail::read_text_file(dir_.path(), "ledger", "h"); }),
                {"a directory, not a regular file"});
  const fs::path huge = dir_.path() / "huge.toml";
  {
    std::ofstream out(huge, std::ios::binary);
    out.seekp(static_cast<std::streamoff>(detail::kMaxTextFileBytes));
    out.put('x');
  }
  ExpectMessage(manifest_error(huge), {"more than the 16 MiB a text input may have"});
}

// ---------------------------------------------------------------------------------------------
// check_bands

/// A 3-resolution study: L2 errors quarter and H1 errors halve per refinement (finest: l2
/// 2.5e-4, l2_rel 1.25e-4, h1 0.1, h1_rel 0.01); rates l2 = 2, h1 = 1.
StudyResult study(int resolutions = 3) {
  StudyResult s;
  s.label = "fem";
  const int nodes[] = {21, 41, 81};
  for (int i = 0; i < resolutions; ++i) {
    CaseResult r;
    r.spec.problem = "laplace-tanh";
    r.spec.method = "fem";
    r.spec.nodes = nodes[i];
    r.h = 6.0 / (nodes[i] - 1);
    const double f = std::pow(0.5, i);
    r.errors.l2 = 4e-3 * f * f;
    r.errors.l2_rel = 2e-3 * f * f;
    r.errors.h1_semi = 0.4 * f;
    r.errors.h1_semi_rel = 0.04 * f;
    r.headline["peak du/dx at x=3"] = 9.6 + 0.3 * i;  // 9.6, 9.9, 10.2
    r.headline["u at x=5"] = 0.5;
    s.cases.push_back(r);
  }
  s.rates.fitted["L2"] = 2.0;
  s.rates.fitted["H1-semi"] = 1.0;
  // A different paper-rule rate: check_bands must use the common rule.
  s.rates_paper.fitted["L2"] = 99;
  s.rates_paper.fitted["H1-semi"] = 99;
  return s;
}

// The bands that study() meets, but l2_rate (line 7), from line 8 on.
const std::string kOtherInsideBands =
    "h1_rate = [0.9, 1.1]\n"                                  // 8
    "l2_finest = [0.0, 2e-3]\n"                               // 9
    "h1_finest = [0.0, 0.3]\n"                                // 10
    "l2_rel_finest = [0.0, 1e-3]\n"                           // 11
    "h1_rel_finest = [0.0, 1e-2]\n"                           // 12
    "headline = { \"peak du/dx at x=3\" = [10.0, 10.5] }\n";  // 13
const std::string kInsideBands = "l2_rate = [1.9, 2.1]\n" + kOtherInsideBands;
// The first resolution is outside every _finest band, the last inside.
const std::string kFinestBands =
    "l2_finest = [0.0, 1.5e-3]\nh1_finest = [0.0, 0.15]\n"
    "l2_rel_finest = [0.0, 6e-4]\nh1_rel_finest = [0.0, 0.015]\n";  // 7 to 10
const std::string kUnknownHeadline = "headline = { \"peak du/dx at x=4\" = [9, 11] }\n";

struct ExpectedViolation {
  std::string metric;
  Num value;
  int line;  ///< the band's line in the manifest
  std::vector<std::string> contains = {}, lacks = {};
  Num low = {}, high = {};
};

/// [case.bands] lines of case "laplace-tanh/fem" (the first on line 7), a study and the
/// violations check_bands finds, in order.
struct BandCheck {
  std::string name, bands;
  StudyResult study;
  std::vector<ExpectedViolation> violations;
  std::string file = "bands.toml";  ///< the manifest name printed in messages
};

using BandChecks = TableTest<BandCheck>;

TEST_P(BandChecks, FindsTheViolations) {
  const BandCheck& r = GetParam();
  const Manifest m =
      load_manifest(write("bands.toml", a_case("laplace-tanh/fem", "[case.bands]\n" + r.bands)));
  const ManifestCase& c = m.cases.at(0);
  // One band a line, each headline table holding one.
  const auto lines = std::count(r.bands.begin(), r.bands.end(), '\n');
  const auto headlines = std::count(r.bands.begin(), r.bands.end(), '{');
  ASSERT_EQ(c.bands.size(), static_cast<std::size_t>(lines - headlines));
  ASSERT_EQ(c.headline_bands.size(), static_cast<std::size_t>(headlines));
  const auto v = check_bands(c, r.study, r.file);
  ASSERT_EQ(v.size(), r.violations.size()) << "first: " << (v.empty() ? "" : v[0].message);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const ExpectedViolation& e = r.violations[i];
    SCOPED_TRACE(e.metric);
    EXPECT_EQ(v[i].case_id, "laplace-tanh/fem");
    EXPECT_EQ(v[i].metric, e.metric);
    ExpectNum("value", v[i].value, e.value);
    EXPECT_EQ(v[i].band.line, e.line);
    ExpectNum("band.low", v[i].band.low, e.low);
    ExpectNum("band.high", v[i].band.high, e.high);
    ExpectMessage(v[i].message, e.contains, e.lacks);
  }
}

const std::string kPeak = "headline:peak du/dx at x=3";

const std::vector<BandCheck> kBandChecks = {
    {"InsideBandsGivesNoViolations", kInsideBands, study(), {}},
    {"BandEdgesAreInside",
     "l2_rate = [2.0, 2.0]\nl2_finest = [2.5e-4, 2.5e-4]\n"
     "headline = { \"peak du/dx at x=3\" = [10.2, 10.2] }\n",
     edited(study(), [](StudyResult& s) { s.cases.back().headline["peak du/dx at x=3"] = 10.2; }),
     {}},
    {"TightenedRateBandGivesOneViolation", "l2_rate = [2.05, 2.1]\n" + kOtherInsideBands,
     edited(study(), [](StudyResult& s) { s.rates.fitted["L2"] = 1.987654; }),
     {{"l2_rate", eq(1.987654), 7,
       {"laplace-tanh/fem", "l2_rate", "1.988", "suites/nightly.toml:7", "2.05"}, {}, eq(2.05),
       eq(2.1)}},
     "suites/nightly.toml"},
    {"UsesCommonRuleRates", "h1_rate = [0.9, 1.1]\n",
     edited(study(), [](StudyResult& s) { s.rates.fitted["H1-semi"] = 1.5; s.rates_paper.fitted["H1-semi"] = 1.0; }),
     {{"h1_rate", eq(1.5), 7}}},
    {"FinestMetricsUseTheLastResolution", kFinestBands, study(), {}},
    {"FinestMetricOutsideAtTheLastResolution", kFinestBands,
     edited(study(), [](StudyResult& s) { s.cases.back().errors.h1_semi_rel = 0.02; }),
     {{"h1_rel_finest", eq(0.02), 10, {"bands.toml:10"}}}},
    // --full adds a finer resolution; the _finest bands still apply to the last of `nodes`, 81.
    {"FullStudyChecksFinestBandsAtTheDefaultFinest", "l2_rel_finest = [1e-4, 6e-4]\n",
     edited(study(),
            [](StudyResult& s) {
              CaseResult finer = s.cases.back();
              finer.spec.nodes = 2 * 81;
              finer.errors.l2_rel = 1e-6;  // outside the band, but not where it applies
              s.cases.push_back(finer);
            }),
     {}},
    // "1.9" with 4 or 5 digits would contradict the message.
    {"PrintedValueIsVisiblyOutside", "l2_rate = [1.9, 2.1]\n",
     edited(study(), [](StudyResult& s) { s.rates.fitted["L2"] = 1.89996; }),
     {{"l2_rate", eq(1.89996), 7, {"1.89996"}, {"= 1.9 "}}}},
    // In band_metrics() order: h1_rate before l2_finest.
    {"NaNViolatesEvenAnUnboundedBand", "l2_finest = [-inf, inf]\nh1_rate = [-inf, inf]\n",
     edited(study(), [](StudyResult& s) { s.cases.back().errors.l2 = s.rates.fitted["H1-semi"] = kNaN; }),
     {{"h1_rate", kIsNaN, 8, {"laplace-tanh/fem", "not a number", "bands.toml:"}},
      {"l2_finest", kIsNaN, 7,
       {"laplace-tanh/fem", "not a number", "bands.toml:", "l2_finest", "bands.toml:7"}}}},
    {"NaNHeadlineViolates", "headline = { \"peak du/dx at x=3\" = [-inf, inf] }\n",
     edited(study(), [](StudyResult& s) { s.cases.back().headline["peak du/dx at x=3"] = kNaN; }),
     {{kPeak, kIsNaN, 7}}},
    {"InfiniteValueViolatesAnOpenBand",
     "l2_finest = [0.0, inf]\nheadline = { \"peak du/dx at x=3\" = [-inf, inf] }\n",
     edited(study(),
            [](StudyResult& s) {
              s.cases.back().errors.l2 = kInf;
              s.cases.back().headline["peak du/dx at x=3"] = -kInf;
            }),
     {{"l2_finest", eq(kInf), 7, {"outside the band"}}, {kPeak, eq(-kInf), 8}}},
    // The finest is 10.2; 9.9 is the middle resolution.
    {"HeadlineOutsideBand", "headline = { \"peak du/dx at x=3\" = [9.7, 9.9] }\n", study(),
     {{kPeak, near(10.2, 1e-12), 7, {"peak du/dx at x=3", "10.2", "bands.toml:7"}}}},
    {"UnknownHeadlineListsAvailableNames", kUnknownHeadline, study(),
     {{"headline:peak du/dx at x=4", kIsNaN, 7,
       {"peak du/dx at x=4", "not computed", "'peak du/dx at x=3'", "'u at x=5'",
        "bands.toml:7"}}}},
    {"UnknownHeadlineWithoutHeadlines", kUnknownHeadline,
     edited(study(), [](StudyResult& s) { s.cases.back().headline.clear(); }),
     {{"headline:peak du/dx at x=4", kIsNaN, 7, {"no headline quantities"}}}},
    // study(1) has rates 2 and 1 set, but they are meaningless.
    {"RatesNeedTwoResolutions", "l2_rate = [1.9, 2.1]\nh1_rate = [0.9, 1.1]\nl2_finest = [0, 1]\n",
     study(1),
     {{"l2_rate", kIsNaN, 7, {"at least 2 resolutions", "has 1", "bands.toml:7"}},
      {"h1_rate", kIsNaN, 8, {"at least 2 resolutions", "has 1", "bands.toml:8"}}}},
    {"EmptyStudyViolatesEveryBand", kInsideBands, StudyResult{},
     {{"l2_rate", kIsNaN, 7}, {"h1_rate", kIsNaN, 8}, {"l2_finest", kIsNaN, 9},
      {"h1_finest", kIsNaN, 10}, {"l2_rel_finest", kIsNaN, 11}, {"h1_rel_finest", kIsNaN, 12},
      {kPeak, kIsNaN, 13}}},
};

INSTANTIATE_TEST_SUITE_P(Manifest, BandChecks, ::testing::ValuesIn(kBandChecks), RowName());

// ---------------------------------------------------------------------------------------------
// Baseline

using BaselineTest = Files;

bool same_double(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

::testing::AssertionResult SameBaseline(const Baseline& a, const Baseline& b) {
  if (a.suite != b.suite)
    return ::testing::AssertionFailure() << "suite " << a.suite << " vs " << b.suite;
  if (a.machine != b.machine)
    return ::testing::AssertionFailure() << "machine " << a.machine << " vs " << b.machine;
  if (a.cases.size() != b.cases.size())
    return ::testing::AssertionFailure() << a.cases.size() << " vs " << b.cases.size() << " cases";
  for (const auto& [id, ca] : a.cases) {
    const auto it = b.cases.find(id);
    if (it == b.cases.end()) return ::testing::AssertionFailure() << "no case " << id;
    const BaselineCase& cb = it->second;
    if (!same_double(ca.l2_rate, cb.l2_rate) || !same_double(ca.h1_rate, cb.h1_rate))
      return ::testing::AssertionFailure() << id << ": rates differ";
    if (ca.resolutions.size() != cb.resolutions.size())
      return ::testing::AssertionFailure() << id << ": resolution counts differ";
    if (!same_double(ca.cpu_seconds, cb.cpu_seconds))
      return ::testing::AssertionFailure() << id << ": CPU seconds differ";
    for (std::size_t i = 0; i < ca.resolutions.size(); ++i) {
      const auto &x = ca.resolutions[i].headline, &y = cb.resolutions[i].headline;
      if (x.size() != y.size()) return ::testing::AssertionFailure() << id << ": headline counts differ";
      for (const auto& [k, v] : x)
        if (!y.contains(k) || !same_double(v, y.at(k)))
          return ::testing::AssertionFailure() << id << ": headline '" << k << "' differs";
    }
    for (std::size_t i = 0; i < ca.resolutions.size(); ++i) {
      const auto &x = ca.resolutions[i], &y = cb.resolutions[i];
      if (x.nodes != y.nodes || !same_double(x.l2, y.l2) || !same_double(x.h1, y.h1) ||
          !same_double(x.l2_rel, y.l2_rel) || !same_double(x.h1_rel, y.h1_rel))
        return ::testing::AssertionFailure() << id << ": resolution " << i << " differs";
    }
  }
  return ::testing::AssertionSuccess();
}

Baseline sample_baseline() {
  Baseline b;
  b.suite = "default";
  BaselineCase fem;
  fem.l2_rate = 2.0012345678901234;
  fem.h1_rate = 1.0 / 3.0;
  fem.resolutions = {{21, 0.1, 0.3, 1.0 / 7.0, 4.4e-2},
                     {41, 1e-300, 5e-324, 0.0, 2.0},
                     {81, 1.2345678901234567e-5, 123456789.0, 6.02214076e23, 1e-17}};
  b.cases["laplace-tanh/fem"] = fem;
  BaselineCase one;  // a single resolution: the rates are NaN
  one.l2_rate = kNaN;
  one.h1_rate = kNaN;
  one.resolutions = {{11, std::nextafter(0.1, 1.0), kNaN, 3.0, -0.0}};
  b.cases["advection-diffusion/rkpm \"quoted\""] = one;
  // Headlines and CPU: keys with quotes, Unicode and a control character survive.
  BaselineCase ring;
  ring.l2_rate = ring.h1_rate = kNaN;
  ring.resolutions = {{11, kNaN, kNaN, kNaN, kNaN, {{"σθθ vs 1D at 0.1 ms (of p)", 0.1234567890123456},
                                                     {"a \"quoted\" key\\", -3.0},
                                                     {"tab\there", 1e300},
                                                     {"not reached", kNaN}}},
                      {21, kNaN, kNaN, kNaN, kNaN, {}}};
  ring.cpu_seconds = 12.5;
  b.cases["ring/sph"] = ring;
  b.machine = machine_note("Some CPU @ 2.0GHz", 2, 2);
  return b;
}

TEST_F(BaselineTest, RoundTripIsExact) {
  const Baseline b = sample_baseline();
  const std::string text = baseline_to_toml(b);
  const Baseline r = load_baseline(write("baseline/default.toml", text));
  EXPECT_TRUE(SameBaseline(b, r));
  EXPECT_TRUE(std::isnan(r.cases.at("advection-diffusion/rkpm \"quoted\"").l2_rate));
  EXPECT_TRUE(std::isnan(r.cases.at("advection-diffusion/rkpm \"quoted\"").h1_rate));
  // Stable: writing what was read gives the same text.
  EXPECT_EQ(baseline_to_toml(r), text);
  // 17 significant digits.
  ExpectMessage(text, {"h1_rate = 0.33333333333333331\n", "[meta]", "suite = \"default\""});
  // Sorted ids: "advection..." before "laplace...".
  EXPECT_LT(text.find("advection-diffusion"), text.find("laplace-tanh/fem"));
}

TEST_F(BaselineTest, HeadlinesCpuAndMachineRoundTrip) {
  const Baseline b = sample_baseline();
  const std::string text = baseline_to_toml(b);
  ExpectMessage(text, {"machine = \"Some CPU @ 2.0GHz, 2 hardware threads, 2 OpenMP threads\"",
                       "cpu_seconds = 12.5\n", "[cases.\"ring/sph\".headline.11]\n",
                       "\"tab\\u0009here\" = 1.0000000000000001e+300\n", "\"not reached\" = \"nan\"\n"},
                {"headline.21"});
  const Baseline r = load_baseline(write("h.toml", text));
  EXPECT_TRUE(SameBaseline(b, r));
  EXPECT_EQ(baseline_to_toml(r), text);
  EXPECT_TRUE(std::isnan(r.cases.at("laplace-tanh/fem").cpu_seconds)) << "optional: not recorded";
}

TEST_F(BaselineTest, RoundTripThenCheckDriftIsClean) {
  const Baseline b = sample_baseline();
  const Baseline r = load_baseline(write("b.toml", baseline_to_toml(b)));
  for (const auto& [id, c] : b.cases)
    EXPECT_TRUE(check_drift(id, c, r.cases.at(id), 1e-15, 0).empty()) << id;
}

TEST_F(BaselineTest, LoadSortsResolutions) {
  const Baseline b = load_baseline(
      write("b.toml", "[cases.a]\nl2_rate = 2\nh1_rate = 1.0\nresolutions = [\n"
                      "  { nodes = 41, l2 = 1, h1 = 2, l2_rel = 3, h1_rel = 4 },\n"
                      "  { nodes = 21, l2 = 5, h1 = 6, l2_rel = 7, h1_rel = 8 },\n]\n"));
  EXPECT_EQ(b.suite, "");
  ASSERT_EQ(b.cases.count("a"), 1u);
  const BaselineCase& c = b.cases.at("a");
  EXPECT_EQ(c.l2_rate, 2.0);
  ASSERT_EQ(c.resolutions.size(), 2u);
  EXPECT_EQ(c.resolutions[0].nodes, 21);
  EXPECT_EQ(c.resolutions[0].h1_rel, 8.0);
  EXPECT_EQ(c.resolutions[1].nodes, 41);
  EXPECT_EQ(c.resolutions[1].l2, 1.0);
}

TEST_F(BaselineTest, MissingFileIsEmpty) {
  const Baseline b = load_baseline(dir_.path() / "not-yet" / "default.toml");
  EXPECT_TRUE(b.cases.empty());
  EXPECT_EQ(b.suite, "");
}

TEST_F(BaselineTest, TheNanStringIsNoValue) {
  const Baseline b = load_baseline(
      write("ok.toml", "[cases.a]\nl2_rate = \"nan\"\nh1_rate = 1.0\nresolutions = [\n"
                       "  { nodes = 21, l2 = 1, h1 = \"nan\", l2_rel = 3, h1_rel = 4 },\n]\n"));
  EXPECT_TRUE(std::isnan(b.cases.at("a").l2_rate));
  EXPECT_TRUE(std::isnan(b.cases.at("a").resolutions.at(0).h1));
}

TEST_F(BaselineTest, WriterRecordsInfAsNoValueSoTheFileLoads) {
  Baseline b;
  b.cases["a"] = BaselineCase{kInf, 1.0, {{21, kInf, -kInf, 1.0, 2.0}}};
  const Baseline r = load_baseline(write("b.toml", baseline_to_toml(b)));
  EXPECT_TRUE(std::isnan(r.cases.at("a").l2_rate));
  EXPECT_TRUE(std::isnan(r.cases.at("a").resolutions.at(0).l2));
  EXPECT_TRUE(std::isnan(r.cases.at("a").resolutions.at(0).h1));
}

TEST(BaselineFromStudy, RecordsRatesAndErrors) {
  StudyResult s;
  for (int n : {21, 41}) {
    CaseResult r;
    r.spec.nodes = n;
    r.errors.l2 = n * 1.0;
    r.errors.h1_semi = n * 2.0;
    r.errors.l2_rel = n * 3.0;
    r.errors.h1_semi_rel = n * 4.0;
    r.errors.h1 = -1;  // the full H1 norm is not recorded
    s.cases.push_back(r);
  }
  s.rates.fitted["L2"] = 2.5;
  s.rates.fitted["H1-semi"] = 1.5;
  s.rates_paper.fitted["L2"] = 9;
  const BaselineCase c = baseline_from_study(s);
  EXPECT_EQ(c.l2_rate, 2.5);
  EXPECT_EQ(c.h1_rate, 1.5);
  ASSERT_EQ(c.resolutions.size(), 2u);
  EXPECT_EQ(c.resolutions[1].nodes, 41);
  EXPECT_EQ(c.resolutions[1].l2, 41.0);
  EXPECT_EQ(c.resolutions[1].h1, 82.0);
  EXPECT_EQ(c.resolutions[1].l2_rel, 123.0);
  EXPECT_EQ(c.resolutions[1].h1_rel, 164.0);

  EXPECT_TRUE(c.resolutions[1].headline.empty());

  // Every headline but the computer's times and speeds; CPU of every resolution together.
  s.cases[0].headline = {{"period (s)", 0.25}, {"CPU per step (s)", 1e-3},
                         {"particle-steps per second", 1e6}, {"unstable", NAN}};
  s.cases[0].cpu.setup = 1;
  s.cases[1].cpu.solve = 2;
  const BaselineCase h = baseline_from_study(s);
  EXPECT_EQ(h.resolutions[0].headline.size(), 2u);
  EXPECT_EQ(h.resolutions[0].headline.at("period (s)"), 0.25);
  EXPECT_TRUE(std::isnan(h.resolutions[0].headline.at("unstable")));
  EXPECT_DOUBLE_EQ(h.cpu_seconds, 3.0);
  EXPECT_TRUE(is_timing_headline("set-up CPU (s)"));
  EXPECT_TRUE(is_timing_headline("CPU minutes"));
  EXPECT_TRUE(is_timing_headline("particle-steps/s")) << "the notched beam's throughput";
  EXPECT_FALSE(is_timing_headline("max speed (m/s)"));
  EXPECT_FALSE(is_timing_headline("half-drain time (s)"));

  s.cases.pop_back();
  const BaselineCase one = baseline_from_study(s);
  EXPECT_TRUE(std::isnan(one.l2_rate));
  EXPECT_TRUE(std::isnan(one.h1_rate));
  ASSERT_EQ(one.resolutions.size(), 1u);
}

/// A baseline that load_baseline refuses, the line its message names and what it says.
struct BadBaseline {
  std::string name, text;
  int line;
  std::string contains;
};

using BadBaselines = TableTest<BadBaseline>;

TEST_P(BadBaselines, RefusedWithFileLineAndFix) {
  const fs::path p = write("b.toml", GetParam().text);
  const std::string msg = baseline_error(p);
  EXPECT_TRUE(AtLine(msg, p, GetParam().line));
  ExpectMessage(msg, {GetParam().contains});
}

/// A baseline whose one resolution (line 5) has l2 = `value`.
std::string with_l2(const std::string& value) {
  return "[cases.a]\nl2_rate = 2.0\nh1_rate = 1.0\nresolutions = [\n  { nodes = 21, l2 = " +
         value + ", h1 = 2, l2_rel = 3, h1_rel = 4 },\n]\n";
}

INSTANTIATE_TEST_SUITE_P(
    Baseline, BadBaselines,
    ::testing::Values(
        BadBaseline{"SyntaxError", "[meta]\nsuite = \"x\"\n\n[cases.\"a\"]\nl2_rate = = 2\n", 5,
                    "--update-baseline"},
        BadBaseline{"MissingKey",
                    "[cases.\"a\"]\nl2_rate = 2.0\nh1_rate = 1.0\nresolutions = [\n"
                    "  { nodes = 21, l2 = 1, h1 = 2, l2_rel = 3, h1_rel = 4 },\n"
                    "  { nodes = 41, l2 = 1, h1 = 2, h1_rel = 4 },\n"  // 6: no l2_rel
                    "]\n",
                    6, "missing 'l2_rel'"},
        BadBaseline{"RateNotANumber",
                    "[cases.a]\nl2_rate = \"fast\"\nh1_rate = 1.0\nresolutions = []\n", 2,
                    "'l2_rate' must be a number"},
        BadBaseline{"NoResolutions", "[cases.a]\nl2_rate = 2.0\nh1_rate = 1.0\n", 1, "resolutions"},
        BadBaseline{"CaseNotATable", "[cases]\na = 3\n", 2, "'a' must be a table"},
        // A non-finite number is refused; the string "nan" is no value (TheNanStringIsNoValue).
        BadBaseline{"Inf", with_l2("inf"), 5, "not finite"},
        BadBaseline{"MinusInf", with_l2("-inf"), 5, "not finite"},
        BadBaseline{"Nan", with_l2("nan"), 5, "not finite"},
        BadBaseline{"PlusInf", with_l2("+inf"), 5, "not finite"},
        BadBaseline{"HeadlineNotByNodes", with_l2("1") + "\n[cases.a.headline.fine]\nx = 1\n", 8,
                    "must be a table named by a resolution's nodes"},
        BadBaseline{"HeadlineOfNoResolution", with_l2("1") + "\n[cases.a.headline.99]\nx = 1\n",
                    8, "names no resolution of the case"},
        BadBaseline{"HeadlineNotANumber", with_l2("1") + "\n[cases.a.headline.21]\nx = \"big\"\n",
                    9, "'x' must be a number"},
        BadBaseline{"CpuInf", with_l2("1") + "cpu_seconds = inf\n", 7, "not finite"}),
    RowName());

// ---------------------------------------------------------------------------------------------
// check_drift

BaselineCase drift_case() {
  BaselineCase c;
  c.l2_rate = 2.0;
  c.h1_rate = 1.0;
  c.resolutions = {{21, 1e-2, 1e-1, 1e-3, 1e-2}, {41, 2.5e-3, 5e-2, 2.5e-4, 5e-3}};
  return c;
}

struct ExpectedDrift {
  std::string metric;
  int nodes;
  bool worse;
  Num relative = {}, baseline = {}, current = {};
  std::vector<std::string> contains = {}, lacks = {};
};

/// A baseline, the current results and the drifts check_drift finds, in order.
struct DriftCheck {
  std::string name;
  BaselineCase baseline, current;
  std::vector<ExpectedDrift> drifts;
  std::string case_id = "a";
};

class DriftChecks : public ::testing::TestWithParam<DriftCheck> {};

TEST_P(DriftChecks, FindsTheDrifts) {
  const DriftCheck& r = GetParam();
  const auto d = check_drift(r.case_id, r.baseline, r.current, 0.05, 1e-12);
  ASSERT_EQ(d.size(), r.drifts.size()) << "first: " << (d.empty() ? "" : d[0].message);
  for (std::size_t i = 0; i < d.size(); ++i) {
    const ExpectedDrift& e = r.drifts[i];
    SCOPED_TRACE(e.metric + " at " + std::to_string(e.nodes));
    EXPECT_EQ(d[i].case_id, r.case_id);
    EXPECT_EQ(d[i].metric, e.metric);
    EXPECT_EQ(d[i].nodes, e.nodes);
    EXPECT_EQ(d[i].worse, e.worse) << d[i].message;
    ExpectNum("relative", d[i].relative, e.relative);
    ExpectNum("baseline", d[i].baseline, e.baseline);
    ExpectNum("current", d[i].current, e.current);
    ExpectMessage(d[i].message, e.contains, e.lacks);
  }
}

/// drift_case() after `edit`.
template <class F>
BaselineCase drifted(F&& edit) {
  return edited(drift_case(), edit);
}

/// NaN for l2 at 21 nodes and for l2_rate: check_drift compares NaN with NaN as equal.
BaselineCase nan_l2() {
  return drifted([](BaselineCase& c) { c.resolutions[0].l2 = c.l2_rate = kNaN; });
}

/// A current result with a non-finite l2 at 41 nodes and h1 rate.
BaselineCase non_finite(double bad) {
  return drifted([bad](BaselineCase& c) { c.resolutions[1].l2 = c.h1_rate = bad; });
}

const std::vector<DriftCheck> kDriftChecks = {
    {"IdenticalGivesNoDrift", drift_case(), drift_case(), {}},
    // |0.09| <= 0.05 * max(1, 2)
    {"SmallChangeWithinToleranceIsNoDrift", drift_case(),
     drifted([](BaselineCase& c) { c.resolutions[1].l2 *= 1.04; c.l2_rate = 2.09; }), {}},
    {"WorseErrorIsFlagged", drift_case(),
     drifted([](BaselineCase& c) { c.resolutions[1].l2 *= 1.10; }),
     {{"l2", 41, true, near(0.10, 1e-12), eq(2.5e-3), eq(2.75e-3),
       {"laplace-tanh/fem", "l2", "41", "worse"}}},
     "laplace-tanh/fem"},
    // relative = |cur - base| / |base|, as documented.
    {"BetterErrorIsFlaggedNotWorse", drift_case(),
     drifted([](BaselineCase& c) { c.resolutions[0].h1_rel *= 0.8; }),
     {{"h1_rel", 21, false, near(0.2, 1e-12), {}, {}, {"better", "--update-baseline"}}}},
    // A 700% change, but both below the floor.
    {"BothBelowFloorIsRoundOff", drifted([](BaselineCase& c) { c.resolutions[1].l2 = 1e-15; }),
     drifted([](BaselineCase& c) { c.resolutions[1].l2 = 8e-15; }), {}},
    {"OneAboveTheFloorDriftsRelativeToTheFloor",
     drifted([](BaselineCase& c) { c.resolutions[1].l2 = 1e-15; }),
     drifted([](BaselineCase& c) { c.resolutions[1].l2 = 2e-12; }),
     {{"l2", 41, true, near((2e-12 - 1e-15) / 1e-12, 1e-9)}}},
    // l2: |0.3| > 0.05 * 2, relative |1.7 - 2| / max(1, 2); h1 higher: better.
    {"LowerRateIsWorse", drift_case(),
     drifted([](BaselineCase& c) { c.l2_rate = 1.7; c.h1_rate = 1.2; }),
     {{"l2_rate", 0, true, near(0.15, 1e-12)}, {"h1_rate", 0, false, near(0.2, 1e-12)}}},
    {"NaNAgainstNumberIsWorse", drift_case(),
     drifted([](BaselineCase& c) { c.resolutions[0].l2 = kNaN; }),
     {{"l2", 21, true, {}, {}, kIsNaN}}},
    {"NaNAgainstNaNIsNoDrift", nan_l2(), nan_l2(), {}},
    {"NumberAgainstNaNIsADriftNotWorse", nan_l2(),
     edited(nan_l2(), [](BaselineCase& c) { c.l2_rate = 2.0; }), {{"l2_rate", 0, false}}},
    // 11 nodes only in the baseline, 81 new in this run.
    {"ResolutionInOnlyOneSide",
     drifted([](BaselineCase& c) {
       c.resolutions.insert(c.resolutions.begin(), {11, 1, 1, 1, 1});
     }),
     drifted([](BaselineCase& c) { c.resolutions.push_back({81, 6e-4, 2.5e-2, 6e-5, 2.5e-3}); }),
     {{"resolution", 11, false, {}, kIsNaN, kIsNaN,
       {"--update-baseline", "11 nodes", "in the baseline but not in this run"},
       {"run the baseline"}},
      {"resolution", 81, false, {}, kIsNaN, kIsNaN,
       {"--update-baseline", "81 nodes", "not in the baseline"}}}},
    {"InfCurrentAgainstAFiniteBaselineIsWorse", drift_case(), non_finite(kInf),
     {{"h1_rate", 0, true}, {"l2", 41, true}}},
    {"MinusInfCurrentAgainstAFiniteBaselineIsWorse", drift_case(), non_finite(-kInf),
     {{"h1_rate", 0, true}, {"l2", 41, true}}},
    {"NaNCurrentAgainstAFiniteBaselineIsWorse", drift_case(), non_finite(kNaN),
     {{"h1_rate", 0, true}, {"l2", 41, true}}},
    // As if read from a hand-edited file.
    {"InfiniteBaselineDoesNotSwitchTheCheckOff",
     drifted([](BaselineCase& c) { c.resolutions[0].l2 = kInf; }), drift_case(),
     {{"l2", 21, false}}},
    // Headlines: any move beyond the tolerance fails (no better direction); a lost one
    // fails, a new one only asks for an update; within the tolerance nothing.
    {"HeadlineMovesAreWorseEitherWay",
     drifted([](BaselineCase& c) {
       c.resolutions[0].headline = {{"period (s)", 0.25}, {"onset (ms)", 2.0}, {"gone", 1.0},
                                    {"steady", 10.0}};
     }),
     drifted([](BaselineCase& c) {
       c.resolutions[0].headline = {{"period (s)", 0.2}, {"onset (ms)", 2.2}, {"new", 3.0},
                                    {"steady", 10.4}};
     }),
     {{"headline: gone", 21, true, {}, eq(1.0), kIsNaN, {"not measured by this run"}},
      {"headline: new", 21, false, {}, kIsNaN, eq(3.0), {"--update-baseline"}},
      {"headline: onset (ms)", 21, true, near(0.1, 1e-12), eq(2.0), eq(2.2),
       {"+10.00% change", "explain it"}},
      {"headline: period (s)", 21, true, near(0.2, 1e-12), eq(0.25), eq(0.2),
       {"-20.00% change"}}}},
    {"HeadlineNaNAgainstAValueIsWorse",
     drifted([](BaselineCase& c) { c.resolutions[1].headline = {{"unstable at (ms)", kNaN}}; }),
     drifted([](BaselineCase& c) { c.resolutions[1].headline = {{"unstable at (ms)", 0.3}}; }),
     {{"headline: unstable at (ms)", 41, true}}},
    // CPU is judged only on the same machine: the default here is another one.
    {"CpuIsNotComparedAcrossMachines", drifted([](BaselineCase& c) { c.cpu_seconds = 1; }),
     drifted([](BaselineCase& c) { c.cpu_seconds = 100; }), {}},
};

// `lost` marks what --update-baseline must not overwrite: a number the baseline held that this
// run did not measure. A headline measured as NaN is a value, not a loss.
TEST(Drift, LostMeansTheBaselineHeldANumberThisRunDidNotMeasure) {
  const auto base = drifted([](BaselineCase& c) {
    c.resolutions[0].headline = {{"gone", 1.0}, {"unstable at (ms)", 0.3}};
  });
  const auto now = drifted([](BaselineCase& c) {
    c.resolutions[0].l2 = kNaN;
    c.resolutions[0].headline = {{"unstable at (ms)", kNaN}};
  });
  std::map<std::string, bool> lost;
  for (const Drift& d : check_drift("a", base, now, INFINITY, 0)) lost[d.metric] = d.lost;
  EXPECT_EQ(lost, (std::map<std::string, bool>{
                      {"l2", true}, {"headline: gone", true}, {"headline: unstable at (ms)", false}}));
  for (const Drift& d : check_drift("a", now, base, INFINITY, 0))
    EXPECT_FALSE(d.lost) << d.metric << ": a number where the baseline had none is not lost";
}

// CPU seconds are judged apart from the drift check, against the run's machine factor
// (tests/test_timing.cpp).
TEST(CpuDrift, IsNotTheDriftChecksBusiness) {
  auto cpu = [](double seconds) {
    return drifted([seconds](BaselineCase& c) { c.cpu_seconds = seconds; });
  };
  EXPECT_TRUE(check_drift("a", cpu(10), cpu(100), 0.05, 1e-12).empty());
}

INSTANTIATE_TEST_SUITE_P(Baseline, DriftChecks, ::testing::ValuesIn(kDriftChecks), RowName());

// ---------------------------------------------------------------------------------------------
// expect = "unstable" and check_stability

/// A transient study of two resolutions; `unstable_at` marks those that blew up.
StudyResult transient_study(std::vector<bool> unstable_at) {
  StudyResult s;
  int nodes = 121;
  for (bool u : unstable_at) {
    CaseResult r;
    r.spec.nodes = nodes;
    nodes = 2 * nodes - 1;
    r.data<TransientData>().steps = 100;
    r.data<TransientData>().end_time = 0.023;
    if (u) r.data<TransientData>().instability = TransientData::Instability{9, 0.0018, "kinetic energy 2.75"};
    s.cases.push_back(r);
  }
  return s;
}

/// A study without transient steps.
StudyResult static_study() {
  StudyResult s;
  s.cases.resize(2);
  return s;
}

/// A case, a study and the one failure check_stability reports, or none.
struct StabilityCheck {
  std::string name, id, problem;
  bool expect_unstable;
  StudyResult study;
  std::vector<std::string> failure = {};  ///< substrings of the failure; empty: none
};

class StabilityChecks : public ::testing::TestWithParam<StabilityCheck> {};

TEST_P(StabilityChecks, FailsWhenStabilityIsNotAsExpected) {
  const StabilityCheck& r = GetParam();
  ManifestCase c;
  c.id = r.id;
  c.problem = r.problem;
  c.expect_unstable = r.expect_unstable;
  const auto fails = check_stability(c, r.study);
  if (r.failure.empty()) {
    EXPECT_TRUE(fails.empty()) << fails.front();
  } else {
    ASSERT_EQ(fails.size(), 1u);
    ExpectMessage(fails[0], r.failure);
  }
}

const std::vector<StabilityCheck> kStabilityChecks = {
    {"UnstableRunFails", "rod-pulse/efg-ci", "rod-pulse", false, transient_study({false, true}),
     {"rod-pulse/efg-ci: 241 nodes: unstable at step 9, t = 0.0018"}},
    {"StableRunPasses", "rod-pulse/efg-ci", "rod-pulse", false, transient_study({false, false})},
    {"ExpectedInstabilityPasses", "rod-pulse/efg-ci", "rod-pulse", true,
     transient_study({true, true})},
    {"ExpectedInstabilityThatStaysStableFails", "grk-bar/grk-j0-courant1.35", "", true,
     transient_study({true, false}), {"241 nodes: expected unstable", "stayed stable"}},
    {"StaticProblemPasses", "laplace-tanh/fem", "laplace-tanh", false, static_study()},
    {"ExpectUnstableOnAStaticProblemIsReported", "laplace-tanh/fem", "laplace-tanh", true,
     static_study(), {"applies to transient runs"}},
};

INSTANTIATE_TEST_SUITE_P(Manifest, StabilityChecks, ::testing::ValuesIn(kStabilityChecks),
                         RowName());

}  // namespace
