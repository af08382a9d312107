/// results.json and ledger.json: what `mfv compare` and `mfv verify` write validates against
/// docs/schemas (python3-jsonschema through scripts/validate_json.py), non-finite numbers are
/// null with a reason, and numbers a run does not measure are never written as 0.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "apps/commands.hpp"
#include "temp_files.hpp"
#include "apps/catalogue.hpp"
#include "verify/results_json.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Exit code of scripts/validate_json.py on `file` (0 valid, 1 invalid, 2 unreadable).
int validate(const std::string& schema, const fs::path& file) {
  const std::string cmd = "python3 '" + std::string(MFV_SOURCE_DIR) +
                          "/scripts/validate_json.py' " + schema + " '" + file.string() + "'";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

TEST(ResultsJson, CompareWritesAValidResultsFile) {
  test::TempDir dir("mfv-results");
  const Catalogue c;
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"fem", "efg"};
  o.nodes = {21, 41};
  o.report = (dir.path() / "cmp").string();
  o.vtk = false;
  std::ostringstream out, progress;
  ASSERT_EQ(command_compare(c, o, out, progress), 0) << out.str();
  const fs::path file = dir.path() / "cmp" / "results.json";
  ASSERT_TRUE(fs::exists(file));
  EXPECT_EQ(validate("results", file), 0);

  const json doc = read_json(file);
  EXPECT_EQ(doc["schema"], kResultsSchema);
  EXPECT_EQ(doc["run"]["kind"], "compare");
  ASSERT_EQ(doc["studies"].size(), 2u);
  const json& fem = doc["studies"][0];
  EXPECT_EQ(fem["method"], "fem");
  ASSERT_EQ(fem["resolutions"].size(), 2u);
  EXPECT_EQ(fem["resolutions"][1]["nodes"], 41);
  // Errors by norm name, rates by norm name (least squares and pairwise).
  EXPECT_GT(fem["resolutions"][1]["errors"]["common"]["l2"]["relative"].get<double>(), 0);
  EXPECT_NEAR(fem["rates"]["common"]["l2"]["least_squares"].get<double>(), 2.0, 0.5);
  EXPECT_EQ(fem["rates"]["common"]["l2"]["pairwise"].size(), 1u);
  EXPECT_TRUE(fem["resolutions"][0]["headline"].contains("peak du/dx at x=3"));
  // Each headline name with its stable id and stated unit.
  ASSERT_TRUE(fem["headlines"].is_array());
  bool peak = false;
  for (const auto& h : fem["headlines"])
    if (h["name"] == "peak du/dx at x=3") {
      peak = true;
      EXPECT_EQ(h["id"], "peak_du_per_dx_at_x_3");
      EXPECT_EQ(h["unit"], "");
    }
  EXPECT_TRUE(peak) << fem["headlines"].dump();
  EXPECT_TRUE(fem["method_params"].is_object());
  // Table 1's FEM column at 21 and 41 nodes, with ours and a computed verdict.
  ASSERT_EQ(fem["published"].size(), 2u);
  EXPECT_EQ(fem["published"][0]["source"], "004 II Table 1");
  EXPECT_EQ(fem["published"][0]["verdict"], "reproduced");
  EXPECT_TRUE(doc["findings"].is_array());
}

TEST(ResultsJson, HeadlineIdsAreAsciiWordsAndUnitsOnlyRecognisedOnes) {
  EXPECT_EQ(headline_id("σθθ vs 1D at 0.1 ms (of p)"), "sigma_theta_theta_vs_1d_at_0_1_ms_of_p");
  EXPECT_EQ(headline_id("band fit ψ+ (deg)"), "band_fit_psi_plus_deg");
  EXPECT_EQ(headline_id("band fit ψ− (deg)"), "band_fit_psi_minus_deg");
  EXPECT_EQ(headline_id("u(a) / Lamé − 1"), "u_a_per_lam_minus_1");
  EXPECT_EQ(headline_id("half-drain time (s)"), "half_drain_time_s");
  EXPECT_EQ(headline_id("()"), "headline");
  EXPECT_EQ(headline_unit("half-drain time (s)"), "s");
  EXPECT_EQ(headline_unit("mean outflow (kg/s per m)"), "kg/s per m");
  EXPECT_EQ(headline_unit("σθθ vs 1D at 0.1 ms (of p)"), "") << "a qualifier, not a unit";
  EXPECT_EQ(headline_unit("drained in band"), "");
  EXPECT_EQ(headline_unit("broken (s"), "");
}

