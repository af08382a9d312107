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
#include "verify/ledger_internal.hpp"
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
  if (row.bound == LedgerRow::Bound::range)  // [low, high] at its one resolution
    return row.nodes.size() == 1 && row.nodes[0] == pv.nodes &&
           (row.paper[0] == pv.value || row.paper[1] == pv.value);
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
      // A row names it, or a check or reading of a row does (one number measured two ways is
      // one claim: issue 44 merged the rows that repeated it).
      const bool named = std::any_of(l.rows.begin(), l.rows.end(), [&](const LedgerRow& r) {
        bool any = names(c, r, name, pv);
        for (const auto& k : r.checks) any = any || names(c, *k.row, name, pv);
        for (const auto& t : r.tries) {
          any = any || names(c, *t.row, name, pv);
          for (const auto& k : t.checks) any = any || names(c, *k.row, name, pv);
        }
        return any;
      });
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
      // A row names it, or a reading tried or a check of a row (a finding that restates
      // another under a paper's own reading, or checks it another way).
      auto names_it = [&](const LedgerRow& r) {
        return r.kind == LedgerRow::Kind::finding && r.problem == name && r.finding == f.id;
      };
      const bool named = std::any_of(l.rows.begin(), l.rows.end(), [&](const LedgerRow& r) {
        bool any = names_it(r);
        for (const auto& c : r.checks) any = any || names_it(*c.row);
        for (const auto& t : r.tries) {
          any = any || names_it(*t.row);
          for (const auto& c : t.checks) any = any || names_it(*c.row);
        }
        return any;
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
id = "fem-b"
problem = "laplace-tanh"
method = "fem"
nodes = [21, 41, 81]

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
        BadRow{"syntax", "[[row]\nid = 1\n", "ledger.toml:"},
        BadRow{"source without rows", std::string(kGoodRows) + "[[source]]\nname = \"T\"\nquote = \"q\"\n",
               "names no rows"},
        BadRow{"source matching nothing",
               std::string(kGoodRows) + "[[source]]\nname = \"T\"\nquote = \"q\"\nrows = [\"x*\"]\n",
               "matches no row"},
        BadRow{"source reading no row tries",
               std::string(kGoodRows) +
                   "[[source]]\nname = \"T\"\nquote = \"q\"\nrows = [\"t1-fem\"]\nreading = \"z\"\n",
               "does not try"},
        BadRow{"unknown role", replace(kGoodRows, "id = \"rate\"", "id = \"rate\"\nrole = \"timing\""),
               "is not claim, check or cost"},
        BadRow{"row in two sources",
               std::string(kGoodRows) +
                   "[[source]]\nname = \"T\"\nquote = \"q\"\nrows = [\"t1-fem\"]\n"
                   "[[source]]\nname = \"U\"\nquote = \"q\"\nrows = [\"t*\"]\n",
               "is in source 'T' and 'U'"}),
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

// A paper's claim about CPU time (role cost) and our own check (role check) have their own
// counts and sections: the claim counts, which a run of the same commit repeats, leave out
// verdicts that move with the machine's load.
TEST(LedgerRoles, ClaimsAboutCpuTimeAndOurOwnChecksAreCountedApart) {
  const Fixture f(replace(replace(kGoodRows, "id = \"rate\"", "id = \"rate\"\nrole = \"cost\""),
                          "id = \"t1-fem\"", "id = \"t1-fem\"\nrole = \"check\""));
  const Ledger l = f.load();
  const StudyResult close = fake_study("laplace-tanh", {21, 41}, {3.32, 6.03}, 1.97);
  const auto entries = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&close, ""}}});
  EXPECT_EQ(count_verdicts(entries).at(kReproduced), 0);
  EXPECT_EQ(count_verdicts(entries, LedgerRow::Role::cost).at(kReproduced), 1);
  EXPECT_EQ(count_verdicts(entries, LedgerRow::Role::check).at(kReproduced), 1);
  const std::string line = verdict_counts_line(entries);
  EXPECT_NE(line.find("claims about CPU time (this machine's, apart): 1 reproduced of 1"),
            std::string::npos)
      << line;
  EXPECT_NE(line.find("our own checks: 1 reproduced of 1"), std::string::npos) << line;
  const std::string md = ledger_markdown(entries);
  EXPECT_NE(md.find("## Claims about CPU time"), std::string::npos);
  const std::string csv = ledger_csv(entries);
  EXPECT_NE(csv.find(",uncertainty_of,role\n"), std::string::npos);
  EXPECT_NE(csv.find(",cost\n"), std::string::npos);
  EXPECT_NE(csv.find(",check\n"), std::string::npos);
  EXPECT_NE(csv.find(",claim\n"), std::string::npos);
  // The paper of a claim about CPU time stays its paper in the machine-readable files.
  EXPECT_EQ(ledger_paper(*entries[2].row), "004");
  EXPECT_EQ(entries[2].row->id, "rate");
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


