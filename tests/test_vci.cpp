/// Variationally consistent integration (methods/methods/vci.*): the divergence-identity defect
/// of the test functions per particle under nodal and stress-point quadrature, its removal by
/// VCI, the elastic patch test passed to round-off with vci=true, and the refusals; plus the
/// RKPM window readings of 004 II Table 1 (rule=derived|fit|eq7.4).
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "methods/methods/vci.hpp"
#include "test_support.hpp"
#include "verify/reference_studies.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

/// Every method that declares a vci parameter, on uniform and perturbed lattices.
class Vci : public ::testing::TestWithParam<std::tuple<std::string, double>> {};

std::optional<Discretization> discretize(const std::string& method, const char* params,
                                         double perturbation, std::string& refusal) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  return discretize_if_supported(method, Params::parse(params), p->domain(),
                                 p->particles(7, perturbation), refusal);
}

/// Nodal and stress-point sums (001's nodal methods) leave a defect in the divergence identity
/// where supports are cut by the edges; Gauss cells nearly integrate it.
bool nodal_sums(const Discretization& d) { return d.quadrature.kind != "gauss-cells"; }

TEST_P(Vci, DefectOfTheDivergenceIdentityIsRemoved) {
  // Σ_q w_q ∇Ψ_I(x_q) − Σ_b w_b Ψ_I(x_b) n_b per particle: O(1) relative where supports are
  // cut by the edges under nodal and stress-point sums; VCI makes it vanish to round-off.
  const auto& [method, perturbation] = GetParam();
  std::string refusal;
  const auto plain = discretize(method, "", perturbation, refusal);
  if (!plain) GTEST_SKIP() << refusal;
  const DefectSummary before = summarize_defect(*plain, divergence_defect(*plain));
  const auto vci = discretize(method, "vci=true", perturbation, refusal);
  ASSERT_TRUE(vci) << refusal;
  const DefectSummary after = summarize_defect(*vci, divergence_defect(*vci));
  std::printf("[ defect   ] %-7s perturbation %.1f: max %.3e rms %.3e (particle %d); vci: max "
              "%.3e rms %.3e\n",
              method.c_str(), perturbation, before.max_relative, before.rms_relative,
              before.worst_particle, after.max_relative, after.rms_relative);
  if (nodal_sums(*plain)) {
    EXPECT_GT(before.max_relative, 1e-3) << "the quadrature integrates the identity exactly now?";
  }
  EXPECT_LT(after.max_relative, 1e-12);
  // The trial table is untouched: VCI corrects only the test gradients.
  EXPECT_EQ(plain->trial_q.grad, vci->trial_q.grad);
  EXPECT_NE(plain->test_q.grad, vci->test_q.grad);
}

TEST_P(Vci, PassesThePatchTestToRoundOffWhenLinearlyConsistent) {
  // With the identity restored, a linearly consistent method on nodal or stress-point sums
  // passes; on Gauss cells the patch error is not the identity's (measured: VCI changes it
  // by under 1%), and without linear consistency (SPH) nothing is reproduced to restore.
  const auto& [method, perturbation] = GetParam();
  std::string refusal;
  const auto d = discretize(method, "", perturbation, refusal);
  if (!d) GTEST_SKIP() << refusal;
  if (!nodal_sums(*d) || d->consistency() < 1)
    GTEST_SKIP() << method << ": " << d->quadrature.kind << " rule, consistency "
                 << d->consistency() << "; VCI alone does not make it pass";
  CaseSpec spec{"elastic-patch", {}, method, Params::parse("vci=true"), 7, perturbation};
  const CaseResult r = run_case(test_catalogue(), spec);
  CaseSpec without = spec;
  without.method_params = Params();
  const CaseResult plain = run_case(test_catalogue(), without);
  std::printf("[ patch    ] %-7s perturbation %.1f: relative L2 %.3e without VCI, %.3e with\n",
              method.c_str(), perturbation, plain.errors.l2_rel, r.errors.l2_rel);
  EXPECT_LT(r.errors.l2_rel, 1e-10) << method;
  EXPECT_LT(r.errors.energy_rel, 1e-10) << method;
  EXPECT_GT(plain.errors.l2_rel, 1e-4) << method << " passes without VCI now?";
}

std::string case_name(const ::testing::TestParamInfo<std::tuple<std::string, double>>& info) {
  return test_name(std::get<0>(info.param)) +
         (std::get<1>(info.param) > 0 ? "_perturbed" : "_uniform");
}

