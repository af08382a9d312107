// The ring measurements (problems/ring_measures.hpp) on synthetic fields whose answers are
// known: a symmetric field, spots, an even and a bunched row, and log-spiral bands.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "problems/ring_measures.hpp"

namespace mfv {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(RingMeasures, SymmetricFieldHasZeroIndexAndSpotsNearOne) {
  const int rows = 4, per = 60;
  Eigen::VectorXd even(rows * per), spots(rows * per);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < per; ++j) {
      even[j + per * i] = 1e6 * (1 + i);
      spots[j + per * i] = j % 15 == 0 ? 1e6 : 0.0;  // four spots per row
    }
  EXPECT_LT(symmetry_index(even, rows, per).worst, 1e-12);
  const RowIndex s = symmetry_index(spots, rows, per);
  // Four equal spots among 60 values: std/rms = √(1 − 4/60).
  EXPECT_NEAR(s.worst, std::sqrt(1 - 4.0 / 60), 1e-12);
  EXPECT_EQ(s.per_row.size(), 4u);
}

TEST(RingMeasures, ClusteringOfAnEvenAndABunchedRow) {
  const int per = 40;
  Eigen::MatrixXd x(2, 2 * per);
  for (int j = 0; j < per; ++j) {
    const double t = 2 * kPi * j / per;
    x.col(j) << std::cos(t), std::sin(t);
    // Second row: pairs bunched, gaps alternating 0.5 and 1.5 of the mean.
    const double tb = 2 * kPi * (j + (j % 2 ? -0.25 : 0.25)) / per;
    x.col(per + j) << 2 * std::cos(tb), 2 * std::sin(tb);
  }
  const RowIndex c = clustering_index(x, 2, per);
  EXPECT_NEAR(c.per_row[0], 1.0, 1e-9);
  EXPECT_NEAR(c.per_row[1], std::sin(1.5 * kPi / per) / std::sin(0.5 * kPi / per), 1e-9);
  EXPECT_EQ(c.row, 1);
}

TEST(RingMeasures, PolarComponentsOfAUniformHydrostaticAndARotatedStress) {
  const double p[4] = {-3, 0, 0, -3};
  for (double th : {0.0, 0.7, 2.5, -1.2}) {
    const Eigen::Vector2d x(std::cos(th), std::sin(th));
    EXPECT_NEAR(hoop_stress(x, p), -3, 1e-12);
    EXPECT_NEAR(radial_stress(x, p), -3, 1e-12);
    // σ = s_rr e⊗e + s_tt t⊗t in Cartesian components.
    const double c = std::cos(th), s = std::sin(th), srr = 2, stt = 7;
    const double sig[4] = {srr * c * c + stt * s * s, (srr - stt) * c * s, (srr - stt) * c * s,
                           srr * s * s + stt * c * c};
    EXPECT_NEAR(hoop_stress(x, sig), stt, 1e-12);
    EXPECT_NEAR(radial_stress(x, sig), srr, 1e-12);
  }
}

/// Points on a polar lattice of a ring b/a = 4/3 with plastic strain concentrated on the
/// spirals θ = θ0 ± ζ·tan ψ.
struct Field {
  Eigen::VectorXd zeta, theta, eps;
};
Field spiral_field(double psi_deg, bool both, int bands) {
  const int nr = 7, nt = 150;
  Field f;
  f.zeta.resize(nr * nt);
  f.theta.resize(nr * nt);
  f.eps.resize(nr * nt);
  const double zmax = std::log(4.0 / 3.0), s = std::tan(psi_deg * kPi / 180);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> noise(-0.002, 0.002);
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nt; ++j) {
      const int k = j + nt * i;
      f.zeta[k] = zmax * i / (nr - 1);
      f.theta[k] = 2 * kPi * j / nt;
      double e = 0.01 * (1 - 0.5 * i / (nr - 1)) + noise(rng);  // falls through the wall
      for (int b = 0; b < bands; ++b) {
        const double t0 = 2 * kPi * b / bands + 0.3;
        for (double sign : {1.0, -1.0}) {
          if (sign < 0 && !both) continue;
          double d = std::remainder(f.theta[k] - t0 - sign * s * f.zeta[k], 2 * kPi);
          e += 0.05 * std::exp(-d * d / (2 * 0.05 * 0.05));
        }
      }
      f.eps[k] = e;
    }
  return f;
}

TEST(RingMeasures, BandFitRecoversBothFamiliesAt45Degrees) {
  const Field f = spiral_field(45, true, 4);
  const BandFit fit = fit_log_spiral_bands(f.zeta, f.theta, f.eps, 7, 150);
  EXPECT_TRUE(fit.plus_present);
  EXPECT_TRUE(fit.minus_present);
  EXPECT_NEAR(fit.angle_plus, 45, 4);
  EXPECT_NEAR(fit.angle_minus, 45, 4);
  EXPECT_GE(fit.bands, 4);
  EXPECT_GT(fit.contrast, 0.5);
}

TEST(RingMeasures, BandFitTellsOneFamilyAndOtherAngles) {
  const Field one = spiral_field(30, false, 5);
  const BandFit fit = fit_log_spiral_bands(one.zeta, one.theta, one.eps, 7, 150);
  EXPECT_TRUE(fit.plus_present);
  EXPECT_NEAR(fit.angle_plus, 30, 4);
  EXPECT_FALSE(fit.minus_present);
  EXPECT_EQ(fit.bands, 5);
}

TEST(RingMeasures, NoBandsInAnAxisymmetricField) {
  Field f = spiral_field(45, true, 0);
  const BandFit fit = fit_log_spiral_bands(f.zeta, f.theta, f.eps, 7, 150);
  EXPECT_LT(fit.contrast, 0.2);
}

TEST(RingMeasures, BadShapesAreInputErrors) {
  EXPECT_THROW(symmetry_index(Eigen::VectorXd::Zero(10), 3, 4), InputError);
  EXPECT_THROW(clustering_index(Eigen::MatrixXd::Zero(2, 5), 1, 2), InputError);
  EXPECT_THROW(fit_log_spiral_bands(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(2),
                                    Eigen::VectorXd::Zero(3), 1, 8),
               InputError);
  EXPECT_THROW(fit_log_spiral_bands(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3),
                                    Eigen::VectorXd::Zero(3), 1, 8, 3.0, 0.0),
               InputError);
}

}  // namespace
}  // namespace mfv