// ---- The reading search, the statistic and the evidence (issue 25) ----

/// The published row t1-fem with readings and checks appended to it (they attach to the
/// last [[row]] of the text, so the row comes last).
std::string row_with(const std::string& extra, const std::string& own = "") {
  return std::string(R"([[row]]
id = "t1-fem"
source = "004 II §7, Table 1"
claim = "FEM peak"
case = "fem"
published = "004 II Table 1"
quantity = "peak du/dx at x=3"
nodes = [21, 41]
paper = [3.3168, 6.0343]
tolerance = 0.01
quote = "“the peak values of u_x are compared”"
)") + own + extra;
}

const char* kTryB = R"(
[[row.try]]
name = "study b"
quote = "“five different discretizations”"
case = "fem-b"
)";

std::map<std::string, CaseOutcome> ran_two(const StudyResult& a, const StudyResult& b) {
  return {{"fem", {&a, ""}}, {"fem-b", {&b, ""}}};
}

TEST(LedgerReadings, TheClosestReadingGivesTheVerdictAndIsNamed) {
  const Fixture f(row_with(kTryB));
  const Ledger l = f.load();
  ASSERT_EQ(l.rows[0].tries.size(), 1u);
  const StudyResult far = fake_study("laplace-tanh", {21, 41}, {3.32, 9.0}, 1.0);
  const StudyResult close = fake_study("laplace-tanh", {21, 41, 81}, {3.3168, 6.0343, 9.0}, 2.0);
  auto e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(far, close))[0];
  EXPECT_EQ(e.verdict, kReproducedReading);
  EXPECT_EQ(e.reading, "study b");
  EXPECT_EQ(e.chosen, 1u);
  ASSERT_EQ(e.readings.size(), 2u);
  EXPECT_EQ(e.readings[0].verdict, kPartly);  // the row's own reading, recorded beside
  EXPECT_DOUBLE_EQ(e.ours[1], 6.0343);
  // Both reproduce: the row's own reading wins and the verdict is plain "reproduced".
  e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(close, close))[0];
  EXPECT_EQ(e.verdict, kReproduced);
  EXPECT_EQ(e.chosen, 0u);
  // The try did not run: the row's own verdict stands.
  e = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&far, ""}}})[0];
  EXPECT_EQ(e.verdict, kPartly);
  EXPECT_EQ(e.readings[1].verdict, kNotRun);
}

