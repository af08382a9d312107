// The compressed plate of 001 §9.4: the band-angle fit and the oscillation growth fit on
// synthetic fields with known answers, the problem's refusal of bad parameters, and a small
// run to the end with finite fields.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "analyses/case.hpp"
#include "problems/plate_measures.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

constexpr double kPi = std::numbers::pi;

/// A 41 × 41 lattice on [−1, 1]² and a Gaussian ridge of width `w` through `through` along
/// the direction at `deg` degrees to the y axis (d = (sin φ, cos φ)), over a weak background.
void ridge(double deg, const Eigen::Vector2d& through, double w, Eigen::MatrixXd& x,
           Eigen::VectorXd& e, double amplitude = 1.0) {
  const int n = 41;
  if (x.cols() != n * n) {
    x.resize(2, n * n);
    e = Eigen::VectorXd::Constant(n * n, 0.01);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) x.col(i + n * j) << -1 + 2.0 * i / (n - 1), -1 + 2.0 * j / (n - 1);
  }
  const double phi = deg * kPi / 180;
  const Eigen::Vector2d normal(std::cos(phi), -std::sin(phi));
  for (int k = 0; k < x.cols(); ++k) {
    const double s = normal.dot(x.col(k) - through);
    e[k] += amplitude * std::exp(-s * s / (2 * w * w));
  }
}

TEST(PlateBandFit, RecoversA45DegreeBand) {
  Eigen::MatrixXd x;
  Eigen::VectorXd e;
  ridge(45, {0, 0}, 0.05, x, e);
  const PlateBandFit f = fit_band_angles(x, e, 41);
  EXPECT_NEAR(f.angle, 45, 1.0);
  EXPECT_NEAR(f.angle_plus, 45, 1.0);
  EXPECT_EQ(f.families, 1);
  EXPECT_GT(f.strength_plus, 2 * f.strength_minus);
}

TEST(PlateBandFit, RecoversA30DegreeBandOffCentreAndOfTheOtherFamily) {
  Eigen::MatrixXd x;
  Eigen::VectorXd e;
  ridge(-30, {0.2, -0.1}, 0.05, x, e);
  const PlateBandFit f = fit_band_angles(x, e, 41);
  EXPECT_NEAR(f.angle, 30, 1.5);
  EXPECT_NEAR(f.angle_minus, 30, 1.5);
  EXPECT_GT(f.strength_minus, 2 * f.strength_plus);
}

TEST(PlateBandFit, FindsBothFamiliesOfACross) {
  Eigen::MatrixXd x;
  Eigen::VectorXd e;
  ridge(45, {0, 0}, 0.05, x, e);
  ridge(-45, {0, 0}, 0.05, x, e);
  // Capped at a band's own height, as the plate caps at its band point's ε̄: otherwise only
  // the crossing, twice as high, would pass the floor.
  const PlateBandFit f = fit_band_angles(x, e.cwiseMin(1.0), 41);
  EXPECT_EQ(f.families, 2);
  EXPECT_NEAR(f.angle_plus, 45, 1.0);
  EXPECT_NEAR(f.angle_minus, 45, 1.0);
}

TEST(PlateBandFit, NoBandIsNaN) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Random(2, 50);
  const PlateBandFit f = fit_band_angles(x, Eigen::VectorXd::Zero(50), 10);
  EXPECT_TRUE(std::isnan(f.angle));
  EXPECT_TRUE(std::isnan(fit_band_angles(x, Eigen::VectorXd::Constant(50, NAN), 10).angle));
}

/// y = trend + A e^{g t} sin(ω t) on t ∈ [0, 1], 2000 samples.
void series(double g, std::vector<double>& t, std::vector<double>& y) {
  t.clear();
  y.clear();
  for (int k = 0; k < 2000; ++k) {
    const double s = k / 1999.0;
    t.push_back(s);
    y.push_back(1.0 - 0.6 * s + 0.2 * s * s + 0.01 * std::exp(g * s) * std::sin(2 * kPi * 25 * s));
  }
}

