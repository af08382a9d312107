/// Variationally consistent integration (methods/methods/vci.*): the divergence-identity defect
/// of the test functions per particle under nodal and stress-point quadrature, its removal by
/// VCI, the elastic patch test passed to round-off with vci=true, and the refusals; plus the
/// RKPM window readings of 004 II Table 1 (rule=derived|fit|eq7.4).
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "methods/methods/vci.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

struct VciCase {
  const char* method;
  double perturbation;
};

std::string case_name(const ::testing::TestParamInfo<VciCase>& info) {
  std::string n = info.param.method;
  for (char& ch : n)
    if (ch == '-') ch = '_';
  return n + (info.param.perturbation > 0 ? "_perturbed" : "_uniform");
}

// The three nodal and stress-point methods 001 finds wanting, on uniform and perturbed lattices.
const VciCase kCases[] = {{"kbm-si", 0.0}, {"kbm-si", 0.3}, {"kbm-ni", 0.0},
                          {"kbm-ni", 0.3}, {"efg-ni", 0.0}, {"efg-ni", 0.3}};

class Vci : public ::testing::TestWithParam<VciCase> {};

Discretization discretize(const char* method, const char* params, double perturbation) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  const auto m = test_catalogue().methods.create(method, Params::parse(params));
  return m->discretize(p->domain(), p->particles(7, perturbation), 1);
}

TEST_P(Vci, DefectOfTheDivergenceIdentityIsRemoved) {
  // Σ_q w_q ∇Ψ_I(x_q) − Σ_b w_b Ψ_I(x_b) n_b per particle: O(1) relative where supports are
  // cut by the edges under nodal and stress-point sums; VCI makes it vanish to round-off.
  const VciCase& c = GetParam();
  const Discretization plain = discretize(c.method, "", c.perturbation);
  const DefectSummary before = summarize_defect(plain, divergence_defect(plain));
  const Discretization vci = discretize(c.method, "vci=true", c.perturbation);
  const DefectSummary after = summarize_defect(vci, divergence_defect(vci));
  std::printf("[ defect   ] %-7s perturbation %.1f: max %.3e rms %.3e (particle %d); vci: max "
              "%.3e rms %.3e\n",
              c.method, c.perturbation, before.max_relative, before.rms_relative,
              before.worst_particle, after.max_relative, after.rms_relative);
  EXPECT_GT(before.max_relative, 1e-3) << "the quadrature integrates the identity exactly now?";
  EXPECT_LT(after.max_relative, 1e-12);
  // The trial table is untouched: VCI corrects only the test gradients.
  EXPECT_EQ(plain.trial_q.grad, vci.trial_q.grad);
  EXPECT_NE(plain.test_q.grad, vci.test_q.grad);
}

TEST_P(Vci, PassesThePatchTestToRoundOff) {
  const VciCase& c = GetParam();
  CaseSpec spec{"elastic-patch", {}, c.method, Params::parse("vci=true"), 7, c.perturbation};
  const CaseResult r = run_case(test_catalogue(), spec);
  CaseSpec without = spec;
  without.method_params = Params();
  const CaseResult plain = run_case(test_catalogue(), without);
  std::printf("[ patch    ] %-7s perturbation %.1f: relative L2 %.3e without VCI, %.3e with\n",
              c.method, c.perturbation, plain.errors.l2_rel, r.errors.l2_rel);
  EXPECT_LT(r.errors.l2_rel, 1e-10) << c.method;
  EXPECT_LT(r.errors.energy_rel, 1e-10) << c.method;
  EXPECT_GT(plain.errors.l2_rel, 1e-4) << c.method << " passes without VCI now?";
}

INSTANTIATE_TEST_SUITE_P(NodalAndStressPoint, Vci, ::testing::ValuesIn(kCases), case_name);

TEST(VciMethod, KeepsTheDivergenceIdentityOnCellRulesAndCollocation) {
  // The decorator is generic: Gauss cells (their own boundary rule) and the collocation
  // methods (test values are deltas at the boundary particles) satisfy the identity too.
  for (const char* m : {"kbm-ci", "efg-ci", "rlm", "sph"}) {
    const Discretization d = discretize(m, "vci=true", 0.2);
    EXPECT_LT(summarize_defect(d, divergence_defect(d)).max_relative, 1e-12) << m;
  }
}

TEST(VciMethod, RefusesEulerianRetabulation) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  const auto m = test_catalogue().methods.create("kbm-si", Params::parse("vci=true"));
  Discretization d = m->discretize(p->domain(), p->particles(5, 0), 1);
  EXPECT_THROW(m->retabulate(d, 1), InputError);
}

