// Unit tests of the verification manifest (verify/manifest.hpp) and the baseline file
// (verify/baseline.hpp): parsing, the "<file>:<line>: <what>; <fix>" errors, band checks and
// drift checks. No numerics: studies are built by hand.
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "methods/core/errors.hpp"
#include "verify/baseline.hpp"
#include "verify/manifest.hpp"

namespace fs = std::filesystem;
using namespace mfv;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

/// A fresh directory per test under the system temp dir, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("mfv_test_manifest_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) +
            "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// Writes `text` to dir/name and returns the path. Line 1 is the first line of `text`.
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << text;
    out.close();
    EXPECT_TRUE(out) << "cannot write " << p;
    return p;
  }

  /// The InputError message of load_manifest(p); a test failure if it does not throw one.
  static std::string manifest_error(const fs::path& p) {
    try {
      load_manifest(p);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "load_manifest(" << p << ") did not throw InputError";
    return {};
  }

  static std::string baseline_error(const fs::path& p) {
    try {
      load_baseline(p);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "load_baseline(" << p << ") did not throw InputError";
    return {};
  }

  fs::path dir_;
};

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

#define EXPECT_HAS(msg, needle) \
  EXPECT_TRUE(Contains((msg), (needle))) << "expected '" << (needle) << "' in: " << (msg)

// ---------------------------------------------------------------------------------------------
// Parsing a valid manifest

using ManifestTest = TempDirTest;

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
  EXPECT_EQ(fs::weakly_canonical(m.baseline), fs::weakly_canonical(dir_ / "baselines/nightly.toml"));
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

  ASSERT_EQ(a.bands.size(), 6u);  // every 1D metric; energy bands: EnergyBandsParse
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

TEST_F(ManifestTest, DefaultsWithoutSuiteTable) {
  const fs::path p = write("my-suite.toml",
                           "[[case]]\n"
                           "id = \"a\"\n"
                           "problem = \"laplace-tanh\"\n"
                           "method = \"fem\"\n"
                           "nodes = [2, 3]\n");
  const Manifest m = load_manifest(p);
  EXPECT_EQ(m.name, "my-suite");  // the file stem
  EXPECT_EQ(m.description, "");
  EXPECT_TRUE(m.baseline.empty());
  EXPECT_DOUBLE_EQ(m.drift_tolerance, 0.05);
  EXPECT_DOUBLE_EQ(m.drift_floor, 1e-12);
  ASSERT_EQ(m.cases.size(), 1u);
  EXPECT_EQ(m.cases[0].full_nodes, m.cases[0].nodes);
  EXPECT_TRUE(m.cases[0].problem_params.values().empty());
  EXPECT_TRUE(m.cases[0].method_params.values().empty());
}

TEST_F(ManifestTest, SuiteNameDefaultsToStemWhenSuiteHasNoName) {
  const fs::path p = write("weekly.toml",
                           "[suite]\n"
                           "description = \"\"\n"  // an empty description is allowed
                           "drift_floor = 0\n"     // >= 0 is allowed
                           "[[case]]\n"
                           "id = \"a\"\n"
                           "problem = \"p\"\n"
                           "method = \"m\"\n"
                           "nodes = [21]\n");
  const Manifest m = load_manifest(p);
  EXPECT_EQ(m.name, "weekly");
  EXPECT_EQ(m.drift_floor, 0.0);
}

TEST_F(ManifestTest, AbsoluteBaselinePathIsKept) {
  const fs::path abs = dir_ / "elsewhere" / "b.toml";
  const fs::path p = write("sub/m.toml", "[suite]\nbaseline = \"" + abs.string() +
                                             "\"\n[[case]]\nid = \"a\"\nproblem = \"p\"\n"
                                             "method = \"m\"\nnodes = [21, 41]\n");
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
  // full_nodes, perturbation and labels appear somewhere.
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

TEST_F(ManifestTest, FindReturnsCaseOrListsValidIds) {
  const Manifest m = load_manifest(write("m.toml", kValid));
  EXPECT_EQ(m.find("advection-diffusion/rkpm").problem, "advection-diffusion");
  try {
    m.find("laplace-tanh/efg");
    FAIL() << "find did not throw";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_HAS(msg, "laplace-tanh/efg");
    EXPECT_HAS(msg, "m.toml");
    EXPECT_HAS(msg, "laplace-tanh/fem");
    EXPECT_HAS(msg, "advection-diffusion/rkpm");
  }
}

TEST(BandMetrics, NamesInReportOrder) {
  EXPECT_EQ(band_metrics(),
            (std::vector<std::string>{"l2_rate", "h1_rate", "l2_finest", "h1_finest",
                                      "l2_rel_finest", "h1_rel_finest", "energy_rate",
                                      "energy_rel_finest"}));
}

TEST_F(ManifestTest, EnergyBandsParse) {
  const Manifest m = load_manifest(write("e.toml",
                                         "[suite]\nname = \"e\"\n[[case]]\nid = \"c\"\n"
                                         "problem = \"cantilever\"\nmethod = \"fem\"\n"
                                         "nodes = [5, 9]\n[case.bands]\n"
                                         "energy_rate = [0.9, 1.2]\n"
                                         "energy_rel_finest = [0.0, 0.1]\n"));
  ASSERT_EQ(m.cases.size(), 1u);
  EXPECT_EQ(m.cases[0].bands.at("energy_rate").low, 0.9);
  EXPECT_EQ(m.cases[0].bands.at("energy_rel_finest").high, 0.1);
  EXPECT_EQ(m.cases[0].bands.at("energy_rate").line, 9);
}

// ---------------------------------------------------------------------------------------------
// Manifest errors: file, line, what, fix

/// A valid case whose header is on line `first`; `extra` lines are appended after `nodes`.
std::string a_case(const std::string& id, const std::string& extra = "") {
  return "[[case]]\n"
         "id = \"" + id + "\"\n"
         "problem = \"laplace-tanh\"\n"
         "method = \"fem\"\n"
         "nodes = [21, 41, 81]\n" + extra;
}

TEST_F(ManifestTest, UnknownBandKeySuggestsTheClosest) {
  const fs::path p = write("typo.toml", a_case("a",
                                               "[case.bands]\n"      // 6
                                               "l2_rate = [1, 3]\n"  // 7
                                               "l2_rte = [1, 3]\n")); // 8
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 8));
  EXPECT_HAS(msg, "unknown key 'l2_rte'");
  EXPECT_HAS(msg, "did you mean 'l2_rate'?");
  EXPECT_HAS(msg, "h1_rel_finest");  // the valid keys are listed
  EXPECT_HAS(msg, "headline");
}