TEST(PlateOscillation, AGrowingSinusoidGivesItsRate) {
  std::vector<double> t, y;
  series(3.0, t, y);
  const OscillationFit f = oscillation_growth(t, y, 101);
  EXPECT_NEAR(f.growth_rate, 3.0, 0.15);
  EXPECT_GT(f.amplitude_ratio, 10);
  EXPECT_NEAR(f.growth_factor, std::exp(f.growth_rate * (f.peak_t.back() - f.peak_t.front())), 1e-9);
  EXPECT_GE(f.half_periods, 40);
}

TEST(PlateOscillation, ADecayingSinusoidGivesANegativeRate) {
  std::vector<double> t, y;
  series(-2.0, t, y);
  const OscillationFit f = oscillation_growth(t, y, 101);
  EXPECT_NEAR(f.growth_rate, -2.0, 0.15);
  EXPECT_LT(f.amplitude_ratio, 0.3);
}

TEST(PlateOscillation, ASmoothCurveHasNoOscillationAboveTheFloor) {
  std::vector<double> t, y;
  for (int k = 0; k < 500; ++k) {
    t.push_back(k / 499.0);
    y.push_back(1.0 - 0.5 * t.back());
  }
  const OscillationFit f = oscillation_growth(t, y, 51, 1e-6);
  EXPECT_LT(f.half_periods, 4);
  EXPECT_TRUE(std::isnan(f.growth_rate));
  EXPECT_TRUE(std::isnan(oscillation_growth({0, 1}, {0, 1}, 51).growth_rate));
}

TEST(PlateOscillation, MovingAverageKeepsALine) {
  const std::vector<double> y{1, 2, 3, 4, 5, 6, 7};
  const std::vector<double> m = moving_average(y, 5);
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(m[i], y[i], 1e-12);
}

CaseSpec plate_case(const std::string& params, int nodes = 11) {
  CaseSpec s;
  s.problem = "compressed-plate";
  s.method = "kbm-si";
  s.nodes = nodes;
  s.problem_params = Params::parse(params);
  return s;
}

TEST(CompressedPlate, BadParametersAreInputErrors) {
  for (const char* bad :
       {"velocity=0", "velocity=-1", "velocity=nan", "velocity=1e9",
        "end_strain=-0.1", "end_strain=nan", "end_strain=0.9", "imperfection_depth=0",
        "imperfection_depth=1", "imperfection_depth=nan", "imperfection_radius=0",
        "imperfection_radius=2", "imperfection_radius=-1", "hardening=0", "hardening=1e9",
        "hardening=nan", "hardening=-1e300", "yield=0", "yield=nan", "yield=1e20",
        "material=steel", "imperfection=edge"}) {
    CaseSpec s = plate_case(std::string(bad) + ",frames=0");
    EXPECT_THROW(run_case(test_catalogue(), s), InputError) << bad;
  }
  EXPECT_THROW(run_case(test_catalogue(), plate_case("frames=0", 3)), InputError);
  EXPECT_THROW(run_case(test_catalogue(), plate_case("frames=0", 100000)), InputError);
}

TEST(CompressedPlate, SmallRunReachesTheEndWithFiniteFieldsAndABand) {
  // 21 × 21 particles, linear softening to half its default strain: a band has formed from
  // the weak spot.
  const CaseResult r = run_case(
      test_catalogue(),
      plate_case("material=j2-softening,frames=2,samples=20,end_strain=0.01", 21));
  const TransientData& t = r.data<TransientData>();
  EXPECT_FALSE(t.instability.has_value()) << t.verdict();
  EXPECT_FALSE(t.stopped_early);
  EXPECT_NEAR(r.headline.at("nominal strain reached"), 0.01, 1e-6);
  EXPECT_GT(r.headline.at("min det F"), 0.5);
  EXPECT_GT(r.headline.at("max plastic strain"), 0.0);
  EXPECT_TRUE(std::isfinite(r.headline.at("band angle (deg)")));
  EXPECT_GT(r.headline.at("peak platen force (N/m)"), 0.0);
  for (const auto& f : t.frames)
    for (const auto& [name, field] : f.data) EXPECT_TRUE(field.allFinite()) << name;
  ASSERT_FALSE(t.profiles.empty());
  EXPECT_GT(t.profiles.front().x.front().size(), 10u);
}