INSTANTIATE_TEST_SUITE_P(EveryVciMethod, Vci,
                         ::testing::Combine(::testing::ValuesIn(methods_with_parameter("vci")),
                                            ::testing::Values(0.0, 0.3)),
                         case_name);

class VciDecorator : public ::testing::TestWithParam<std::string> {};

TEST_P(VciDecorator, KeepsTheDivergenceIdentityOnEveryRule) {
  // The decorator is generic: Gauss cells (their own boundary rule) and the collocation
  // methods (test values are deltas at the boundary particles) satisfy the identity too.
  std::string refusal;
  const auto d = discretize(GetParam(), "vci=true", 0.2, refusal);
  if (!d) GTEST_SKIP() << refusal;
  EXPECT_LT(summarize_defect(*d, divergence_defect(*d)).max_relative, 1e-12) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(EveryVciMethod, VciDecorator,
                         ::testing::ValuesIn(methods_with_parameter("vci")),
                         [](const auto& info) { return test_name(info.param); });

/// Quadratic VCI (issue 43): both divergence identities hold to round-off afterwards, on every
/// rule of every method that declares vci.
TEST_P(VciDecorator, QuadraticKeepsBothDivergenceIdentities) {
  std::string refusal;
  const auto d = discretize(GetParam(), "vci=quadratic", 0.2, refusal);
  if (!d) GTEST_SKIP() << refusal;
  EXPECT_LT(summarize_defect(*d, divergence_defect(*d)).max_relative, 1e-12) << GetParam();
  const Eigen::MatrixXd d2 = second_divergence_defect(*d);
  // Relative to the size of the sums that cancel: Σ_q w_q |∇Ψ_I| |x_q| ~ the support's extent.
  EXPECT_LT(d2.cwiseAbs().maxCoeff(), 1e-11 * (1 + d->particles.x.cwiseAbs().maxCoeff()))
      << GetParam();
}

/// The cause of kbm-si's stall (issue 43), measured on the 1D manufactured solution: at every
/// interior particle the Shepard test functions (not linearly complete, 001 eq 28) leave the
/// second identity Σ_q w_q (Ψ_I′ x_q + Ψ_I) = 0 unmet under stress-point sums, and near the
/// ends the first one Σ_q w_q Ψ_I′ = [Ψ_I] too; MLS test functions (efg-ni) meet the second
/// in the interior. tests/reference/kbm_1d.py computes the same defects independently.
Discretization mms_1d(const char* method, const char* params, int nodes) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("mms-poisson-1d");
  return test_catalogue().methods.create(method, Params::parse(params))
      ->discretize(p->domain(), p->particles(nodes, 0), 1);
}

TEST(VciCause, ShepardTestsMissTheSecondIdentityInTheInterior) {
  const Discretization kbm = mms_1d("kbm-si", "", 41);
  const Eigen::MatrixXd d2 = second_divergence_defect(kbm), d1 = divergence_defect(kbm);
  const double h = kbm.particles.spacing;
  double interior2 = 0, boundary1 = 0, interior1 = 0;
  for (int I = 0; I < kbm.particles.size(); ++I) {
    const double x = kbm.particles.x(0, I);
    const bool interior = x > 6 * h && x < 2 - 6 * h;
    if (interior) {
      interior2 = std::max(interior2, std::abs(d2(0, I)) / h);
      interior1 = std::max(interior1, std::abs(d1(0, I)));
    } else {
      boundary1 = std::max(boundary1, std::abs(d1(0, I)));
    }
  }
  std::printf("[ cause    ] kbm-si 41 nodes: interior |d2|/h %.3e, |d1| interior %.1e, near the "
              "ends %.3e\n", interior2, interior1, boundary1);
  EXPECT_GT(interior2, 1e-3) << "the interior quadrature meets the second identity now?";
  EXPECT_LT(interior1, 1e-12);
  EXPECT_GT(boundary1, 1e-3);
  // The same rule with MLS test functions (EFG with stress points) meets it in the interior.
  const Discretization efg = mms_1d("efg", "integration=stress-points", 41);
  const Eigen::MatrixXd e2 = second_divergence_defect(efg);
  double efg_interior = 0;
  for (int I = 0; I < efg.particles.size(); ++I) {
    const double x = efg.particles.x(0, I);
    if (x > 6 * h && x < 2 - 6 * h) efg_interior = std::max(efg_interior, std::abs(e2(0, I)) / h);
  }
  EXPECT_LT(efg_interior, 1e-10);
}

StudyResult mms_study(const char* params) {
  CaseSpec spec{"mms-poisson-1d", {}, "kbm-si", Params::parse(params), 0, 0};
  return run_study(test_catalogue(), spec, {11, 21, 41, 81, 161, 321});
}