TEST_F(ManifestTest, UnknownCaseKeySuggestsTheClosest) {
  const fs::path p = write("m.toml", a_case("a") + "nodez_full = [1]\n" + "perturbaton = 0.1\n");
  const std::string msg = manifest_error(p);
  // Either key may be reported first (table order), but the line must match the key.
  if (Contains(msg, "perturbaton")) {
    EXPECT_TRUE(AtLine(msg, p, 7));
    EXPECT_HAS(msg, "did you mean 'perturbation'?");
  } else {
    EXPECT_TRUE(AtLine(msg, p, 6));
    EXPECT_HAS(msg, "unknown key 'nodez_full'");
  }
  EXPECT_HAS(msg, "[[case]] 'a'");
}

TEST_F(ManifestTest, UnknownKeyWithoutCloseMatchListsValidKeys) {
  const fs::path p = write("m.toml", "[suite]\n"
                                     "colour = \"blue\"\n" +
                                         a_case("a"));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 2));
  EXPECT_HAS(msg, "unknown key 'colour' in [suite]");
  EXPECT_FALSE(Contains(msg, "did you mean")) << msg;
  EXPECT_HAS(msg, "valid keys: name, description, baseline, drift_tolerance, drift_floor");
}

TEST_F(ManifestTest, UnknownTopLevelKey) {
  const fs::path p = write("m.toml", a_case("a") + "[[cases]]\nid = \"b\"\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "unknown key 'cases'");
  EXPECT_HAS(msg, "did you mean 'case'?");
}

TEST_F(ManifestTest, MissingRequiredKeys) {
  struct Missing {
    std::string key, text;
  };
  const std::vector<Missing> cases = {
      {"id", "[[case]]\nproblem = \"p\"\nmethod = \"m\"\nnodes = [21, 41]\n"},
      {"problem", "[[case]]\nid = \"a\"\nmethod = \"m\"\nnodes = [21, 41]\n"},
      {"method", "[[case]]\nid = \"a\"\nproblem = \"p\"\nnodes = [21, 41]\n"},
      {"nodes", "[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.key);
    // A valid first case so that the failing case's header is on line 7.
    const fs::path p = write("missing-" + c.key + ".toml", a_case("first") + "\n" + c.text);
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 7));
    EXPECT_HAS(msg, "has no '" + c.key + "'");
    EXPECT_HAS(msg, "add the required key");
  }
}

TEST_F(ManifestTest, NoCases) {
  const fs::path p = write("m.toml", "[suite]\nname = \"x\"\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 1));
  EXPECT_HAS(msg, "[[case]]");
}

TEST_F(ManifestTest, CaseMustBeArrayOfTables) {
  const fs::path p = write("m.toml", "case = \"laplace\"\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 1));
  EXPECT_HAS(msg, "array of tables");
}

TEST_F(ManifestTest, DuplicateId) {
  const fs::path p = write("dup.toml", a_case("same") + "\n" + a_case("other") + "\n" +
                                           a_case("same"));  // headers on lines 1, 7, 13
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 13));
  EXPECT_HAS(msg, "duplicate case id 'same'");
  EXPECT_HAS(msg, "line 1");
  EXPECT_HAS(msg, "unique");
}

TEST_F(ManifestTest, IdWithWhiteSpace) {
  for (const std::string id : {"laplace tanh", "a\\tb", " lead"}) {
    SCOPED_TRACE(id);
    const fs::path p = write("ws.toml", "\n" + a_case(id));
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 3));
    EXPECT_HAS(msg, "white space");
  }
}

TEST_F(ManifestTest, EmptyId) {
  const fs::path p = write("m.toml", a_case(""));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 2));
  EXPECT_HAS(msg, "'id' is empty");
}

TEST_F(ManifestTest, WrongTypeNamesTheType) {
  const fs::path p = write("m.toml", "[[case]]\nid = \"a\"\nproblem = 3\nmethod = \"m\"\n"
                                     "nodes = [21, 41]\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 3));
  EXPECT_HAS(msg, "'problem' must be a string, got an integer");
}

TEST_F(ManifestTest, NodesNotIncreasing) {
  const fs::path p = write("nodes.toml",
                           "[[case]]\n"
                           "id = \"a\"\n"
                           "problem = \"p\"\n"
                           "method = \"m\"\n"
                           "nodes = [\n"  // 5
                           "  21,\n"      // 6
                           "  41,\n"      // 7
                           "  41,\n"      // 8: the offending entry
                           "]\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 8));
  EXPECT_HAS(msg, "'nodes' is not increasing (41 after 41)");
  EXPECT_HAS(msg, "increasing integers >= 2");
}

TEST_F(ManifestTest, FullNodesDecreasing) {
  const fs::path p = write("m.toml", a_case("a", "full_nodes = [81, 41]\n"));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "'full_nodes' is not increasing (41 after 81)");
}

TEST_F(ManifestTest, NodesBelowTwo) {
  for (const std::string nodes : {"[1, 21]", "[0]", "[-5, 21]"}) {
    SCOPED_TRACE(nodes);
    const fs::path p = write("m.toml", "\n\n[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"
                                       "nodes = " + nodes + "\n");
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 7));
    EXPECT_HAS(msg, "not a node count >= 2");
  }
}