TEST(CompressedPlate, NeedlemansLawRunsThroughTheWeakSpot) {
  // The default material, 11 × 11 to a nominal strain of 0.01: it flows (rate-dependent, the
  // engine's dt reaches it through the weak spot) with finite fields.
  const CaseResult r =
      run_case(test_catalogue(), plate_case("frames=1,samples=10,end_strain=0.01", 11));
  const TransientData& t = r.data<TransientData>();
  EXPECT_FALSE(t.instability.has_value()) << t.verdict();
  EXPECT_NEAR(r.headline.at("nominal strain reached"), 0.01, 1e-6);
  EXPECT_GT(r.headline.at("max plastic strain"), 1e-3);
  EXPECT_GT(r.headline.at("min det F"), 0.5);
  for (const auto& f : t.frames)
    for (const auto& [name, field] : f.data) EXPECT_TRUE(field.allFinite()) << name;
}


/// A synthetic study of the plate with material=viscoplastic and the headlines the
/// oscillation finding reads.
StudySummary plate_study(const std::string& frame, double growth, bool blew, double bx,
                         double by) {
  StudySummary s;
  s.method = "kbm-si";
  s.label = "kbm-si " + frame;
  s.finest_nodes = 41;
  s.problem_resolved.set("frame", frame.c_str());
  s.problem_resolved.set("material", "viscoplastic");
  s.headlines.push_back({{"oscillation growth factor", growth},
                         {"oscillation growth rate", std::log(growth)},
                         {"oscillation half-periods", 6},
                         {"unstable", blew ? 1.0 : 0.0},
                         {"unstable at (nominal strain)", blew ? 0.08 : NAN},
                         {"softening from (nominal strain)", 0.05},
                         {"blow-up particle x (mm)", bx},
                         {"blow-up particle y (mm)", by}});
  return s;
}

std::string oscillation_verdict(const std::vector<StudySummary>& studies) {
  const auto p = create_problem(test_catalogue(), "compressed-plate", Params{});
  for (const Finding& f : p->findings())
    if (f.id == "eulerian-oscillations-grow") return f.check(studies).status;
  ADD_FAILURE() << "no finding eulerian-oscillations-grow";
  return {};
}

TEST(PlateFindings, GrowthAtTheBandPointReproducesAndACornerBlowUpDoesNot) {
  const StudySummary lag = plate_study("lagrangian", 1.2, false, NAN, NAN);
  EXPECT_EQ(oscillation_verdict({lag, plate_study("eulerian", 3.0, false, NAN, NAN)}),
            "reproduced");
  // Blown up after softening with the fastest particle near the centre: unbounded growth.
  EXPECT_EQ(oscillation_verdict({lag, plate_study("eulerian", 1.1, true, 0.5, -1.0)}),
            "reproduced");
  // Blown up at a platen corner: not the band point's oscillation.
  EXPECT_EQ(oscillation_verdict({lag, plate_study("eulerian", 1.1, true, -5.0, -5.0)}),
            "not reproduced");
  // The Lagrangian run's oscillation doubling too: not 001's contrast.
  EXPECT_EQ(oscillation_verdict({plate_study("lagrangian", 3.0, false, NAN, NAN),
                                 plate_study("eulerian", 3.0, false, NAN, NAN)}),
            "not reproduced");
}

}  // namespace
}  // namespace mfv
