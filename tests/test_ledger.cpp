/// The reproduction ledger: the checked-in suites/ledger.toml restates every published value
/// exactly and names every published value and finding of every problem; bad rows are refused
/// with file:line; verdicts come from the run (not run, not reached, not yet built).
#include <cmath>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "problems/problem.hpp"
#include "temp_files.hpp"
#include "apps/catalogue.hpp"
#include "verify/ledger.hpp"
#include "verify/manifest.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;

const fs::path kSuite = fs::path(MFV_SOURCE_DIR) / "suites" / "default.toml";

bool params_contain(const Params& resolved, const Params& wanted) {
  for (const auto& [k, v] : wanted.values())
    if (!resolved.has(k) || format_value(resolved.values().at(k)) != format_value(v)) return false;
  return true;
}

/// Whether a published row of the ledger names this published value of `problem`.
bool names(const Catalogue& c, const LedgerRow& row, const std::string& problem,
           const PublishedValue& pv) {
  if (row.kind != LedgerRow::Kind::published || row.problem != problem) return false;
  if (row.published_source != pv.source || row.quantity != pv.quantity ||
      row.method != pv.method)
    return false;
  if (!params_contain(c.methods.resolve(row.method, row.method_params), pv.method_params))
    return false;
  const Params pp = resolved_case_params(c, row.problem, row.problem_params);
  for (const auto& [k, v] : pv.problem_params.values())
    if (pp.has(k) && format_value(pp.values().at(k)) != format_value(v)) return false;
  for (std::size_t i = 0; i < row.nodes.size(); ++i)
    if (row.nodes[i] == pv.nodes && row.paper[i] == pv.value) return true;
  return false;
}

/// Every problem at its defaults and at every parameter set the suite runs it with.
std::vector<std::pair<std::string, Params>> problem_instances(const Catalogue& c,
                                                              const Manifest& m) {
  std::vector<std::pair<std::string, Params>> out;
  std::set<std::string> seen;
  auto add = [&](const std::string& name, const Params& p) {
    if (seen.insert(name + " " + p.to_string()).second) out.emplace_back(name, p);
  };
  for (const auto& name : c.problems.keys()) add(name, {});
  for (const auto& mc : m.cases) add(mc.problem, mc.problem_params);
  return out;
}

TEST(Ledger, CheckedInLedgerLoadsAgainstTheDefaultSuite) {
  const Catalogue c;
  const Manifest m = load_manifest(kSuite);
  ASSERT_FALSE(m.ledger.empty()) << "suites/default.toml names no ledger";
  const Ledger l = load_ledger(m.ledger, m, c);
  EXPECT_GT(l.rows.size(), 80u);
}