TEST_F(ManifestTest, NodesEmptyOrNotIntegers) {
  {
    const fs::path p = write("m.toml", "[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"
                                       "nodes = []\n");
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 5));
    EXPECT_HAS(msg, "'nodes' is empty");
  }
  {
    const fs::path p = write("m.toml", "[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"
                                       "nodes = [21, 41.0]\n");
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 5));
    EXPECT_HAS(msg, "'nodes' must hold integers, got a number");
  }
  {
    const fs::path p = write("m.toml", "[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"
                                       "nodes = 21\n");
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 5));
    EXPECT_HAS(msg, "'nodes' must be an array, got an integer");
  }
}

TEST_F(ManifestTest, BandLowAboveHigh) {
  const fs::path p = write("band.toml", a_case("a",
                                               "[case.bands]\n"          // 6
                                               "l2_rate = [1.9, 2.1]\n"  // 7
                                               "h1_rate = [1.1, 0.9]\n"  // 8
                                               ));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 8));
  EXPECT_HAS(msg, "band 'h1_rate' has low 1.1 > high 0.9");
  EXPECT_HAS(msg, "swap them");
}

TEST_F(ManifestTest, HeadlineBandLowAboveHigh) {
  const fs::path p = write("m.toml", a_case("a",
                                            "[case.bands]\n"
                                            "headline = { \"peak\" = [2, 1] }\n"));  // 7
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 7));
  EXPECT_HAS(msg, "peak");
  EXPECT_HAS(msg, "low 2 > high 1");
}

TEST_F(ManifestTest, MalformedBands) {
  const struct {
    const char* band;
    const char* expect;
  } cases[] = {{"l2_finest = [0.1]", "has 1 elements, not 2"},
               {"l2_finest = [0, 1, 2]", "has 3 elements, not 2"},
               {"l2_finest = 0.1", "must be an array, got a number"},
               {"l2_finest = [0, \"x\"]", "must hold two numbers"},
               {"l2_finest = [nan, 1]", "holds nan"},
               {"headline = [1, 2]", "'headline' must be a table"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.band);
    const fs::path p = write("m.toml", a_case("a", std::string("[case.bands]\n") + c.band + "\n"));
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 7));
    EXPECT_HAS(msg, c.expect);
  }
}

TEST_F(ManifestTest, RateBandNeedsTwoResolutions) {
  const fs::path p = write("m.toml", "\n[[case]]\nid = \"a\"\nproblem = \"p\"\nmethod = \"m\"\n"
                                     "nodes = [21]\n[case.bands]\nl2_rate = [1, 3]\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 2));
  EXPECT_HAS(msg, "rate band");
  EXPECT_HAS(msg, "at least two resolutions");

  // Also when only full_nodes has a single resolution.
  const fs::path q = write("m2.toml", a_case("a", "full_nodes = [81]\n[case.bands]\n"
                                                  "h1_rate = [1, 3]\n"));
  EXPECT_TRUE(AtLine(manifest_error(q), q, 1));
}

TEST_F(ManifestTest, TomlSyntaxError) {
  const fs::path p = write("syntax.toml",
                           "[[case]]\n"
                           "id = \"a\"\n"
                           "problem = laplace-tanh\n"  // 3: unquoted string
                           "method = \"m\"\n"
                           "nodes = [21, 41]\n");
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 3));
  EXPECT_HAS(msg, "fix the TOML syntax");
}

TEST_F(ManifestTest, TomlSyntaxErrorDuplicateKey) {
  const fs::path p = write("m.toml", a_case("a", "method = \"efg\"\n"));  // 6: 'method' again
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "TOML syntax");
}

TEST_F(ManifestTest, MissingFileNamesThePath) {
  const fs::path p = dir_ / "no-such-manifest.toml";
  const std::string msg = manifest_error(p);
  EXPECT_HAS(msg, p.string());
  EXPECT_HAS(msg, "cannot read manifest");
  EXPECT_HAS(msg, std::strerror(ENOENT));
  EXPECT_HAS(msg, "; ");
}

TEST(ReadTextFile, ReadsWholeFileAndNamesMissingPath) {
  const fs::path p = fs::temp_directory_path() /
                     ("mfv_read_text_" + std::to_string(::getpid()) + ".txt");
  std::string big(20000, 'x');  // more than one read buffer
  big += "\nend";
  {
    std::ofstream(p, std::ios::binary) << big;
  }
  EXPECT_EQ(detail::read_text_file(p, "thing", "hint"), big);
  fs::remove(p);
  try {
    detail::read_text_file(p, "thing", "do this");
    FAIL() << "no throw";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_HAS(msg, "cannot read thing " + p.string());
    EXPECT_HAS(msg, "; do this");
  }
}

TEST_F(ManifestTest, NegativePerturbation) {
  const fs::path p = write("m.toml", a_case("a", "perturbation = -0.1\n"));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "perturbation -0.1 is negative");
  EXPECT_HAS(msg, ">= 0");
}

TEST_F(ManifestTest, NonFinitePerturbation) {
  const fs::path p = write("m.toml", a_case("a", "perturbation = inf\n"));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "finite");
}

TEST_F(ManifestTest, DriftToleranceMustBePositive) {
  for (const std::string v : {"0", "0.0", "-0.05"}) {
    SCOPED_TRACE(v);
    const fs::path p = write("m.toml", "[suite]\nname = \"s\"\ndrift_tolerance = " + v + "\n" +
                                           a_case("a"));
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 3));
    EXPECT_HAS(msg, "drift_tolerance");
    EXPECT_HAS(msg, "not positive");
  }
}