TEST(VciCause, KbmSiStallsAsWrittenAndConvergesAtTwoWithQuadraticVci) {
  const StudyResult plain = mms_study("");
  const StudyResult linear = mms_study("vci=linear");
  const StudyResult quadratic = mms_study("vci=quadratic");
  auto finest = [](const StudyResult& s) { return s.cases.back().errors.l2_rel; };
  auto smallest = [](const StudyResult& s) {
    double m = INFINITY;
    for (const auto& c : s.cases) m = std::min(m, c.errors.l2_rel);
    return m;
  };
  std::printf("[ mms 1d   ] kbm-si L2 rate %.2f (finest %.2e, smallest %.2e); vci=linear %.2f "
              "(%.2e); vci=quadratic %.2f (%.2e), H1 %.2f\n",
              plain.rates.rate("L2"), finest(plain), smallest(plain), linear.rates.rate("L2"),
              finest(linear), quadratic.rates.rate("L2"), finest(quadratic),
              quadratic.rates.rate("H1-semi"));
  // As 001 writes it: the error stops falling (the finest is not the smallest).
  EXPECT_GT(finest(plain), 1.2 * smallest(plain));
  EXPECT_LT(plain.rates.rate("L2"), 1.2);
  // Linear VCI fixes the boundary defect only: the interior one still stalls it.
  EXPECT_LT(linear.rates.pairwise_of("L2").back(), 1.0);
  // Quadratic VCI: second order in L2, every pair.
  EXPECT_GT(quadratic.rates.rate("L2"), 1.9);
  for (double r : quadratic.rates.pairwise_of("L2")) EXPECT_GT(r, 1.8);
  EXPECT_GT(quadratic.rates.rate("H1-semi"), 1.2);
}

/// mfv's kbm-si, as 001 writes it and with either VCI order, equals the independent numpy
/// implementations (tests/reference/, no code shared) study by study: the stall is the
/// method's, not ours. The recorded studies are the ones the ledger's independent checks
/// read; reference/<name> re-runs the scripts against them.
class ReferenceAgreement : public ::testing::TestWithParam<std::string> {};

TEST_P(ReferenceAgreement, KbmSiEqualsTheIndependentImplementation) {
  const auto file = std::filesystem::path(MFV_SOURCE_DIR) / "tests" / "reference" / GetParam();
  for (const StudyResult& ref : load_reference_studies(file)) {
    const CaseResult& first = ref.cases.front();
    std::vector<int> nodes;
    for (const auto& c : ref.cases) nodes.push_back(c.spec.nodes);
    CaseSpec spec{first.spec.problem, first.spec.problem_params, first.spec.method,
                  first.spec.method_params, 0, 0};
    const StudyResult ours = run_study(test_catalogue(), spec, nodes);
    ASSERT_EQ(ours.cases.size(), ref.cases.size());
    for (std::size_t k = 0; k < ref.cases.size(); ++k) {
      // 1e-5: the two compute the error norm on different fine rules (measured: 2e-6 apart).
      EXPECT_NEAR(ours.cases[k].errors.l2_rel / ref.cases[k].errors.l2_rel, 1.0, 1e-5)
          << ref.label << " at " << nodes[k];
      EXPECT_EQ(ours.cases[k].particles, ref.cases[k].particles) << ref.label;
    }
    std::printf("[ reference] %-36s L2 rate ours %.4f, independent %.4f\n", ref.label.c_str(),
                ours.rates.rate("L2"), ref.rates.rate("L2"));
  }
}

INSTANTIATE_TEST_SUITE_P(Kbm, ReferenceAgreement,
                         ::testing::Values("kbm_1d.json", "kbm_cantilever_2d.json"),
                         [](const auto& info) {
                           return test_name(info.param.substr(0, info.param.find('.')));
                         });

TEST(VciMethod, RefusesEulerianRetabulation) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  const auto m = test_catalogue().methods.create("kbm-si", Params::parse("vci=true"));
  Discretization d = m->discretize(p->domain(), p->particles(5, 0), 1);
  EXPECT_THROW(m->retabulate(d, 1), InputError);
}

TEST(VciMethod, RefusesAValueThatIsNotAnOrder) {
  EXPECT_THROW(test_catalogue().methods.create("kbm-si", Params::parse("vci=yes")), InputError);
  EXPECT_THROW(test_catalogue().methods.create("kbm-si", Params::parse("vci=cubic")), InputError);
  EXPECT_NO_THROW(test_catalogue().methods.create("kbm-si", Params::parse("vci=quadratic")));
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