TEST(ResultsJson, NonFiniteNumbersAreNullWithAReason) {
  const Catalogue c;
  StudyResult s;
  s.label = "one";
  CaseResult r;
  r.spec.problem = "laplace-tanh";
  r.spec.method = "fem";
  r.spec.nodes = 21;
  r.h = 0.3;
  r.errors.l2 = 1e-3;
  r.errors.l2_rel = std::numeric_limits<double>::infinity();
  r.data<StaticSolveData>().solve.solver = "UMFPACK LU";
  r.data<StaticSolveData>().solve.condition = NAN;
  r.headline["peak du/dx at x=3"] = NAN;
  s.cases.push_back(r);
  s.rates.fitted["L2"] = NAN;  // one resolution: no rate
  const json doc = json::parse(results_json(c, RunInfo{"study", "t", 2, 1, 1}, {s}, {}));
  const json& res = doc["studies"][0]["resolutions"][0];
  EXPECT_TRUE(res["errors"]["common"]["l2"]["relative"].is_null());
  EXPECT_TRUE(res["solver"]["condition"].is_null());
  EXPECT_TRUE(res["headline"]["peak du/dx at x=3"].is_null());
  EXPECT_TRUE(doc["studies"][0]["rates"]["common"]["l2"]["least_squares"].is_null());
  const json& nulls = doc["nulls"];
  EXPECT_NE(nulls.value("/studies/0/resolutions/0/errors/common/l2/relative", "").find("+inf"),
            std::string::npos);
  EXPECT_TRUE(nulls.contains("/studies/0/resolutions/0/headline/peak du~1dx at x=3"));
  EXPECT_TRUE(nulls.contains("/studies/0/rates/common/l2/least_squares"));
  EXPECT_TRUE(doc.at(json::json_pointer("/studies/0/resolutions/0/headline/peak du~1dx at x=3"))
                  .is_null());
}

TEST(ResultsJson, ErrorsATransientOrAnalysisRunDoesNotMeasureAreNullNotZero) {
  const Catalogue c;
  StudyResult transient, analysis;
  CaseResult r;
  r.spec.problem = "rod-pulse";
  r.spec.method = "sph";
  r.spec.nodes = 121;
  r.data<TransientData>().steps = 10;
  r.errors.l2_rel = 0.05;  // the velocity error; every other norm stays at its default 0
  transient.cases.push_back(r);
  CaseResult a;
  a.spec.problem = "time-step";
  a.spec.method = "fem";
  a.spec.nodes = 21;
  a.data<FigureData>().setup = "bar";
  analysis.cases.push_back(a);
  const json doc =
      json::parse(results_json(c, RunInfo{"compare", "t", 2, 1, 1}, {transient, analysis}, {}));
  const json& t = doc["studies"][0]["resolutions"][0]["errors"]["common"];
  EXPECT_DOUBLE_EQ(t["l2"]["relative"].get<double>(), 0.05);
  EXPECT_TRUE(t["h1_seminorm"]["relative"].is_null());
  EXPECT_TRUE(t["l2"]["absolute"].is_null());
  const json& an = doc["studies"][1]["resolutions"][0]["errors"]["common"];
  EXPECT_TRUE(an["l2"]["relative"].is_null());
  EXPECT_TRUE(doc["nulls"].contains("/studies/1/resolutions/0/errors/common/l2/relative"));
}