TEST_F(ManifestTest, DriftFloorMustBeNonNegative) {
  const fs::path p = write("m.toml", "[suite]\ndrift_floor = -1e-12\n" + a_case("a"));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 2));
  EXPECT_HAS(msg, "drift_floor");
  EXPECT_HAS(msg, "negative");
}

TEST_F(ManifestTest, ParameterOfUnsupportedType) {
  const fs::path p = write("m.toml", a_case("a", "method_params = { list = [1, 2] }\n"));
  const std::string msg = manifest_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "parameter 'list' in 'method_params' is an array");
}

// ---------------------------------------------------------------------------------------------
// check_bands

class CheckBandsTest : public TempDirTest {
 protected:
  /// A 3-resolution study: L2 errors quarter and H1 errors halve per refinement (finest: l2
  /// 2.5e-4, l2_rel 1.25e-4, h1 0.1, h1_rel 0.01); rates l2 = 2, h1 = 1.
  static StudyResult study(int resolutions = 3) {
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
    s.rates.l2 = 2.0;
    s.rates.h1_semi = 1.0;
    // A different paper-rule rate: check_bands must use the common rule.
    s.rates_paper.l2 = 99;
    s.rates_paper.h1_semi = 99;
    return s;
  }

  /// A one-case manifest with the given [case.bands] lines (the first band on line 7) and
  /// its case.
  ManifestCase with_bands(const std::string& bands) {
    file_ = write("bands.toml", a_case("laplace-tanh/fem", "[case.bands]\n" + bands));
    manifest_ = load_manifest(file_);
    return manifest_.cases.at(0);
  }

  fs::path file_;
  Manifest manifest_;
};

const char* kInsideBands =
    "l2_rate = [1.9, 2.1]\n"                            // 7
    "h1_rate = [0.9, 1.1]\n"                            // 8
    "l2_finest = [0.0, 2e-3]\n"                         // 9
    "h1_finest = [0.0, 0.3]\n"                          // 10
    "l2_rel_finest = [0.0, 1e-3]\n"                     // 11
    "h1_rel_finest = [0.0, 1e-2]\n"                     // 12
    "headline = { \"peak du/dx at x=3\" = [10.0, 10.5] }\n";  // 13

TEST_F(CheckBandsTest, InsideBandsGivesNoViolations) {
  const ManifestCase c = with_bands(kInsideBands);
  ASSERT_EQ(c.bands.size(), 6u);
  const auto v = check_bands(c, study(), "bands.toml");
  EXPECT_TRUE(v.empty()) << v.size() << " violations, first: " << (v.empty() ? "" : v[0].message);
}

TEST_F(CheckBandsTest, BandEdgesAreInside) {
  const ManifestCase c = with_bands("l2_rate = [2.0, 2.0]\nl2_finest = [2.5e-4, 2.5e-4]\n"
                                    "headline = { \"peak du/dx at x=3\" = [10.2, 10.2] }\n");
  StudyResult s = study();
  s.cases.back().headline["peak du/dx at x=3"] = 10.2;
  const auto v = check_bands(c, s, "bands.toml");
  EXPECT_TRUE(v.empty()) << v.size() << " violations, first: " << (v.empty() ? "" : v[0].message);
}

TEST_F(CheckBandsTest, TightenedRateBandGivesOneViolation) {
  ManifestCase c = with_bands(kInsideBands);
  c.bands["l2_rate"].low = 2.05;  // the measured 2.0 is now below the band
  StudyResult s = study();
  s.rates.l2 = 1.987654;
  const auto v = check_bands(c, s, "suites/nightly.toml");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].case_id, "laplace-tanh/fem");
  EXPECT_EQ(v[0].metric, "l2_rate");
  EXPECT_DOUBLE_EQ(v[0].value, 1.987654);
  EXPECT_DOUBLE_EQ(v[0].band.low, 2.05);
  EXPECT_DOUBLE_EQ(v[0].band.high, 2.1);
  EXPECT_EQ(v[0].band.line, 7);
  EXPECT_HAS(v[0].message, "laplace-tanh/fem");
  EXPECT_HAS(v[0].message, "l2_rate");
  EXPECT_HAS(v[0].message, "1.988");
  EXPECT_HAS(v[0].message, "suites/nightly.toml:7");
  EXPECT_HAS(v[0].message, "2.05");
}

TEST_F(CheckBandsTest, UsesCommonRuleRates) {
  const ManifestCase c = with_bands("h1_rate = [0.9, 1.1]\n");
  StudyResult s = study();
  s.rates.h1_semi = 1.5;
  s.rates_paper.h1_semi = 1.0;
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].metric, "h1_rate");
  EXPECT_DOUBLE_EQ(v[0].value, 1.5);
}

TEST_F(CheckBandsTest, FinestMetricsUseTheLastResolution) {
  // The first resolution is outside every _finest band, the last inside: no violations.
  const ManifestCase c = with_bands("l2_finest = [0.0, 1.5e-3]\nh1_finest = [0.0, 0.15]\n"
                                    "l2_rel_finest = [0.0, 6e-4]\nh1_rel_finest = [0.0, 0.015]\n");
  EXPECT_TRUE(check_bands(c, study(), "bands.toml").empty());

  StudyResult s = study();
  s.cases.back().errors.h1_semi_rel = 0.02;
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].metric, "h1_rel_finest");
  EXPECT_DOUBLE_EQ(v[0].value, 0.02);
  EXPECT_EQ(v[0].band.line, 10);
  EXPECT_HAS(v[0].message, "bands.toml:10");
}