TEST(Ledger, PublishedRowsEqualTheProblemsPublishedValues) {
  const Catalogue c;
  const Manifest m = load_manifest(kSuite);
  const Ledger l = load_ledger(m.ledger, m, c);
  int checked = 0;
  for (const auto& row : l.rows) {
    if (row.kind != LedgerRow::Kind::published) continue;
    const auto problem = create_problem(c, row.problem, row.problem_params);
    for (std::size_t i = 0; i < row.nodes.size(); ++i) {
      bool found = false;
      for (const auto& pv : problem->published()) {
        if (!names(c, row, row.problem, pv) || pv.nodes != row.nodes[i] ||
            pv.value != row.paper[i])
          continue;
        found = true;
        EXPECT_EQ(pv.tolerance, row.tolerance) << row.id << " at " << row.nodes[i] << " nodes";
      }
      EXPECT_TRUE(found) << row.id << ": no published value " << row.paper[i] << " at "
                         << row.nodes[i] << " nodes in " << row.problem;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// A new PublishedValue or Finding in any problem fails here until a ledger row names it.
TEST(Ledger, EveryPublishedValueAndFindingIsNamedByARow) {
  const Catalogue c;
  const Manifest m = load_manifest(kSuite);
  const Ledger l = load_ledger(m.ledger, m, c);
  for (const auto& [name, params] : problem_instances(c, m)) {
    const auto problem = create_problem(c, name, params);
    for (const auto& pv : problem->published()) {
      const bool named = std::any_of(l.rows.begin(), l.rows.end(),
                                     [&](const LedgerRow& r) { return names(c, r, name, pv); });
      EXPECT_TRUE(named) << fmt::format(
          "{} ({}): published value '{}' {} of {} {} at {} nodes = {} ({}) has no ledger row; "
          "add one to suites/ledger.toml",
          name, params.to_string(), pv.quantity, pv.source, pv.method,
          pv.method_params.to_string(), pv.nodes, pv.value, pv.problem_params.to_string());
    }
    std::set<std::string> ids;
    for (const auto& f : problem->findings()) {
      EXPECT_FALSE(f.id.empty()) << name << ": the finding '" << f.claim << "' has no id";
      EXPECT_TRUE(ids.insert(f.id).second) << name << ": duplicate finding id " << f.id;
      const bool named = std::any_of(l.rows.begin(), l.rows.end(), [&](const LedgerRow& r) {
        return r.kind == LedgerRow::Kind::finding && r.problem == name && r.finding == f.id;
      });
      EXPECT_TRUE(named) << name << ": finding '" << f.id << "' (" << f.claim
                         << ") has no ledger row";
    }
  }
}

/// A two-case manifest and a ledger written next to it.
struct Fixture {
  test::TempDir dir{"mfv-ledger"};
  Catalogue catalogue;
  Manifest manifest;
  fs::path ledger_path;
  explicit Fixture(const std::string& ledger_text) {
    std::ofstream(dir.path() / "suite.toml") << R"([suite]
name = "t"
ledger = "ledger.toml"

[[case]]
id = "fem"
problem = "laplace-tanh"
method = "fem"
nodes = [21, 41]

[[case]]
id = "diffusion-fem"
problem = "advection-diffusion"
problem_params = { a = 0 }
method = "fem"
nodes = [31, 61]
)";
    ledger_path = dir.path() / "ledger.toml";
    std::ofstream(ledger_path) << ledger_text;
    manifest = load_manifest(dir.path() / "suite.toml");
  }
  Ledger load() const { return load_ledger(ledger_path, manifest, catalogue); }
};

const char* kGoodRows = R"([[row]]
id = "t1-fem"
source = "004 II Table 1"
claim = "FEM peak"
case = "fem"
published = "004 II Table 1"
quantity = "peak du/dx at x=3"
nodes = [21, 41]
paper = [3.3168, 6.0343]
tolerance = 0.01

[[row]]
id = "ring"
source = "000 §5.2"
claim = "rubber ring"
problem = "no-such-ring"

[[row]]
id = "rate"
source = "004 II §7"
claim = "rate up to 2"
cases = ["fem"]
measure = "l2_rate"
paper = [2.0]
tolerance = 0.1

[[row]]
id = "t61"
source = "004 I Table 6.1"
claim = "FEM u"
case = "diffusion-fem"
published = "004 I Table 6.1"
quantity = "error u"
nodes = [31]
paper = [0.19545]
tolerance = 0.05
)";

struct BadRow {
  const char* name;
  std::string text;
  const char* expected;  ///< in the message
};

class LedgerBadInput : public ::testing::TestWithParam<BadRow> {};

TEST_P(LedgerBadInput, RefusedWithFileAndLine) {
  const Fixture f(GetParam().text);
  try {
    f.load();
    FAIL() << "accepted: " << GetParam().name;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ledger.toml:"), std::string::npos) << what;
    EXPECT_NE(what.find(GetParam().expected), std::string::npos) << what;
  }
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

INSTANTIATE_TEST_SUITE_P(
    Rows, LedgerBadInput,
    ::testing::Values(
        BadRow{"wrong value", replace(kGoodRows, "3.3168", "3.3169"), "publishes no"},
        BadRow{"wrong tolerance", replace(kGoodRows, "tolerance = 0.01", "tolerance = 0.1"),
               "tolerance 0.1 differs"},
        BadRow{"unknown case", replace(kGoodRows, "case = \"fem\"", "case = \"femm\""),
               "names the case 'femm'"},
        BadRow{"unknown key", replace(kGoodRows, "claim = \"FEM peak\"", "claim = \"x\"\nclam = 1"),
               "unknown key 'clam'"},
        BadRow{"duplicate id", replace(kGoodRows, "id = \"ring\"", "id = \"t1-fem\""),
               "duplicate row id"},
        BadRow{"open row of an existing problem",
               replace(kGoodRows, "problem = \"no-such-ring\"", "problem = \"cantilever\""),
               "now exists"},
        BadRow{"nan tolerance", replace(kGoodRows, "tolerance = 0.1", "tolerance = nan"),
               "positive finite"},
        BadRow{"paper count", replace(kGoodRows, "paper = [3.3168, 6.0343]", "paper = [3.3168]"),
               "1 paper value(s) for 2"},
        BadRow{"bad measure", replace(kGoodRows, "l2_rate", "l3_rate"), "unknown measure"},
        BadRow{"syntax", "[[row]\nid = 1\n", "ledger.toml:"}),
    [](const auto& info) {
      std::string s = info.param.name;
      for (auto& ch : s)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return s;
    });

StudyResult fake_study(const std::string& problem, std::vector<int> nodes,
                       std::vector<double> peaks, double l2_rate) {
  StudyResult s;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    CaseResult r;
    r.spec.problem = problem;
    r.spec.method = "fem";
    r.spec.nodes = nodes[i];
    r.headline["peak du/dx at x=3"] = peaks[i];
    r.errors.l2_rel = peaks[i];
    s.cases.push_back(r);
  }
  s.rates.fitted["L2"] = l2_rate;
  return s;
}

TEST(Ledger, VerdictsComeFromTheRun) {
  const Fixture f(kGoodRows);
  const Ledger l = f.load();
  const StudyResult close = fake_study("laplace-tanh", {21, 41}, {3.32, 6.03}, 1.97);
  const StudyResult far = fake_study("laplace-tanh", {21, 41}, {3.32, 9.0}, 1.0);
  const StudyResult blown = fake_study("laplace-tanh", {21, 41}, {3.32, NAN}, NAN);

  auto verdicts = [&](const std::map<std::string, CaseOutcome>& ran) {
    std::map<std::string, std::string> v;
    for (const auto& e : evaluate_ledger(l, f.catalogue, f.manifest, ran)) v[e.row->id] = e.verdict;
    return v;
  };
  auto v = verdicts({{"fem", {&close, ""}}});
  EXPECT_EQ(v["t1-fem"], kReproduced);
  EXPECT_EQ(v["rate"], kReproduced);
  EXPECT_EQ(v["ring"], kNotYetBuilt);
  EXPECT_EQ(v["t61"], kNotRun);  // its case was not selected

  v = verdicts({{"fem", {&far, ""}}});
  EXPECT_EQ(v["t1-fem"], kPartly);  // one of two values off
  EXPECT_EQ(v["rate"], kNotReproduced);

  v = verdicts({{"fem", {&blown, ""}}});
  EXPECT_EQ(v["t1-fem"], kNotReached);  // a NaN is never a match
  EXPECT_EQ(v["rate"], kNotReached);

  v = verdicts({{"fem", {nullptr, "singular"}}});
  EXPECT_EQ(v["t1-fem"], kNotReached);

  const auto entries = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&close, ""}}});
  const auto counts = count_verdicts(entries);
  EXPECT_EQ(counts.at(kReproduced), 2);
  EXPECT_EQ(counts.at(kNotYetBuilt), 1);
  EXPECT_EQ(counts.at(kNotRun), 1);
  EXPECT_NE(verdict_counts_line(entries).find("2 reproduced"), std::string::npos);
  const std::string md = ledger_markdown(entries);
  EXPECT_NE(md.find("| t1-fem"), std::string::npos);
  const std::string csv = ledger_csv(entries);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
}