/// Issue 43: a [[source]] judges every row of a table under one reading, chosen from the
/// text; a try that reproduces one row and not its sibling is reported, never counted.
TEST(LedgerSources, OneReadingForEveryRowOfTheSource) {
  const std::string second = R"(
[[row]]
id = "t1-fem-81"
source = "004 II §7, Table 1"
claim = "FEM peak at 81"
case = "fem"
published = "004 II Table 1"
quantity = "peak du/dx at x=3"
nodes = [81]
paper = [8.4687]
tolerance = 0.01
quote = "“the peak values of u_x are compared”"
)";
  const std::string rows = row_with(kTryB) + second + kTryB;
  const StudyResult own = fake_study("laplace-tanh", {21, 41, 81}, {3.32, 9.0, 9.0}, 1.0);
  const StudyResult b = fake_study("laplace-tanh", {21, 41, 81}, {3.3168, 6.0343, 9.0}, 2.0);
  {
    // Without a source each row takes its closest reading: the try passes the first row.
    const Fixture f(rows);
    const auto e = evaluate_ledger(f.load(), f.catalogue, f.manifest, ran_two(own, b));
    EXPECT_EQ(e[0].verdict, kReproducedReading);
    EXPECT_EQ(e[1].verdict, kNotReproduced);
  }
  const Fixture f(rows + R"(
[[source]]
name = "Table 1"
rows = ["t1-fem*"]
quote = "“the peak values”"
pairs = [["t1-fem", "t1-fem-81"]]
)");
  const Ledger l = f.load();
  ASSERT_EQ(l.sources.size(), 1u);
  EXPECT_EQ(l.sources[0].rows, (std::vector<std::string>{"t1-fem", "t1-fem-81"}));
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(own, b));
  EXPECT_EQ(e[0].verdict, kPartly) << "the source's reading is the row's own";
  EXPECT_EQ(e[0].chosen, 0u);
  EXPECT_NE(e[0].why.find("one reading for Table 1"), std::string::npos) << e[0].why;
  const std::string md = ledger_sources_markdown(l, e);
  EXPECT_NE(md.find("### Table 1"), std::string::npos) << md;
  EXPECT_NE(md.find("study b (1 of 2)"), std::string::npos) << md;
  EXPECT_NE(md.find("t1-fem-81 / t1-fem"), std::string::npos) << md;
  // A source that names the try reads every row under it.
  const Fixture g(rows + R"(
[[source]]
name = "Table 1"
rows = ["t1-fem", "t1-fem-81"]
reading = "study b"
quote = "“five different discretizations”"
)");
  const auto eg = evaluate_ledger(g.load(), g.catalogue, g.manifest, ran_two(own, b));
  EXPECT_EQ(eg[0].verdict, kReproducedReading);
  EXPECT_EQ(eg[1].verdict, kNotReproduced);
  EXPECT_EQ(eg[1].chosen, 1u);
}

TEST(LedgerEvidence, AConvergedCheckThatDisagreesVetoesTheOneThatAgrees) {
  const Fixture f(row_with(R"(
[[row.check]]
kind = "converged"
route = "the next resolution"
case = "fem-b"

[[row.check]]
kind = "converged"
route = "the same study again"
case = "fem"
)"));
  const Ledger l = f.load();
  const StudyResult a = fake_study("laplace-tanh", {21, 41}, {3.3168, 6.0343}, 1.0);
  const StudyResult off = fake_study("laplace-tanh", {21, 41, 81}, {3.32, 6.5, 9}, 1.0);
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(a, off))[0];
  ASSERT_EQ(e.readings[0].checks.size(), 2u);
  EXPECT_FALSE(e.readings[0].checks[0].agrees);
  EXPECT_TRUE(e.readings[0].checks[1].agrees);
  EXPECT_EQ(e.evidence, kEvidenceSingle);
  // Reproduced at the row's resolution but not by the finer run: not counted as reproduced.
  EXPECT_EQ(e.verdict, kPartly);
  EXPECT_NE(e.why.find("not under refinement: the next resolution gives"), std::string::npos)
      << e.why;
}

TEST(LedgerReadings, AmongPartlyReadingsTheNearestWins) {
  const Fixture f(row_with(kTryB));
  const Ledger l = f.load();
  const StudyResult own = fake_study("laplace-tanh", {21, 41}, {3.3168, 6.6}, 1.0);    // ×1.094
  const StudyResult b = fake_study("laplace-tanh", {21, 41, 81}, {3.3168, 6.3, 9}, 1.0);  // ×1.044
  EXPECT_EQ(evaluate_ledger(l, f.catalogue, f.manifest, ran_two(own, b))[0].chosen, 1u);
  EXPECT_EQ(evaluate_ledger(l, f.catalogue, f.manifest, ran_two(b, own))[0].chosen, 0u);
}