TEST_F(CheckBandsTest, FullStudyChecksFinestBandsAtTheDefaultFinest) {
  // --full adds a finer resolution; the _finest bands still apply to the last of `nodes`.
  const ManifestCase c = with_bands("l2_rel_finest = [1e-4, 6e-4]\n");
  StudyResult s = study();
  ASSERT_EQ(s.cases.back().spec.nodes, c.nodes.back());
  CaseResult finer = s.cases.back();
  finer.spec.nodes = 2 * c.nodes.back();
  finer.errors.l2_rel = 1e-6;  // outside the band, but not the resolution it was written for
  s.cases.push_back(finer);
  EXPECT_TRUE(check_bands(c, s, "bands.toml").empty());
}

TEST_F(CheckBandsTest, PrintedValueIsVisiblyOutside) {
  const ManifestCase c = with_bands("l2_rate = [1.9, 2.1]\n");
  StudyResult s = study();
  s.rates.l2 = 1.89996;  // "1.9" with 4 or 5 digits would contradict the message
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_HAS(v[0].message, "1.89996");
  EXPECT_FALSE(Contains(v[0].message, "= 1.9 ")) << v[0].message;
}

TEST_F(CheckBandsTest, NaNViolatesEvenAnUnboundedBand) {
  const ManifestCase c = with_bands("l2_finest = [-inf, inf]\nh1_rate = [-inf, inf]\n");
  StudyResult s = study();
  s.cases.back().errors.l2 = kNaN;
  s.rates.h1_semi = kNaN;
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 2u);
  // band_metrics() order: h1_rate before l2_finest.
  EXPECT_EQ(v[0].metric, "h1_rate");
  EXPECT_EQ(v[1].metric, "l2_finest");
  for (const auto& x : v) {
    EXPECT_TRUE(std::isnan(x.value));
    EXPECT_HAS(x.message, "laplace-tanh/fem");
    EXPECT_HAS(x.message, "not a number");
    EXPECT_HAS(x.message, "bands.toml:");
  }
  EXPECT_HAS(v[1].message, "l2_finest");
  EXPECT_HAS(v[1].message, "bands.toml:7");
}

TEST_F(CheckBandsTest, NaNHeadlineViolates) {
  const ManifestCase c = with_bands("headline = { \"peak du/dx at x=3\" = [-inf, inf] }\n");
  StudyResult s = study();
  s.cases.back().headline["peak du/dx at x=3"] = kNaN;
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].metric, "headline:peak du/dx at x=3");
  EXPECT_TRUE(std::isnan(v[0].value));
}

TEST_F(CheckBandsTest, HeadlineOutsideBand) {
  const ManifestCase c = with_bands("headline = { \"peak du/dx at x=3\" = [9.7, 9.9] }\n");
  const auto v = check_bands(c, study(), "bands.toml");  // finest: 10.2 (9.9 is the middle)
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].metric, "headline:peak du/dx at x=3");
  EXPECT_NEAR(v[0].value, 10.2, 1e-12);
  EXPECT_HAS(v[0].message, "peak du/dx at x=3");
  EXPECT_HAS(v[0].message, "10.2");
  EXPECT_HAS(v[0].message, "bands.toml:7");
}

TEST_F(CheckBandsTest, UnknownHeadlineListsAvailableNames) {
  const ManifestCase c = with_bands("headline = { \"peak du/dx at x=4\" = [9, 11] }\n");
  const auto v = check_bands(c, study(), "bands.toml");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].case_id, "laplace-tanh/fem");
  EXPECT_EQ(v[0].metric, "headline:peak du/dx at x=4");
  EXPECT_TRUE(std::isnan(v[0].value));
  EXPECT_HAS(v[0].message, "peak du/dx at x=4");
  EXPECT_HAS(v[0].message, "not computed");
  EXPECT_HAS(v[0].message, "'peak du/dx at x=3'");
  EXPECT_HAS(v[0].message, "'u at x=5'");
  EXPECT_HAS(v[0].message, "bands.toml:7");

  StudyResult none = study();
  none.cases.back().headline.clear();
  const auto w = check_bands(c, none, "bands.toml");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_HAS(w[0].message, "no headline quantities");
}

TEST_F(CheckBandsTest, RatesNeedTwoResolutions) {
  const ManifestCase c = with_bands("l2_rate = [1.9, 2.1]\nh1_rate = [0.9, 1.1]\n"
                                    "l2_finest = [0, 1]\n");
  const StudyResult s = study(1);  // rates 2 and 1 are set but meaningless
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].metric, "l2_rate");
  EXPECT_EQ(v[1].metric, "h1_rate");
  for (const auto& x : v) {
    EXPECT_TRUE(std::isnan(x.value));
    EXPECT_HAS(x.message, "at least 2 resolutions");
    EXPECT_HAS(x.message, "has 1");
  }
  EXPECT_HAS(v[0].message, "bands.toml:7");
  EXPECT_HAS(v[1].message, "bands.toml:8");
}

TEST_F(CheckBandsTest, EmptyStudyViolatesEveryBand) {
  const ManifestCase c = with_bands(kInsideBands);
  const auto v = check_bands(c, StudyResult{}, "bands.toml");
  EXPECT_EQ(v.size(), 7u);
  for (const auto& x : v) EXPECT_TRUE(std::isnan(x.value)) << x.metric;
}

// ---------------------------------------------------------------------------------------------
// Baseline

using BaselineTest = TempDirTest;