TEST(Ledger, AStatedReadingIsNamedInTheVerdict) {
  const Fixture f(replace(kGoodRows, "tolerance = 0.01\n", "tolerance = 0.01\nreading = \"r\"\n"));
  const Ledger l = f.load();
  const StudyResult close = fake_study("laplace-tanh", {21, 41}, {3.32, 6.03}, 1.97);
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&close, ""}}});
  EXPECT_EQ(e[0].verdict, kReproducedReading);
}

TEST(Ledger, AMissingLedgerFileIsNamed) {
  Fixture f(kGoodRows);
  fs::remove(f.ledger_path);
  try {
    f.load();
    FAIL() << "a missing ledger was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(f.ledger_path.string()), std::string::npos) << e.what();
  }
}

TEST(Ledger, AFindingThatDoesNotExistYetIsOpenNotAnError) {
  const Fixture f(std::string(kGoodRows) + R"(
[[row]]
id = "fig3"
source = "004 II Fig. 3"
claim = "SPH Galerkin boundary gradient"
finding = "laplace-tanh:no-such-finding"
)");
  const Ledger l = f.load();
  const StudyResult close = fake_study("laplace-tanh", {21, 41}, {3.32, 6.03}, 1.97);
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&close, ""}}});
  EXPECT_EQ(e.back().verdict, kNotYetBuilt);
  EXPECT_NE(e.back().why.find("no-such-finding"), std::string::npos);
}