TEST(LedgerReadings, AFittedReadingIsShownButNeverCounted) {
  const Fixture f(row_with(std::string(kTryB) + "fitted = true\n"));
  const Ledger l = f.load();
  const StudyResult far = fake_study("laplace-tanh", {21, 41}, {3.32, 9.0}, 1.0);
  const StudyResult close = fake_study("laplace-tanh", {21, 41, 81}, {3.3168, 6.0343, 9.0}, 2.0);
  const auto entries = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(far, close));
  EXPECT_EQ(entries[0].verdict, kPartly);
  EXPECT_EQ(entries[0].chosen, 0u);
  EXPECT_EQ(entries[0].readings[1].verdict, kReproduced);
  EXPECT_NE(ledger_markdown(entries).find("fitted: shown for scale, not counted"),
            std::string::npos);
}

TEST(LedgerReadings, ATryMayReadOursAtOtherResolutions) {
  const Fixture f(row_with(R"(
[[row.try]]
name = "finer"
quote = "“q”"
case = "fem-b"
nodes = [41, 81]
)"));
  const Ledger l = f.load();
  const StudyResult a = fake_study("laplace-tanh", {21, 41}, {1, 1}, 1.0);
  const StudyResult b = fake_study("laplace-tanh", {21, 41, 81}, {9, 3.3168, 6.0343}, 2.0);
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(a, b))[0];
  EXPECT_EQ(e.verdict, kReproducedReading);
  EXPECT_EQ(e.read->nodes, (std::vector<int>{41, 81}));
  EXPECT_NE(ledger_markdown({e}).find("(n = 41, 81)"), std::string::npos);
}

TEST(LedgerReadings, TheStatisticChoosesHowARateIsRead) {
  const std::string rows = R"X([[row]]
id = "rate"
source = "004 II §7"
claim = "rate as high as 3"
cases = ["fem"]
measure = "l2_rate"
statistic = "finest_pair"
paper = [3.0]
tolerance = 0.05
quote = "“can go as high as”"

[[row.try]]
name = "best pair"
quote = "“as high as”"
statistic = "best_pair"

[[row.try]]
name = "least squares"
quote = "“the slopes p and q” (eq 7.3)"
statistic = "least_squares"
)X";
  const Fixture f(rows);
  const Ledger l = f.load();
  StudyResult s = fake_study("laplace-tanh", {21, 41, 81}, {1, 1, 1}, 2.0);
  s.rates.pairwise["L2"] = {3.5, 3.0};
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&s, ""}}})[0];
  ASSERT_EQ(e.readings.size(), 3u);
  EXPECT_DOUBLE_EQ(e.readings[0].ours[0], 3.0);  // finest pair
  EXPECT_DOUBLE_EQ(e.readings[1].ours[0], 3.5);  // best pair
  EXPECT_DOUBLE_EQ(e.readings[2].ours[0], 2.0);  // least squares
  EXPECT_EQ(e.verdict, kReproduced);
  EXPECT_EQ(e.chosen, 0u);
  s.rates.pairwise["L2"] = {3.0, std::nan("")};  // a pair not reached: finest_pair has none
  const auto g = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&s, ""}}})[0];
  EXPECT_EQ(g.readings[0].verdict, kNotReached);
  EXPECT_EQ(g.chosen, 1u);
}