bool same_double(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

::testing::AssertionResult SameBaseline(const Baseline& a, const Baseline& b) {
  if (a.suite != b.suite)
    return ::testing::AssertionFailure() << "suite " << a.suite << " vs " << b.suite;
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
  return b;
}

TEST_F(BaselineTest, RoundTripIsExact) {
  const Baseline b = sample_baseline();
  const std::string text = baseline_to_toml(b);
  const fs::path p = write("baseline/default.toml", text);
  const Baseline r = load_baseline(p);
  EXPECT_TRUE(SameBaseline(b, r));
  EXPECT_TRUE(std::isnan(r.cases.at("advection-diffusion/rkpm \"quoted\"").l2_rate));
  EXPECT_TRUE(std::isnan(r.cases.at("advection-diffusion/rkpm \"quoted\"").h1_rate));
  // Stable: writing what was read gives the same text.
  EXPECT_EQ(baseline_to_toml(r), text);
  EXPECT_HAS(text, "h1_rate = 0.33333333333333331\n");  // 17 significant digits
  EXPECT_HAS(text, "[meta]");
  EXPECT_HAS(text, "suite = \"default\"");
  // Sorted ids: "advection..." before "laplace...".
  EXPECT_LT(text.find("advection-diffusion"), text.find("laplace-tanh/fem"));
}

TEST_F(BaselineTest, LoadSortsResolutions) {
  const fs::path p = write("b.toml",
                           "[cases.a]\nl2_rate = 2\nh1_rate = 1.0\nresolutions = [\n"
                           "  { nodes = 41, l2 = 1, h1 = 2, l2_rel = 3, h1_rel = 4 },\n"
                           "  { nodes = 21, l2 = 5, h1 = 6, l2_rel = 7, h1_rel = 8 },\n"
                           "]\n");
  const Baseline b = load_baseline(p);
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
  const Baseline b = load_baseline(dir_ / "not-yet" / "default.toml");
  EXPECT_TRUE(b.cases.empty());
  EXPECT_EQ(b.suite, "");
}

TEST_F(BaselineTest, SyntaxErrorNamesFileAndLine) {
  const fs::path p = write("b.toml", "[meta]\nsuite = \"x\"\n\n[cases.\"a\"]\nl2_rate = = 2\n");
  const std::string msg = baseline_error(p);
  EXPECT_TRUE(AtLine(msg, p, 5));
  EXPECT_HAS(msg, "--update-baseline");
}

TEST_F(BaselineTest, MissingKeyNamesFileAndLine) {
  const fs::path p = write("b.toml",
                           "[cases.\"a\"]\n"
                           "l2_rate = 2.0\n"
                           "h1_rate = 1.0\n"
                           "resolutions = [\n"
                           "  { nodes = 21, l2 = 1, h1 = 2, l2_rel = 3, h1_rel = 4 },\n"
                           "  { nodes = 41, l2 = 1, h1 = 2, h1_rel = 4 },\n"  // 6: no l2_rel
                           "]\n");
  const std::string msg = baseline_error(p);
  EXPECT_TRUE(AtLine(msg, p, 6));
  EXPECT_HAS(msg, "missing 'l2_rel'");
}

TEST_F(BaselineTest, MalformedValuesNameFileAndLine) {
  {
    const fs::path p = write("b1.toml", "[cases.a]\nl2_rate = \"fast\"\nh1_rate = 1.0\n"
                                        "resolutions = []\n");
    const std::string msg = baseline_error(p);
    EXPECT_TRUE(AtLine(msg, p, 2));
    EXPECT_HAS(msg, "'l2_rate' must be a number");
  }
  {
    const fs::path p = write("b2.toml", "[cases.a]\nl2_rate = 2.0\nh1_rate = 1.0\n");
    const std::string msg = baseline_error(p);
    EXPECT_TRUE(AtLine(msg, p, 1));
    EXPECT_HAS(msg, "resolutions");
  }
  {
    const fs::path p = write("b3.toml", "[cases]\na = 3\n");
    const std::string msg = baseline_error(p);
    EXPECT_TRUE(AtLine(msg, p, 2));
    EXPECT_HAS(msg, "'a' must be a table");
  }
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
  s.rates.l2 = 2.5;
  s.rates.h1_semi = 1.5;
  s.rates_paper.l2 = 9;
  const BaselineCase c = baseline_from_study(s);
  EXPECT_EQ(c.l2_rate, 2.5);
  EXPECT_EQ(c.h1_rate, 1.5);
  ASSERT_EQ(c.resolutions.size(), 2u);
  EXPECT_EQ(c.resolutions[1].nodes, 41);
  EXPECT_EQ(c.resolutions[1].l2, 41.0);
  EXPECT_EQ(c.resolutions[1].h1, 82.0);
  EXPECT_EQ(c.resolutions[1].l2_rel, 123.0);
  EXPECT_EQ(c.resolutions[1].h1_rel, 164.0);

  s.cases.pop_back();
  const BaselineCase one = baseline_from_study(s);
  EXPECT_TRUE(std::isnan(one.l2_rate));
  EXPECT_TRUE(std::isnan(one.h1_rate));
  ASSERT_EQ(one.resolutions.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// check_drift

BaselineCase drift_case() {
  BaselineCase c;
  c.l2_rate = 2.0;
  c.h1_rate = 1.0;
  c.resolutions = {{21, 1e-2, 1e-1, 1e-3, 1e-2}, {41, 2.5e-3, 5e-2, 2.5e-4, 5e-3}};
  return c;
}

TEST(CheckDrift, IdenticalGivesNoDrift) {
  EXPECT_TRUE(check_drift("a", drift_case(), drift_case(), 0.05, 1e-12).empty());
}

TEST(CheckDrift, SmallChangeWithinToleranceIsNoDrift) {
  BaselineCase cur = drift_case();
  cur.resolutions[1].l2 *= 1.04;
  cur.l2_rate = 2.09;  // |0.09| <= 0.05 * max(1, 2)
  EXPECT_TRUE(check_drift("a", drift_case(), cur, 0.05, 1e-12).empty());
}

TEST(CheckDrift, WorseErrorIsFlagged) {
  BaselineCase cur = drift_case();
  cur.resolutions[1].l2 *= 1.10;
  const auto d = check_drift("laplace-tanh/fem", drift_case(), cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].case_id, "laplace-tanh/fem");
  EXPECT_EQ(d[0].metric, "l2");
  EXPECT_EQ(d[0].nodes, 41);
  EXPECT_DOUBLE_EQ(d[0].baseline, 2.5e-3);
  EXPECT_DOUBLE_EQ(d[0].current, 2.75e-3);
  EXPECT_NEAR(d[0].relative, 0.10, 1e-12);
  EXPECT_TRUE(d[0].worse);
  EXPECT_HAS(d[0].message, "laplace-tanh/fem");
  EXPECT_HAS(d[0].message, "l2");
  EXPECT_HAS(d[0].message, "41");
  EXPECT_HAS(d[0].message, "worse");
}

TEST(CheckDrift, BetterErrorIsFlaggedNotWorse) {
  BaselineCase cur = drift_case();
  cur.resolutions[0].h1_rel *= 0.8;
  const auto d = check_drift("a", drift_case(), cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].metric, "h1_rel");
  EXPECT_EQ(d[0].nodes, 21);
  EXPECT_FALSE(d[0].worse);
  EXPECT_NEAR(d[0].relative, 0.2, 1e-12);  // |cur - base| / |base|, as documented
  EXPECT_HAS(d[0].message, "better");
  EXPECT_HAS(d[0].message, "--update-baseline");
}

TEST(CheckDrift, BothBelowFloorIsRoundOff) {
  BaselineCase base = drift_case(), cur = drift_case();
  base.resolutions[1].l2 = 1e-15;
  cur.resolutions[1].l2 = 8e-15;  // 700% change, but both below the floor
  EXPECT_TRUE(check_drift("a", base, cur, 0.05, 1e-12).empty());
  // One above the floor: a drift, relative to the floor.
  cur.resolutions[1].l2 = 2e-12;
  const auto d = check_drift("a", base, cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].metric, "l2");
  EXPECT_TRUE(d[0].worse);
  EXPECT_NEAR(d[0].relative, (2e-12 - 1e-15) / 1e-12, 1e-9);
}