TEST(Ledger, AOneSidedClaimAcceptsAnythingOnItsSide) {
  const Fixture f(replace(replace(kGoodRows, "nodes = [21, 41]\npaper = [3.3168, 6.0343]",
                                  "nodes = [21]\npaper = [3.3168]"),
                          "tolerance = 0.01\n", "tolerance = 0.01\ncompare = \"at_least\"\n"));
  const Ledger l = f.load();
  auto verdict = [&](double ours) {
    const StudyResult s = fake_study("laplace-tanh", {21, 41}, {ours, 6.0}, 2.0);
    return evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&s, ""}}})[0].verdict;
  };
  EXPECT_EQ(verdict(10.0), kReproduced);  // far above a lower bound still keeps it
  EXPECT_EQ(verdict(3.29), kReproduced);  // within 1% below
  EXPECT_EQ(verdict(3.25), kPartly);      // within 3% below
  EXPECT_EQ(verdict(2.0), kNotReproduced);
  EXPECT_EQ(verdict(NAN), kNotReached);
}

/// The measurement gaps the ledger's author left are closed: every published row names a suite
/// case, and the GRK Δt rows (the numeric step and eq 5.2.5, j = −1, 0, 1) get a verdict from
/// the suite's grk-bar cases, never "not run" or "not reached".
TEST(Ledger, GrkStepRowsAreMeasuredByTheSuite) {
  const Catalogue c;
  const Manifest m = load_manifest(kSuite);
  const Ledger l = load_ledger(m.ledger, m, c);
  for (const auto& row : l.rows)
    if (row.kind == LedgerRow::Kind::published)
      EXPECT_EQ(row.cases.size(), 1u) << row.id << ": no suite case measures it";
  std::map<std::string, StudyResult> studies;
  for (const auto& mc : m.cases)
    if (mc.problem == "grk-bar" && mc.method == "rkpm" &&
        mc.problem_params.has("courant") && mc.problem_params.number("courant") == 1.0) {
      const CaseSpec spec{mc.problem, mc.problem_params, mc.method, mc.method_params, 0, 0};
      studies.emplace(mc.id, run_study(c, spec, mc.nodes));
    }
  ASSERT_TRUE(studies.count("grk-bar/grk-j-1"));
  std::map<std::string, CaseOutcome> ran;
  for (const auto& [id, s] : studies) ran[id] = {&s, ""};
  int rows = 0;
  for (const auto& e : evaluate_ledger(l, c, m, ran)) {
    if (e.row->id.rfind("004-III-grk-dt-", 0) != 0) continue;
    ++rows;
    EXPECT_NE(e.verdict, kNotRun) << e.row->id << ": " << e.why;
    EXPECT_NE(e.verdict, kNotReached) << e.row->id << ": " << e.why;
    ASSERT_EQ(e.ours.size(), 1u);
    EXPECT_TRUE(std::isfinite(e.ours[0]) && e.ours[0] > 0) << e.row->id;
  }
  EXPECT_EQ(rows, 6);
}

}  // namespace
}  // namespace mfv