TEST(ResultsJson, VerifyWritesValidResultsAndLedgerFiles) {
  test::TempDir dir("mfv-results");
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
  std::ofstream(dir.path() / "ledger.toml") << R"([[row]]
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
id = "t61"
source = "004 I Table 6.1"
claim = "FEM u"
case = "diffusion-fem"
published = "004 I Table 6.1"
quantity = "error u"
nodes = [31]
paper = [0.19545]
tolerance = 0.05

[[row]]
id = "kbm"
source = "001 §9.1"
claim = "KBM si rate"
finding = "cantilever:kbm-si-rate"
)";
  const Catalogue c;
  VerifyOptions o;
  o.manifest = (dir.path() / "suite.toml").string();
  o.cases = {"fem"};
  o.report = (dir.path() / "report").string();
  o.vtk = false;
  std::ostringstream out, progress;
  ASSERT_EQ(command_verify(c, o, out, progress), 0) << out.str();
  EXPECT_NE(out.str().find("Ledger"), std::string::npos) << out.str();
  const fs::path report = dir.path() / "report";
  EXPECT_EQ(validate("results", report / "results.json"), 0);
  EXPECT_EQ(validate("ledger", report / "ledger.json"), 0);
  ASSERT_TRUE(fs::exists(report / "ledger.csv"));

  const json doc = read_json(report / "results.json");
  EXPECT_EQ(doc["regression"]["status"], "PASS");
  EXPECT_EQ(doc["cases"].size(), 1u);
  const json& rows = doc["ledger"]["rows"];
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0]["verdict"], "reproduced");
  EXPECT_EQ(rows[1]["verdict"], "not yet built");
  EXPECT_EQ(rows[2]["verdict"], "not run");  // its case was not selected
  EXPECT_EQ(rows[3]["verdict"], "not run");
  EXPECT_EQ(doc["ledger"]["counts"]["reproduced"], 1);

  // index.md opens with the summary (reproduction apart from regression), contents, the
  // regression, then the ledger's counts by paper (issue 28: what failed comes first).
  std::stringstream md;
  md << std::ifstream(report / "index.md").rdbuf();
  const std::string text = md.str();
  const auto summary = text.find("## Summary"), contents = text.find("## Contents"),
             ledger = text.find("## Reproduction ledger"),
             regression = text.find("## Regression");
  ASSERT_NE(summary, std::string::npos);
  EXPECT_LT(summary, contents);
  EXPECT_LT(contents, regression);
  EXPECT_LT(regression, ledger);
  EXPECT_NE(text.find("1 reproduced"), std::string::npos);
  EXPECT_EQ(text.find("| t1-fem |"), std::string::npos) << "the rows are ledger.md's";
  // The full ledger and every case's regression row are one link away.
  std::stringstream full, regression_page;
  full << std::ifstream(report / "ledger.md").rdbuf();
  regression_page << std::ifstream(report / "regression.md").rdbuf();
  EXPECT_NE(full.str().find("| t1-fem |"), std::string::npos);
  EXPECT_NE(full.str().find("tolerance"), std::string::npos);
  EXPECT_NE(regression_page.str().find("H1-seminorm rate"), std::string::npos);
  EXPECT_NE(text.find("](ledger.md)"), std::string::npos);
  EXPECT_NE(text.find("](regression.md)"), std::string::npos);
}

// The validator is not a rubber stamp: a number written as text, a verdict outside the list
// and a NaN literal are refused.
TEST(ResultsJson, TheSchemasRefuseBrokenDocuments) {
  test::TempDir dir("mfv-results");
  const Catalogue c;
  StudyResult s;
  s.label = "fem";
  CaseResult r;
  r.spec.problem = "laplace-tanh";
  r.spec.method = "fem";
  r.spec.nodes = 21;
  r.h = 0.3;
  s.cases.push_back(r);
  json doc = json::parse(results_json(c, RunInfo{"study", "t", 2, 1, 1}, {s}, {}));
  std::ofstream(dir.path() / "good.json") << doc.dump();
  EXPECT_EQ(validate("results", dir.path() / "good.json"), 0);

  json text_number = doc;
  text_number["studies"][0]["resolutions"][0]["errors"]["common"]["l2"]["relative"] = "0";
  std::ofstream(dir.path() / "text.json") << text_number.dump();
  EXPECT_EQ(validate("results", dir.path() / "text.json"), 1);

  json verify = doc;
  verify["run"]["kind"] = "verify";  // a verify document needs suite, regression, cases, ledger
  std::ofstream(dir.path() / "verify.json") << verify.dump();
  EXPECT_EQ(validate("results", dir.path() / "verify.json"), 1);

  std::ofstream(dir.path() / "nan.json") << R"({"schema": "mfv-results-1", "x": NaN})";
  EXPECT_EQ(validate("results", dir.path() / "nan.json"), 2);

  std::ofstream(dir.path() / "ledger.json")
      << R"({"schema": "mfv-ledger-1", "nulls": {}, "ledger_file": "l", "counts": {},
             "rows": [{"id": "a", "source": "s", "claim": "c", "kind": "open",
                       "verdict": "PASS", "why": "", "paper": []}]})";
  EXPECT_EQ(validate("ledger", dir.path() / "ledger.json"), 1);
}

}  // namespace
}  // namespace mfv