TEST(LedgerEvidence, ComputedFromChecksThatAgreeWithinTheTolerance) {
  const std::string checks = R"(
[[row.check]]
kind = "converged"
route = "study b: the same resolutions, more quadrature"
case = "fem-b"
)";
  const Fixture f(row_with(checks));
  const Ledger l = f.load();
  const StudyResult a = fake_study("laplace-tanh", {21, 41}, {3.3168, 6.0343}, 1.0);
  const StudyResult near = fake_study("laplace-tanh", {21, 41, 81}, {3.32, 6.04, 9}, 1.0);
  const StudyResult off = fake_study("laplace-tanh", {21, 41, 81}, {3.32, 6.5, 9}, 1.0);
  auto e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(a, near))[0];
  EXPECT_EQ(e.evidence, kEvidenceConverged);
  ASSERT_EQ(e.readings[0].checks.size(), 1u);
  EXPECT_TRUE(e.readings[0].checks[0].agrees);
  e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(a, off))[0];
  EXPECT_EQ(e.evidence, kEvidenceSingle);
  EXPECT_FALSE(e.readings[0].checks[0].agrees);
  const std::string md = ledger_markdown({e});
  EXPECT_NE(md.find("study b: the same resolutions"), std::string::npos);
  // A check that did not run gives no evidence; a row that did not run has none at all.
  e = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&a, ""}}})[0];
  EXPECT_EQ(e.evidence, kEvidenceSingle);
  // ... and says it did not run, not that it "differs" (a --full case in a default run).
  EXPECT_NE(ledger_csv({e}).find("→ not run in this invocation"), std::string::npos);
  EXPECT_EQ(ledger_csv({e}).find("differs (not run)"), std::string::npos);
  EXPECT_NE(ledger_markdown({e}).find("| not run (a --full case?) |"), std::string::npos);
  e = evaluate_ledger(l, f.catalogue, f.manifest, {})[0];
  EXPECT_EQ(e.evidence, "–");
  // An independent check outranks a converged one.
  const Fixture g(row_with(std::string(checks) + R"(
[[row.check]]
kind = "independent"
route = "closed form"
case = "fem-b"
)"));
  const Ledger lg = g.load();
  EXPECT_EQ(evaluate_ledger(lg, g.catalogue, g.manifest, ran_two(a, near))[0].evidence,
            kEvidenceIndependent);
}

TEST(LedgerEvidence, ATryCarriesItsOwnChecks) {
  const Fixture f(row_with(std::string(kTryB) + R"(
[[row.try.check]]
kind = "converged"
route = "the first study"
case = "fem"
)"));
  const Ledger l = f.load();
  ASSERT_EQ(l.rows[0].tries.at(0).checks.size(), 1u);
  EXPECT_TRUE(l.rows[0].checks.empty());
  const StudyResult a = fake_study("laplace-tanh", {21, 41}, {3.33, 6.05}, 1.0);
  const StudyResult b = fake_study("laplace-tanh", {21, 41, 81}, {3.3168, 6.0343, 9}, 1.0);
  const auto e = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(a, b))[0];
  EXPECT_EQ(e.chosen, 1u);
  EXPECT_EQ(e.evidence, kEvidenceConverged);
  EXPECT_EQ(e.readings[0].evidence, kEvidenceSingle);
}