TEST(CheckDrift, LowerRateIsWorse) {
  BaselineCase cur = drift_case();
  cur.l2_rate = 1.7;  // |0.3| > 0.05 * 2
  cur.h1_rate = 1.2;  // higher: better
  const auto d = check_drift("a", drift_case(), cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].metric, "l2_rate");
  EXPECT_EQ(d[0].nodes, 0);
  EXPECT_TRUE(d[0].worse);
  EXPECT_NEAR(d[0].relative, 0.15, 1e-12);  // |1.7 - 2| / max(1, 2)
  EXPECT_EQ(d[1].metric, "h1_rate");
  EXPECT_FALSE(d[1].worse);
  EXPECT_NEAR(d[1].relative, 0.2, 1e-12);
}

TEST(CheckDrift, NaNAgainstNumberIsDrift) {
  BaselineCase base = drift_case(), cur = drift_case();
  cur.resolutions[0].l2 = kNaN;
  auto d = check_drift("a", base, cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].metric, "l2");
  EXPECT_TRUE(d[0].worse);
  EXPECT_TRUE(std::isnan(d[0].current));

  base.resolutions[0].l2 = kNaN;  // NaN against NaN: no drift
  base.l2_rate = cur.l2_rate = kNaN;
  EXPECT_TRUE(check_drift("a", base, cur, 0.05, 1e-12).empty());

  cur.l2_rate = 2.0;  // a number where the baseline has NaN: a drift, not worse
  d = check_drift("a", base, cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].metric, "l2_rate");
  EXPECT_FALSE(d[0].worse);
}

TEST(CheckDrift, ResolutionInOnlyOneSide) {
  BaselineCase cur = drift_case();
  cur.resolutions.push_back({81, 6e-4, 2.5e-2, 6e-5, 2.5e-3});  // new in this run
  BaselineCase base = drift_case();
  base.resolutions.insert(base.resolutions.begin(), {11, 1, 1, 1, 1});  // only in the baseline
  const auto d = check_drift("a", base, cur, 0.05, 1e-12);
  ASSERT_EQ(d.size(), 2u);
  for (const auto& x : d) {
    EXPECT_EQ(x.metric, "resolution");
    EXPECT_FALSE(x.worse);
    EXPECT_TRUE(std::isnan(x.baseline));
    EXPECT_TRUE(std::isnan(x.current));
    EXPECT_HAS(x.message, "--update-baseline");
  }
  EXPECT_EQ(d[0].nodes, 11);
  EXPECT_HAS(d[0].message, "11 nodes");
  EXPECT_HAS(d[0].message, "in the baseline but not in this run");
  EXPECT_FALSE(Contains(d[0].message, "run the baseline")) << d[0].message;
  EXPECT_EQ(d[1].nodes, 81);
  EXPECT_HAS(d[1].message, "81 nodes");
  EXPECT_HAS(d[1].message, "not in the baseline");
}

TEST_F(BaselineTest, RoundTripThenCheckDriftIsClean) {
  const Baseline b = sample_baseline();
  const Baseline r = load_baseline(write("b.toml", baseline_to_toml(b)));
  for (const auto& [id, c] : b.cases)
    EXPECT_TRUE(check_drift(id, c, r.cases.at(id), 1e-15, 0).empty()) << id;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Non-finite values: never a pass (issue 12)

TEST_F(ManifestTest, BandThatAdmitsNoFiniteValueIsALoadError) {
  for (const char* band : {"l2_finest = [inf, inf]\n", "l2_finest = [-inf, -inf]\n",
                           "l2_finest = [nan, 1.0]\n"}) {
    const fs::path p = write("m.toml", a_case("a", std::string("[case.bands]\n") + band));
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 7)) << band;
    EXPECT_HAS(msg, "l2_finest");
  }
}