TEST(VciMethod, RefusesAValueOtherThanTrueOrFalse) {
  EXPECT_THROW(test_catalogue().methods.create("kbm-si", Params::parse("vci=yes")), InputError);
}

Verdict verdict(const char* problem, const std::string& id, const std::vector<StudySummary>& s) {
  for (const auto& f : test_catalogue().problems.create(problem)->findings())
    if (f.id == id) return f.check(s);
  return {"no such finding", ""};
}

TEST(VciFindings, CantileverRateWithVciIsItsOwnRow) {
  StudySummary plain, vci;
  plain.method = vci.method = "kbm-si";
  plain.label = "kbm-si";
  vci.label = "kbm-si vci=true";
  vci.params = Params::parse("vci=true");
  plain.resolutions = vci.resolutions = 4;
  plain.l2_rate = 0.3;
  vci.l2_rate = 1.48;
  EXPECT_EQ(verdict("cantilever", "kbm-si-rate", {plain, vci}).status, "not reproduced");
  EXPECT_EQ(verdict("cantilever", "kbm-si-rate-vci", {plain, vci}).status, "not reproduced");
  vci.l2_rate = 1.95;
  // The plain finding ignores the VCI study, the VCI finding reads it under its reading.
  EXPECT_EQ(verdict("cantilever", "kbm-si-rate", {plain, vci}).status, "not reproduced");
  EXPECT_EQ(verdict("cantilever", "kbm-si-rate-vci", {plain, vci}).status,
            "reproduced under a stated reading");
  EXPECT_EQ(verdict("cantilever", "kbm-si-rate-vci", {plain}).status, "not run");
}

TEST(VciFindings, Table1ReadingsAreCheckedPerColumn) {
  // Two columns of the derived reading at the table's 21/41/81-node rows: one within the
  // tolerance (j = 2), one not (j = 0.5).
  auto study = [](double j, std::vector<double> peaks, const char* rule) {
    StudySummary s;
    s.method = "rkpm";
    s.params = Params::parse(fmt::format("kernel=gaussian,j={},rule={}", j, rule));
    s.resolutions = static_cast<int>(peaks.size());
    s.finest_nodes = 81;
    for (double p : peaks) s.headlines.push_back({{"peak du/dx at x=3", p}});
    return s;
  };
  const std::vector<StudySummary> all = {study(2, {5.3157, 8.3102, 9.8421}, "derived"),
                                         study(0.5, {3.3302, 6.0648, 8.4982}, "derived")};
  const Verdict v = verdict("laplace-tanh", "table1-derived", all);
  EXPECT_EQ(v.status, "partly") << v.ours;
  EXPECT_NE(v.ours.find("j=0.5: max |diff| 0.2951 (fails)"), std::string::npos) << v.ours;
  EXPECT_EQ(verdict("laplace-tanh", "table1-literal", all).status, "not run");
}

double peak(const char* params, int nodes) {
  CaseSpec spec{"laplace-tanh", {}, "rkpm", Params::parse(params), nodes, 0};
  return run_case(test_catalogue(), spec).headline.at("peak du/dx at x=3");
}

TEST(Table1Readings, DerivedWindowIsTwoToTheJSpacingsOverPi) {
  // rule=derived: a = 2^j Δx/π, the same discretization as rule=custom with that scale.
  EXPECT_DOUBLE_EQ(peak("kernel=gaussian,j=2,rule=derived", 41),
                   peak("kernel=gaussian,j=2,rule=custom,scale=0.3183098861837907", 41));
  EXPECT_DOUBLE_EQ(peak("kernel=gaussian,j=1,rule=fit", 41),
                   peak("kernel=gaussian,j=1,rule=custom,scale=0.3297", 41));
  // Neither reading exists for the cubic window.
  EXPECT_THROW(test_catalogue().methods.create("rkpm", Params::parse("kernel=cubic-window,rule=derived")),
               InputError);
}

TEST(Table1Readings, DerivedReadingMatchesTheWideColumnsNotTheNarrowOnes) {
  // 004 II Table 1 at 41 nodes: j = 1.5 and 2 within 0.01 (measured 0.003, 0.001), j = 0.5
  // off by more than 0.1 (measured 0.30: the narrow window is where the reading fails).
  EXPECT_NEAR(peak("kernel=gaussian,j=1.5,rule=derived", 41), 7.6968, 0.01);
  EXPECT_NEAR(peak("kernel=gaussian,j=2,rule=derived", 41), 8.3095, 0.01);
  EXPECT_GT(std::abs(peak("kernel=gaussian,j=0.5,rule=derived", 41) - 6.3599), 0.1);
}

}  // namespace
}  // namespace mfv