TEST(LedgerReadings, CsvAndPageShowEveryReadingAndCheck) {
  const Fixture f(row_with(std::string(kTryB) + R"(
[[row.check]]
kind = "independent"
route = "a closed form"
case = "fem-b"
)"));
  const Ledger l = f.load();
  const StudyResult a = fake_study("laplace-tanh", {21, 41}, {3.32, 9.0}, 1.0);
  const StudyResult b = fake_study("laplace-tanh", {21, 41, 81}, {3.3168, 6.0343, 9}, 1.0);
  const auto entries = evaluate_ledger(l, f.catalogue, f.manifest, ran_two(a, b));
  const std::string csv = ledger_csv(entries);
  EXPECT_NE(csv.find(",evidence,reading,readings_tried,checks,"), std::string::npos);
  EXPECT_NE(csv.find("* study b"), std::string::npos);
  EXPECT_NE(csv.find("a closed form"), std::string::npos);
  const std::string md = ledger_markdown(entries);
  EXPECT_NE(md.find("## Counts by paper and section"), std::string::npos);
  EXPECT_NE(md.find("## 004 — "), std::string::npos);
  EXPECT_NE(md.find("<a id=\"row-t1-fem\"></a>"), std::string::npos);
  EXPECT_NE(md.find("[2 tried](#row-t1-fem)"), std::string::npos);
  EXPECT_NE(md.find("“five different discretizations”"), std::string::npos);
  EXPECT_NE(md.find("**study b** ← verdict"), std::string::npos);
}

TEST(LedgerReadings, AFindingMayBeJudgedOnNamedCasesOnly) {
  const Fixture f(R"([[row]]
id = "fig3"
source = "004 II Fig. 3"
claim = "SPH Galerkin boundary gradient"
finding = "laplace-tanh:sph-galerkin-boundary-gradient"
quote = "q"

[[row.try]]
name = "fem only"
quote = "q"
cases = ["fem-b"]
)");
  const Ledger l = f.load();
  ASSERT_EQ(l.rows[0].tries.at(0).row->cases, std::vector<std::string>{"fem-b"});
  const StudyResult a = fake_study("laplace-tanh", {21, 41}, {3.32, 6.03}, 1.97);
  // fem-b did not run: the try is not run (never judged on the other studies).
  auto e = evaluate_ledger(l, f.catalogue, f.manifest, {{"fem", {&a, ""}}})[0];
  EXPECT_EQ(e.readings[1].verdict, kNotRun);
  EXPECT_NE(e.readings[1].why.find("fem-b did not run"), std::string::npos) << e.readings[1].why;
  // A case of another problem is refused.
  const Fixture g(replace(std::string(R"([[row]]
id = "fig3"
source = "004 II Fig. 3"
claim = "c"
finding = "laplace-tanh:sph-galerkin-boundary-gradient"
cases = ["diffusion-fem"]
)"), "", ""));
  EXPECT_THROW(g.load(), InputError);
}

TEST(LedgerReadings, PaperAndSectionComeFromTheRow) {
  auto section = [](const std::string& id, const std::string& source) {
    LedgerRow r;
    r.id = id;
    r.source = source;
    return std::make_pair(ledger_paper(r), ledger_section(r));
  };
  EXPECT_EQ(section("004-II-T1-j1", "004 II §7, Table 1 (RKPM j = 1 column)"),
            std::make_pair(std::string("004"), std::string("II §7")));
  EXPECT_EQ(section("004-I-T6.1-fem-u", "004 I §6, Table 6.1 (a = 0)").second, "I §6");
  EXPECT_EQ(section("001-T3-sph-1Lc", "001 §9.2, Table 3").second, "§9.2");
  EXPECT_EQ(section("003-alpha", "Belytschko et al. 2000a via 003 §4.3.3").second, "§4.3.3");
  EXPECT_EQ(section("000-3.1.2-onset", "000 §3.1.2, Fig. 3").second, "§3.1.2");
  EXPECT_EQ(section("004-III-ts-fem", "004 III §5.2.").second, "III §5.2");
  EXPECT_EQ(section("hydrostatics-at-rest", "hydrostatics"),
            std::make_pair(std::string("other"), std::string("hydrostatics")));
}

INSTANTIATE_TEST_SUITE_P(
    Readings, LedgerBadInput,
    ::testing::Values(
        BadRow{"try without quote", row_with("\n[[row.try]]\nname = \"b\"\ncase = \"fem-b\"\n"),
               "has no 'quote'"},
        BadRow{"try without name", row_with("\n[[row.try]]\nquote = \"q\"\ncase = \"fem-b\"\n"),
               "has no 'name'"},
        BadRow{"try of another kind", row_with("\n[[row.try]]\nname = \"b\"\nquote = \"q\"\n"
                                               "measure = \"l2_rate\"\n"),
               "'measure' cannot be set in a try"},
        BadRow{"try of an unknown case",
               row_with("\n[[row.try]]\nname = \"b\"\nquote = \"q\"\ncase = \"nope\"\n"),
               "names the case 'nope'"},
        BadRow{"try reading other node counts",
               row_with("\n[[row.try]]\nname = \"b\"\nquote = \"q\"\nnodes = [21]\n"),
               "reads 1 resolution(s) for 2"},
        BadRow{"two tries of one name", row_with(std::string(kTryB) + kTryB), "twice"},
        BadRow{"fitted not boolean",
               row_with(std::string(kTryB) + "fitted = \"yes\"\n"), "'fitted' must be"},
        BadRow{"check kind", row_with("\n[[row.check]]\nkind = \"sure\"\nroute = \"r\"\n"
                                      "case = \"fem-b\"\n"),
               "kind = \"sure\" is not known"},
        BadRow{"check without route", row_with("\n[[row.check]]\nkind = \"converged\"\n"
                                               "case = \"fem-b\"\n"),
               "has no 'route'"},
        BadRow{"check that repeats the reading",
               row_with("\n[[row.check]]\nkind = \"converged\"\nroute = \"r\"\n"),
               "replaces nothing"},
        BadRow{"try as a plain table", row_with("try = { name = \"b\" }\n"),
               "must be [[row.try]] tables"},
        BadRow{"statistic of a published row", row_with("", "statistic = \"best_pair\"\n"),
               "measures no rate"},
        BadRow{"unknown statistic",
               replace(kGoodRows, "measure = \"l2_rate\"",
                       "measure = \"l2_rate\"\nstatistic = \"median\""),
               "statistic = \"median\" is not known"},
        BadRow{"tries without the row's own quote",
               replace(row_with(kTryB), "quote = \"“the peak values of u_x are compared”\"\n", ""),
               "does not say what its own rests on"}),
    [](const auto& info) {
      std::string s = info.param.name;
      for (auto& ch : s)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return s;
    });

/// The measurement gaps the ledger's author left are closed: every published row names a suite
/// case, and the GRK Δt rows (004 III's numeric step and eq 5.2.5, j = −1, 0, 1: one row per
/// number since issue 44) get a verdict from the suite's time-step cases, never "not run" or
/// "not reached", with the grk-bar engine's step as the numeric rows' independent route.
TEST(Ledger, GrkStepRowsAreMeasuredByTheSuite) {
  const Catalogue c;
  const Manifest m = load_manifest(kSuite);
  const Ledger l = load_ledger(m.ledger, m, c);
  for (const auto& row : l.rows)
    if (row.kind == LedgerRow::Kind::published)
      EXPECT_EQ(row.cases.size(), 1u) << row.id << ": no suite case measures it";
  std::map<std::string, StudyResult> studies;
  for (const auto& mc : m.cases) {
    const bool engine = mc.problem == "grk-bar" && mc.method == "rkpm" &&
                        mc.problem_params.has("courant") &&
                        mc.problem_params.number("courant") == 1.0;
    const bool eigen = mc.problem == "time-step" && mc.method == "rkpm" && !mc.full_only;
    if (engine || eigen) {
      const CaseSpec spec{mc.problem, mc.problem_params, mc.method, mc.method_params, 0, 0};
      studies.emplace(mc.id, run_study(c, spec, mc.nodes));
    }
  }
  ASSERT_TRUE(studies.count("grk-bar/grk-j-1"));
  std::map<std::string, CaseOutcome> ran;
  for (const auto& [id, s] : studies) ran[id] = {&s, ""};
  int rows = 0;
  for (const auto& e : evaluate_ledger(l, c, m, ran)) {
    if (e.row->id.rfind("004-III-ts-j", 0) != 0) continue;
    ++rows;
    EXPECT_NE(e.verdict, kNotRun) << e.row->id << ": " << e.why;
    EXPECT_NE(e.verdict, kNotReached) << e.row->id << ": " << e.why;
    ASSERT_EQ(e.ours.size(), 1u);
    EXPECT_TRUE(std::isfinite(e.ours[0]) && e.ours[0] > 0) << e.row->id;
    if (e.row->id.ends_with("-num")) {
      ASSERT_FALSE(e.readings[0].checks.empty()) << e.row->id;
      EXPECT_TRUE(e.readings[0].checks[0].agrees) << e.row->id << ": the engine's step";
    }
  }
  EXPECT_EQ(rows, 6);
}

/// Issue 44: a finding's uncertainty is computed per number its verdict rests on: the GCI from
/// the number's own levels, or, read at one resolution, against the same number of a converged
/// check (two levels, F_s = 3); without either it says why.
TEST(LedgerUncertainty, AFindingCarriesTheUncertaintyOfEachNumber) {
  LedgerReadingOutcome o;
  // Three levels, second order, halving h: f = 1 + h^2.
  o.numbers.push_back({"a: peak", {0.4, 0.2, 0.1}, {1.16, 1.04, 1.01}});
  // One level, and a converged check (half the step, first order) that has the same number.
  o.numbers.push_back({"a: growth", {0.1}, {2.0}});
  // One level and no check of it.
  o.numbers.push_back({"a: onset", {0.1}, {0.5}});
  LedgerCheck check;
  check.kind = LedgerCheck::Kind::converged;
  check.route = "half the time step";
  check.refinement = 2;
  check.order = 1;
  LedgerCheckOutcome c;
  c.check = &check;
  c.numbers.push_back({"a: growth", {0.1}, {2.1}});
  o.checks.push_back(c);
  ledger_internal::finding_uncertainty(o);
  ASSERT_EQ(o.uncertainty.size(), 3u);
  EXPECT_EQ(o.uncertainty_of, (std::vector<std::string>{"a: peak", "a: growth", "a: onset"}));
  const Uncertainty& three = o.uncertainty[0];
  ASSERT_TRUE(three.known()) << three.why_none;
  EXPECT_NEAR(three.order, 2.0, 1e-9);
  EXPECT_NEAR(three.extrapolated, 1.0, 1e-9);
  EXPECT_NEAR(three.gci, 1.25 * (0.03 / 1.01) / 3, 1e-9);
  const Uncertainty& two = o.uncertainty[1];
  ASSERT_TRUE(two.known()) << two.why_none;
  EXPECT_EQ(two.levels, 2);
  EXPECT_NEAR(two.absolute, 3 * 0.1 * 2 / (2 - 1), 1e-9);  // U = F_s |Δ| r^p / (r^p − 1)
  EXPECT_NE(two.method.find("half the time step"), std::string::npos) << two.method;
  EXPECT_FALSE(o.uncertainty[2].known());
  EXPECT_NE(o.uncertainty[2].why_none.find("one resolution"), std::string::npos);
  // A check's refined case is named by ours with a suffix: the shortest such label is the
  // counterpart (a "-wall-particles-dt" case refines another study).
  LedgerReadingOutcome dam;
  dam.numbers.push_back({"dam/sph (eulerian): front", {0.1}, {1.0}});
  LedgerCheckOutcome refined;
  refined.check = &check;
  refined.numbers.push_back({"dam/sph-wall-particles-dt (eulerian): front", {0.1}, {5.0}});
  refined.numbers.push_back({"dam/sph-dt (lagrangian): front", {0.1}, {7.0}});
  refined.numbers.push_back({"dam/sph-dt (eulerian): front", {0.1}, {1.1}});
  dam.checks.push_back(refined);
  ledger_internal::finding_uncertainty(dam);
  ASSERT_TRUE(dam.uncertainty.at(0).known()) << dam.uncertainty[0].why_none;
  EXPECT_NEAR(dam.uncertainty[0].absolute, 3 * 0.1 * 2, 1e-9);
  // A number never measured says so.
  LedgerReadingOutcome missing;
  missing.numbers.push_back({"b: peak", {0.1}, {NAN}});
  ledger_internal::finding_uncertainty(missing);
  ASSERT_EQ(missing.uncertainty.size(), 1u);
  EXPECT_EQ(missing.uncertainty[0].why_none, "not measured");
}

}  // namespace
}  // namespace mfv