TEST_F(CheckBandsTest, InfiniteValueViolatesAnOpenBand) {
  const ManifestCase c = with_bands("l2_finest = [0.0, inf]\n"
                                    "headline = { \"peak du/dx at x=3\" = [-inf, inf] }\n");
  StudyResult s = study();
  s.cases.back().errors.l2 = kInf;
  s.cases.back().headline["peak du/dx at x=3"] = -kInf;
  const auto v = check_bands(c, s, "bands.toml");
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].metric, "l2_finest");
  EXPECT_HAS(v[0].message, "outside the band");
  EXPECT_EQ(v[1].metric, "headline:peak du/dx at x=3");
}

TEST_F(BaselineTest, NonFiniteNumberIsALoadErrorButTheNanStringIsNoValue) {
  for (const char* value : {"inf", "-inf", "nan", "+inf"}) {
    const fs::path p = write("b.toml", std::string("[cases.a]\nl2_rate = 2.0\nh1_rate = 1.0\n"
                                                   "resolutions = [\n"
                                                   "  { nodes = 21, l2 = ") +
                                           value + ", h1 = 2, l2_rel = 3, h1_rel = 4 },\n]\n");
    const std::string msg = baseline_error(p);
    EXPECT_TRUE(AtLine(msg, p, 5)) << value;
    EXPECT_HAS(msg, "not finite");
  }
  const fs::path ok = write("ok.toml", "[cases.a]\nl2_rate = \"nan\"\nh1_rate = 1.0\n"
                                       "resolutions = [\n"
                                       "  { nodes = 21, l2 = 1, h1 = \"nan\", l2_rel = 3, h1_rel = 4 },\n]\n");
  const Baseline b = load_baseline(ok);
  EXPECT_TRUE(std::isnan(b.cases.at("a").l2_rate));
  EXPECT_TRUE(std::isnan(b.cases.at("a").resolutions.at(0).h1));
}

TEST_F(BaselineTest, WriterRecordsInfAsNoValueSoTheFileLoads) {
  Baseline b;
  BaselineCase c;
  c.l2_rate = kInf;
  c.h1_rate = 1.0;
  c.resolutions = {{21, kInf, -kInf, 1.0, 2.0}};
  b.cases["a"] = c;
  const fs::path p = write("b.toml", baseline_to_toml(b));
  const Baseline r = load_baseline(p);
  EXPECT_TRUE(std::isnan(r.cases.at("a").l2_rate));
  EXPECT_TRUE(std::isnan(r.cases.at("a").resolutions.at(0).l2));
  EXPECT_TRUE(std::isnan(r.cases.at("a").resolutions.at(0).h1));
}

TEST(CheckDrift, NonFiniteCurrentAgainstAFiniteBaselineIsWorse) {
  for (double bad : {kInf, -kInf, kNaN}) {
    BaselineCase cur = drift_case();
    cur.resolutions[1].l2 = bad;
    cur.h1_rate = bad;
    const auto d = check_drift("a", drift_case(), cur, 0.05, 1e-12);
    ASSERT_EQ(d.size(), 2u) << bad;
    for (const auto& x : d) EXPECT_TRUE(x.worse) << x.message;
  }
}

TEST(CheckDrift, InfiniteBaselineDoesNotSwitchTheCheckOff) {
  BaselineCase base = drift_case();
  base.resolutions[0].l2 = kInf;  // as if read from a hand-edited file
  const auto d = check_drift("a", base, drift_case(), 0.05, 1e-12);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].metric, "l2");
  EXPECT_EQ(d[0].nodes, 21);
}

// ---------------------------------------------------------------------------------------------
// expect = "unstable" and check_stability

TEST_F(ManifestTest, ExpectKeyParsesAndRefusesOtherValues) {
  {
    const fs::path p = write("m.toml", a_case("a", "expect = \"unstable\"\n") +
                                           a_case("b", "expect = \"stable\"\n") + a_case("c"));
    const Manifest m = load_manifest(p);
    EXPECT_TRUE(m.cases.at(0).expect_unstable);
    EXPECT_FALSE(m.cases.at(1).expect_unstable);
    EXPECT_FALSE(m.cases.at(2).expect_unstable);
  }
  for (const char* bad : {"expect = \"blows up\"\n", "expect = true\n"}) {
    const fs::path p = write("m.toml", a_case("a", bad));
    const std::string msg = manifest_error(p);
    EXPECT_TRUE(AtLine(msg, p, 6)) << bad;
    EXPECT_HAS(msg, "expect");
  }
}

namespace {
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
}  // namespace

TEST(CheckStability, UnstableRunFailsUnlessExpected) {
  ManifestCase c;
  c.id = "rod-pulse/efg-ci";
  c.problem = "rod-pulse";
  const auto fails = check_stability(c, transient_study({false, true}));
  ASSERT_EQ(fails.size(), 1u);
  EXPECT_HAS(fails[0], "rod-pulse/efg-ci: 241 nodes: unstable at step 9, t = 0.0018");
  EXPECT_TRUE(check_stability(c, transient_study({false, false})).empty());
  c.expect_unstable = true;
  EXPECT_TRUE(check_stability(c, transient_study({true, true})).empty());
}

TEST(CheckStability, ExpectedInstabilityThatStaysStableFails) {
  ManifestCase c;
  c.id = "grk-bar/grk-j0-courant1.35";
  c.expect_unstable = true;
  const auto fails = check_stability(c, transient_study({true, false}));
  ASSERT_EQ(fails.size(), 1u);
  EXPECT_HAS(fails[0], "241 nodes: expected unstable");
  EXPECT_HAS(fails[0], "stayed stable");
}

TEST(CheckStability, ExpectUnstableOnAStaticProblemIsReported) {
  ManifestCase c;
  c.id = "laplace-tanh/fem";
  c.problem = "laplace-tanh";
  StudyResult s;
  s.cases.resize(2);  // no transient steps
  EXPECT_TRUE(check_stability(c, s).empty());
  c.expect_unstable = true;
  const auto fails = check_stability(c, s);
  ASSERT_EQ(fails.size(), 1u);
  EXPECT_HAS(fails[0], "applies to transient runs");
}
