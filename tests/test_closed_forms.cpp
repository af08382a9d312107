/// The closed-form dispersion relations of 000 §3–4 (stability/closed_forms.*) checked against
/// the paper's findings, and the `rubber` material (000 eq 5.1) with its strong-ellipticity map.
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "stability/closed_forms.hpp"
#include "stability/material_stability.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

namespace cf = closed_form;

std::unique_ptr<Kernel> kernel(const std::string& name) {
  return test_catalogue().kernels.create(name);
}

void record(const std::string& key, double value) {
  ::testing::Test::RecordProperty(key, fmt::format("{:.6g}", value));
  std::cout << "  [closed forms] " << key << " = " << fmt::format("{:.6g}", value) << "\n";
}

// ───────────────────────────── 1D ─────────────────────────────

TEST(ClosedForm1D, CorrectionFactorFromDefinition) {
  // Quartic spline, D_mx = 1.5: W(2/3) = 1/9, W'(2/3) = −8/9 per unit s, h = 1.5 Δx:
  // w'(Δx) = −(8/9)/1.5/(11/9) = −16/33, a = 1/(2·16/33) = 33/32.
  const auto W = kernel("quartic-spline");
  EXPECT_NEAR(cf::correction_factor_1d(*W, 1.5), 33.0 / 32.0, 1e-13);
  for (const char* name : {"quartic-spline", "exponential"})
    for (double dmx : {1.5, 2.0, 2.5}) {
      const auto K = kernel(name);
      const double am = cf::correction_factor_1d(*K, dmx, 0.0);
      const double as = cf::correction_factor_1d(*K, dmx, 0.5);
      record(fmt::format("a_m {} Dmx={}", name, dmx), am);
      record(fmt::format("a_s {} Dmx={}", name, dmx), as);
      EXPECT_GT(am, 0.5);
      EXPECT_LT(am, 2.0);
      EXPECT_GT(as, 0.5);
      EXPECT_LT(as, 2.0);
    }
}

TEST(ClosedForm1D, LagrangianNodalZeroAtCutoffForAnyModulusAndSupport) {
  for (const char* name : {"quartic-spline", "exponential"})
    for (double dmx : {1.2, 1.5, 2.0, 2.5, 3.3})
      for (double C : {-2.0, 0.0, 0.7, 5.0}) {
        const auto W = kernel(name);
        EXPECT_NEAR(cf::omega2_lagrangian_nodal_1d(*W, dmx, 0.1, M_PI / 0.1, C, 2.0), 0.0,
                    1e-20)
            << name << " Dmx " << dmx << " C " << C;
      }
}

TEST(ClosedForm1D, LagrangianNodalUnstableExactlyWhenModulusNegative) {
  const auto W = kernel("quartic-spline");
  for (double dmx : {1.5, 2.5})
    for (int i = 1; i < 100; ++i) {
      const double k = M_PI * i / 100;
      EXPECT_GT(cf::omega2_lagrangian_nodal_1d(*W, dmx, 1, k, 1.0, 1), 0);
      EXPECT_LT(cf::omega2_lagrangian_nodal_1d(*W, dmx, 1, k, -1.0, 1), 0);
      EXPECT_EQ(cf::omega2_lagrangian_nodal_1d(*W, dmx, 1, k, 0.0, 1), 0);
      // Stable domain (000 Fig. 5): σ̄* = −1 at every κ, stable above for C^{σT} > 0.
      const auto tp = cf::stable_threshold_lagrangian_1d(*W, dmx, k, 1.0);
      const auto tn = cf::stable_threshold_lagrangian_1d(*W, dmx, k, -1.0);
      EXPECT_EQ(tp.sigma_bar, -1.0);
      EXPECT_TRUE(tp.stable_above);
      EXPECT_EQ(tn.sigma_bar, -1.0);
      EXPECT_FALSE(tn.stable_above);
    }
  EXPECT_TRUE(std::isnan(cf::stable_threshold_lagrangian_1d(*W, 1.5, M_PI, 1.0).sigma_bar));
}

// Small κ: the discrete wave speed. The test gradient is the uncorrected w_{,X}, so eq 3.12
// tends to C̄/(aρ) exactly and to the continuum C̄/ρ only up to a − 1 (closed_forms.hpp D1).
TEST(ClosedForm1D, SmallWavenumberLimit) {
  for (const char* name : {"quartic-spline", "exponential"})
    for (double dmx : {1.5, 2.0, 2.5}) {
      const auto W = kernel(name);
      const double dx = 0.01, k = 1e-4 / dx, C = 3.0, rho = 2.0;
      const double am = cf::correction_factor_1d(*W, dmx, 0.0);
      const double as = cf::correction_factor_1d(*W, dmx, 0.5);
      const double lag = cf::omega2_lagrangian_nodal_1d(*W, dmx, dx, k, C, rho) / (k * k);
      EXPECT_NEAR(lag, C / (am * rho), 1e-6 * C / rho);
      const double sp = cf::omega2_lagrangian_stress_points_1d(*W, dmx, dx, k, C, rho) / (k * k);
      EXPECT_NEAR(sp, C / (2 * rho) * (1 / am + 1 / as), 1e-6 * C / rho);
      // Eulerian: C̄' = C^{σT} + σ is the continuum modulus of the current configuration.
      const double sigma = 0.4;
      const double eul =
          cf::omega2_eulerian_nodal_1d(*W, dmx, dx, k, C, sigma, rho) / (k * k);
      // Quartic spline, D_mx = 1.5: only j = ±1 enter; w'' (Δx) = W''(2/3)/(h² S0) = 16/11 and
      // Σ_j w''(jΔx) j²Δx²/2 = 16/11 (not the consistent 1), so ω²/κ² → ((C + 2σ)/a − σ·16/11)/ρ.
      if (std::string(name) == "quartic-spline" && dmx == 1.5) {
        EXPECT_NEAR(eul, ((C + 2 * sigma) / am - sigma * 16.0 / 11.0) / rho, 1e-6 * C / rho);
      }
      // The quartic spline has a within 10 % of 1: the continuum speed to that accuracy. The
      // exponential weight at D_mx = 1.5 (a = 1.63) is far from it; only recorded.
      if (std::string(name) == "quartic-spline") {
        EXPECT_NEAR(lag / (C / rho), 1.0, 0.1) << name << " " << dmx;
        EXPECT_NEAR(sp / (C / rho), 1.0, 0.1) << name << " " << dmx;
        EXPECT_NEAR(eul / ((C + sigma) / rho), 1.0, 0.1) << name << " " << dmx;
      }
      record(fmt::format("c^2 ratio lagrangian nodal {} Dmx={}", name, dmx), lag / (C / rho));
      record(fmt::format("c^2 ratio stress points {} Dmx={}", name, dmx), sp / (C / rho));
      record(fmt::format("c^2 ratio eulerian nodal sigma/C=0.133 {} Dmx={}", name, dmx),
             eul / ((C + sigma) / rho));
    }
}

TEST(ClosedForm1D, EulerianNodalAgreesWithLagrangianWithoutStress) {
  // With σ = 0 eq 3.18 is eq 3.12 (C̄' = C^{σT} = C̄).
  const auto W = kernel("quartic-spline");
  for (int i = 0; i <= 50; ++i) {
    const double k = M_PI * i / 50;
    EXPECT_NEAR(cf::omega2_eulerian_nodal_1d(*W, 2.0, 1, k, 1.3, 0.0, 1.1),
                cf::omega2_lagrangian_nodal_1d(*W, 2.0, 1, k, 1.3, 1.1), 1e-14);
  }
}

TEST(ClosedForm1D, EulerianTensileInstabilityOnset) {
  const auto W = kernel("quartic-spline");
  // 000 §3.1.2, Fig. 3: σ̄ = 1, D_mx = 1.5 unstable above κ ≈ 0.6π/Δx (read off the figure).
  // Here exactly 0.5π/Δx: for D_mx = 1.5, 3a·4w'(Δx)² = 2w''(Δx), so ω² ∝ sin² − (1 − cos).
  const double onset15 = cf::onset_wavenumber_eulerian_1d(*W, 1.5, 1.0);
  record("onset kappa/(pi/dx) quartic Dmx=1.5 sigma_bar=1", onset15);
  EXPECT_NEAR(onset15, 0.5, 1e-9);
  // The onset exists for every σ̄ > 0 and falls as σ̄ grows.
  double prev = 1.0 + 1e-12;
  for (double sb : {0.01, 0.1, 0.16, 0.5, 1.0, 2.0, 5.0}) {
    const double k = cf::onset_wavenumber_eulerian_1d(*W, 1.5, sb);
    record(fmt::format("onset kappa/(pi/dx) quartic Dmx=1.5 sigma_bar={}", sb), k);
    ASSERT_FALSE(std::isnan(k)) << sb;
    EXPECT_LT(k, prev) << sb;
    prev = k;
  }
  // D_mx = 2.5: at the same σ̄ the onset is at higher κ (or absent), i.e. a larger tension is
  // needed to destabilize a given wave number.
  for (double sb : {0.1, 0.5, 1.0, 2.0}) {
    const double k15 = cf::onset_wavenumber_eulerian_1d(*W, 1.5, sb);
    const double k25 = cf::onset_wavenumber_eulerian_1d(*W, 2.5, sb);
    record(fmt::format("onset kappa/(pi/dx) quartic Dmx=2.5 sigma_bar={}", sb), k25);
    EXPECT_TRUE(std::isnan(k25) || k25 > k15) << sb;
  }
  // The tensile threshold σ̄*(κ) (000 Fig. 6a) is larger for D_mx = 2.5 wherever both are
  // tension thresholds.
  for (int i = 1; i < 20; ++i) {
    const double k = M_PI * i / 20;
    const auto t15 = cf::stable_threshold_eulerian_1d(*W, 1.5, k, 1.0);
    const auto t25 = cf::stable_threshold_eulerian_1d(*W, 2.5, k, 1.0);
    if (!t15.stable_above && !t25.stable_above && t15.sigma_bar > 0 && t25.sigma_bar > 0) {
      EXPECT_GT(t25.sigma_bar, t15.sigma_bar) << k;
    }
    // Consistency of the threshold with ω² itself.
    for (const auto& [t, dmx] : {std::pair{t15, 1.5}, std::pair{t25, 2.5}}) {
      if (!std::isfinite(t.sigma_bar)) continue;
      const double above = t.sigma_bar + 0.01, below = t.sigma_bar - 0.01;
      const double wa = cf::omega2_eulerian_nodal_1d(*W, dmx, 1, k, 1.0, above, 1.0);
      const double wb = cf::omega2_eulerian_nodal_1d(*W, dmx, 1, k, 1.0, below, 1.0);
      EXPECT_EQ(wa >= 0, t.stable_above) << k << " " << dmx;
      EXPECT_EQ(wb >= 0, !t.stable_above) << k << " " << dmx;
    }
  }
  // No tensile instability under compression with C^{σT} > 0 down to σ̄ = −0.5 at D_mx = 1.5.
  EXPECT_TRUE(std::isnan(cf::onset_wavenumber_eulerian_1d(*W, 1.5, -0.5)));
  // 000 §3.1.2: C̄' = 0 (σ̄ = −1) is stable for D_mx = 1.5, although the PDE is at its limit.
  EXPECT_TRUE(std::isnan(cf::onset_wavenumber_eulerian_1d(*W, 1.5, -1.0)));
  // C^{σT} < 0 (000 Fig. 4a): D_mx = 1.5 unstable at all wave numbers for σ̄ = 0.
  EXPECT_LT(cf::onset_wavenumber_eulerian_1d(*W, 1.5, 0.0, -1.0), 1e-3);
}

TEST(ClosedForm1D, StressPointsPositiveAtCutoffAndFallingWithSupport) {
  double prev = std::numeric_limits<double>::infinity();
  for (double dmx : {1.5, 2.0, 2.5}) {
    const auto W = kernel("quartic-spline");
    const double w2 = cf::omega2_lagrangian_stress_points_1d(*W, dmx, 1, M_PI, 1, 1);
    record(fmt::format("stress points omega(pi/dx)/c quartic Dmx={}", dmx), std::sqrt(w2));
    EXPECT_GT(w2, 1e-3);
    EXPECT_LT(w2, prev);
    prev = w2;
    // No zero anywhere in (0, π]: rank deficiency removed.
    for (int i = 1; i <= 200; ++i)
      EXPECT_GT(cf::omega2_lagrangian_stress_points_1d(*W, dmx, 1, M_PI * i / 200, 1, 1), 0);
  }
  // Exponential weight: more concentrated, "more stable" (000 Fig. 7b). Read as the cut-off
  // frequency ω(π/Δx)/c, larger than the quartic spline's for every D_mx; relative to each
  // branch's own peak it is larger for D_mx = 2, 2.5 and equal (= 1, both branches rise up to
  // the cut-off) for D_mx = 1.5.
  for (double dmx : {1.5, 2.0, 2.5}) {
    double rel[2], cut[2];
    int n = 0;
    for (const char* name : {"quartic-spline", "exponential"}) {
      const auto W = kernel(name);
      double peak = 0;
      for (int i = 1; i <= 400; ++i)
        peak = std::max(peak, cf::omega2_lagrangian_stress_points_1d(*W, dmx, 1, M_PI * i / 400,
                                                                     1, 1));
      cut[n] = cf::omega2_lagrangian_stress_points_1d(*W, dmx, 1, M_PI, 1, 1);
      rel[n] = std::sqrt(cut[n] / peak);
      record(fmt::format("stress points omega(pi)/omega_peak {} Dmx={}", name, dmx), rel[n]);
      record(fmt::format("stress points omega(pi)/c {} Dmx={}", name, dmx), std::sqrt(cut[n]));
      ++n;
    }
    EXPECT_GT(cut[1], cut[0]) << dmx;
    if (dmx > 1.5) {
      EXPECT_GT(rel[1], rel[0] + 0.1) << dmx;
    } else {
      EXPECT_NEAR(rel[0], 1.0, 1e-12);
      EXPECT_NEAR(rel[1], 1.0, 1e-12);
    }
  }
}

TEST(ClosedForm1D, StressPointCutoffMatchesEq325) {
  // At κ = π/Δx eq 3.23 reduces to (a_s C̄/2ρ0)(Σ w̄ s̄)² with the master sum zero (3.25).
  const auto W = kernel("quartic-spline");
  const double as = cf::correction_factor_1d(*W, 1.5, 0.5);
  // D_mx = 1.5: midpoints at ±0.5Δx (s = 1/3) and ±1.5Δx (s = 1, W = 0): b = 0 in eq 3.27.
  auto Wq = [](double s) { return 1 - 6 * s * s + 8 * s * s * s - 3 * s * s * s * s; };
  const double S = 2 * Wq(1.0 / 3);
  const double a = 12 * (1.0 / 3) * (2.0 / 3) * (2.0 / 3) / 1.5 / S;  // |w̄'(Δx/2)|
  EXPECT_NEAR(cf::omega2_lagrangian_stress_points_1d(*W, 1.5, 1, M_PI, 1, 1),
              as / 2 * std::pow(2 * a, 2), 1e-12);
}

// ───────────────────────────── 2D ─────────────────────────────

cf::Setup2D setup(cf::Lattice2D lattice, double lambda = 1.0, double mu = 1.0) {
  cf::Setup2D s;
  s.lattice = lattice;
  s.lambda = lambda;
  s.mu = mu;
  return s;
}

TEST(ClosedForm2D, CorrectionMatrixIsIsotropic) {
  const auto W = kernel("quartic-spline");
  for (auto lat : {cf::Lattice2D::rectangular, cf::Lattice2D::hexagonal}) {
    const auto s = setup(lat);
    const Eigen::Matrix2d a = cf::correction_matrix_2d(*W, s, Eigen::Vector2d::Zero());
    EXPECT_NEAR(a(0, 1), 0, 1e-13);
    EXPECT_NEAR(a(1, 0), 0, 1e-13);
    EXPECT_NEAR(a(0, 0), a(1, 1), 1e-12);
    record(fmt::format("2D a {} Dmx=1.5", lat == cf::Lattice2D::rectangular ? "rect" : "hex"),
           a(0, 0));
  }
}

TEST(ClosedForm2D, LagrangianNodalZeroFrequencyAtCutoff) {
  const auto W = kernel("quartic-spline");
  auto s = setup(cf::Lattice2D::rectangular, 1.0, 1.0);
  s.stress(0, 0) = 0.3;  // whatever the stress
  // Square lattice: θ = 0 at κ = π/Δx and θ = 45° at the zone corner √2π/Δx.
  for (auto [kappa, theta] : {std::pair{M_PI, 0.0}, std::pair{M_SQRT2 * M_PI, M_PI / 4}}) {
    const auto w = cf::omega2_lagrangian_nodal_2d(*W, s, kappa, theta);
    EXPECT_NEAR(w[0], 0, 1e-13);
    EXPECT_NEAR(w[1], 0, 1e-13);
  }
  // Hexagonal lattice: the zone-edge midpoint M, θ = 30°, κ = 2π/(√3Δx).
  auto h = setup(cf::Lattice2D::hexagonal);
  const auto w = cf::omega2_lagrangian_nodal_2d(*W, h, 2 * M_PI / std::sqrt(3.0), M_PI / 6);
  EXPECT_NEAR(w[0], 0, 1e-13);
  EXPECT_NEAR(w[1], 0, 1e-13);
}

TEST(ClosedForm2D, QuadCentreStressPointsLeaveTheCornerModeTriangleCentresRemoveIt) {
  const auto W = kernel("quartic-spline");
  auto q = setup(cf::Lattice2D::rectangular);
  // Quad centres: zero frequency at the zone corner, θ = 45°, κ = √2π/Δx.
  const auto wq = cf::omega2_lagrangian_stress_points_2d(*W, q, M_SQRT2 * M_PI, M_PI / 4);
  record("quad centres omega^2 at corner (both branches, max)", std::max(wq[0], wq[1]));
  EXPECT_NEAR(wq[0], 0, 1e-13);
  EXPECT_NEAR(wq[1], 0, 1e-13);
  // ... but not at θ = 0, κ = π/Δx, where nodal integration has it.
  const auto wq0 = cf::omega2_lagrangian_stress_points_2d(*W, q, M_PI, 0);
  EXPECT_GT(wq0[0], 1e-3);
  // Triangle centres on the hexagonal lattice: the smallest ω² over the whole Brillouin
  // zone (scanned on a grid of wave vectors away from k = 0) stays positive, in particular
  // at M where nodal integration vanishes.
  auto h = setup(cf::Lattice2D::hexagonal);
  const auto wm = cf::omega2_lagrangian_stress_points_2d(*W, h, 2 * M_PI / std::sqrt(3.0),
                                                        M_PI / 6);
  record("triangle centres omega^2 at M, lower branch", wm[0]);
  EXPECT_GT(wm[0], 1e-2);
  double lowest = std::numeric_limits<double>::infinity();
  for (int it = 0; it <= 24; ++it)
    for (int ik = 1; ik <= 40; ++ik) {
      const double theta = M_PI / 3 * it / 24;  // 60° covers the zone by symmetry
      const double kappa = 4 * M_PI / 3 * ik / 40;
      const double ratio = cf::omega2_lagrangian_stress_points_2d(*W, h, kappa, theta)[0] /
                           (kappa * kappa);
      lowest = std::min(lowest, ratio);
    }
  record("triangle centres min omega^2/kappa^2 over the zone (c^2 = mu/rho = 1)", lowest);
  EXPECT_GT(lowest, 1e-3);
}

// Small κ: as in 1D the Lagrangian branches tend to the continuum ones (acoustic tensor with
// the prestress) divided by the correction factor a (the test gradient is uncorrected): 1/a for
// nodal integration, the mean of 1/a over the kinds of points (equal Voronoi volumes) with
// stress points. The Eulerian limit also carries the second-moment error of w_{,xx}; recorded.
TEST(ClosedForm2D, SmallWavenumberGivesContinuumSpeeds) {
  const auto W = kernel("quartic-spline");
  for (auto lat : {cf::Lattice2D::rectangular, cf::Lattice2D::hexagonal})
    for (bool sp : {false, true})
      for (auto frame : {cf::Frame::lagrangian, cf::Frame::eulerian}) {
        auto s = setup(lat, 2.0, 1.0);
        s.stress_points = sp;
        s.frame = frame;
        s.stress = 0.2 * Eigen::Matrix2d::Identity();
        const double d = s.dx;
        std::vector<Eigen::Vector2d> kinds{Eigen::Vector2d::Zero()};
        if (sp && lat == cf::Lattice2D::rectangular) kinds.push_back({0.5 * d, 0.5 * d});
        if (sp && lat == cf::Lattice2D::hexagonal) {
          kinds.push_back(Eigen::Vector2d(0.5 * d, std::sqrt(3.0) / 6 * d));
          kinds.push_back(Eigen::Vector2d(d, std::sqrt(3.0) / 3 * d));
        }
        double inv_a = 0;
        for (const auto& o : kinds)
          inv_a += 1 / cf::correction_matrix_2d(*W, s, o)(0, 0) / static_cast<double>(kinds.size());
        for (double theta : {0.0, 0.3, M_PI / 4}) {
          const double k = 1e-3;
          const auto w = cf::omega2_2d(*W, s, k, theta);
          const auto c = cf::omega2_continuum_2d(s, k, theta);
          for (int b = 0; b < 2; ++b) {
            if (frame == cf::Frame::lagrangian) {
              EXPECT_NEAR(w[b] / c[b], inv_a, 1e-5);
            } else {
              EXPECT_NEAR(w[b] / c[b], 1.0, 0.2);
            }
          }
          if (theta == 0.0)
            record(fmt::format("2D c^2 ratio {} {} {} (P wave)",
                               lat == cf::Lattice2D::rectangular ? "rect" : "hex",
                               sp ? "stress-points" : "nodal",
                               frame == cf::Frame::lagrangian ? "lagrangian" : "eulerian"),
                   w[1] / c[1]);
        }
      }
}

TEST(ClosedForm2D, LagrangianStressFreeIsStableEulerianTensionIsNot) {
  const auto W = kernel("quartic-spline");
  // Lagrangian kernel, nodal: no negative ω² (no tensile instability) even at σ̄ = σ/μ = 2.
  for (auto lat : {cf::Lattice2D::rectangular, cf::Lattice2D::hexagonal}) {
    auto s = setup(lat, 1.0, 1.0);
    s.stress = 2.0 * Eigen::Matrix2d::Identity();
    for (bool sp : {false, true}) {
      s.stress_points = sp;
      for (int it = 0; it <= 6; ++it)
        for (int ik = 1; ik <= 30; ++ik) {
          const auto w = cf::omega2_2d(*W, s, M_SQRT2 * M_PI * ik / 30, M_PI / 4 * it / 6);
          EXPECT_GT(w[0], -1e-12);
        }
    }
  }
  // Eulerian kernel, nodal, σ̄ = 1 (isotropic tension): negative ω² at θ = 30° and 45°
  // (000 Fig. 10); stress points at σ̄ = 2 do not remove it (000 Fig. 12).
  auto lowest = [&](cf::Setup2D s, double theta) {
    double lo = std::numeric_limits<double>::infinity();
    for (int ik = 1; ik <= 200; ++ik)
      lo = std::min(lo, cf::omega2_2d(*W, s, M_SQRT2 * M_PI * ik / 200, theta)[0]);
    return lo;
  };
  auto e = setup(cf::Lattice2D::rectangular, 1.0, 1.0);
  e.frame = cf::Frame::eulerian;
  e.stress = Eigen::Matrix2d::Identity();
  for (double deg : {30.0, 45.0}) {
    const double lo = lowest(e, deg * M_PI / 180);
    record(fmt::format("eulerian nodal rect sigma/mu=1 theta={} min omega^2", deg), lo);
    EXPECT_LT(lo, 0);
  }
  e.stress_points = true;
  e.stress = 2 * Eigen::Matrix2d::Identity();
  for (auto lat : {cf::Lattice2D::rectangular, cf::Lattice2D::hexagonal}) {
    e.lattice = lat;
    double lo = std::numeric_limits<double>::infinity();
    for (double deg : {0.0, 15.0, 30.0, 45.0}) lo = std::min(lo, lowest(e, deg * M_PI / 180));
    record(fmt::format("eulerian stress points {} sigma/mu=2 min omega^2",
                       lat == cf::Lattice2D::rectangular ? "rect" : "hex"),
           lo);
    // Quad centres: the corner mode (zero without stress) turns negative under tension. The
    // triangle centres stay stable here, unlike 000 Fig. 12b (closed_forms.md).
    if (lat == cf::Lattice2D::rectangular) {
      EXPECT_LT(lo, 0);
    } else {
      EXPECT_GT(lo, 0);
    }
  }
  // Hexagonal nodal Eulerian: unstable at M (θ = 30°) for any tension.
  auto hx = setup(cf::Lattice2D::hexagonal, 1.0, 1.0);
  hx.frame = cf::Frame::eulerian;
  hx.stress = 0.1 * Eigen::Matrix2d::Identity();
  EXPECT_LT(cf::omega2_2d(*W, hx, 2 * M_PI / std::sqrt(3.0), M_PI / 6)[0], 0);
}

// ───────────────────────────── rubber (000 eq 5.1) ─────────────────────────────

std::unique_ptr<Material> rubber() { return test_catalogue().materials.create("rubber"); }

TEST(Rubber, StressFreeAtIdentityAndSmallStrainModuli) {
  const auto m = rubber();
  const double c1 = 1.265e5, c2 = 1.012e4, lam = 1.012e7;
  const double mu0 = c1 + c2, lambda0 = 2 * lam - 2.0 / 3.0 * (c1 + c2);
  Eigen::Matrix2d F = Eigen::Matrix2d::Identity(), P;
  m->first_piola(2, 1, F.data(), P.data(), nullptr);
  EXPECT_LT(P.norm(), 1e-6);
  // A_iJkL at F = I is λ0 δ_iJ δ_kL + μ0(δ_ik δ_JL + δ_iL δ_Jk).
  const Eigen::Matrix4d A = tangent_modulus_2d(*m, F);
  auto d = [](int i, int j) { return i == j ? 1.0 : 0.0; };
  for (int i = 0; i < 2; ++i)
    for (int J = 0; J < 2; ++J)
      for (int k = 0; k < 2; ++k)
        for (int L = 0; L < 2; ++L) {
          const double ref =
              lambda0 * d(i, J) * d(k, L) + mu0 * (d(i, k) * d(J, L) + d(i, L) * d(J, k));
          EXPECT_NEAR(A(i + 2 * J, k + 2 * L), ref, 1e-5 * lambda0) << i << J << k << L;
        }
  record("rubber mu0 = c1 + c2", mu0);
  record("rubber lambda0 = 2 lambda - 2(c1+c2)/3", lambda0);
  EXPECT_TRUE(pde_stable(*m, F));
  EXPECT_NEAR(min_acoustic_eigenvalue(*m, F), mu0, 1e-5 * lambda0);
  EXPECT_NEAR(m->wave_speed(2, 125.4), std::sqrt((lambda0 + 2 * mu0) / 125.4), 1e-9);
  // 1D (uniaxial strain) is the 11 component of the 2D state with F22 = 1.
  const double f1 = 1.1;
  double p1 = 0;
  m->first_piola(1, 1, &f1, &p1, nullptr);
  Eigen::Matrix2d F2 = Eigen::Matrix2d::Identity();
  F2(0, 0) = f1;
  m->first_piola(2, 1, F2.data(), P.data(), nullptr);
  EXPECT_NEAR(p1, P(0, 0), 1e-9 * std::abs(P(0, 0)));
}

TEST(Rubber, PrincipalStretchStabilityMap) {
  const auto m = rubber();
  // Principal stretches (λ1, λ2) in plane strain; print the map of 001 Fig. 1 (PDE).
  std::cout << "  [closed forms] rubber PDE stability, rows λ2 = 2.0 … 0.1, columns λ1 = 0.1 … "
               "2.0 ('+' stable, '.' not)\n";
  for (int j = 19; j >= 0; --j) {
    std::string row;
    for (int i = 0; i < 20; ++i) {
      Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
      F(0, 0) = 0.1 * (i + 1);
      F(1, 1) = 0.1 * (j + 1);
      row += pde_stable(*m, F, 180) ? '+' : '.';
    }
    std::cout << "  [closed forms]   " << row << "\n";
  }
  // Compression is stable: the energy behind eq 5.1 is c1/2 (I1 − 3) + c2/2 (I2 − 3) + f(J)
  // with f''(J) = c1/3 J^{-4/3} − 2c2/3 J^{-2/3} + 2λ(1 − ln J)/J² > 0 for J below ≈ e,
  // i.e. polyconvex, hence strongly elliptic, in every compressed state. Strong ellipticity is
  // lost in large dilatation (J ≳ e, where the λ ln I3 pressure softens).
  for (double l1 = 0.05; l1 <= 1.0001; l1 += 0.05)
    for (double l2 = 0.05; l2 <= 1.0001; l2 += 0.05) {
      Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
      F(0, 0) = l1;
      F(1, 1) = l2;
      EXPECT_TRUE(pde_stable(*m, F, 180)) << l1 << " " << l2;
    }
  for (auto [l1, l2] : {std::pair{2.0, 2.0}, std::pair{3.0, 1.0}, std::pair{1.7, 1.7}}) {
    Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
    F(0, 0) = l1;
    F(1, 1) = l2;
    EXPECT_FALSE(pde_stable(*m, F)) << l1 << " " << l2;
  }
  // Equibiaxial stretch at the loss of strong ellipticity.
  double lo = 1.0, hi = 2.0;
  while (hi - lo > 1e-6) {
    const double mid = 0.5 * (lo + hi);
    Eigen::Matrix2d F = mid * Eigen::Matrix2d::Identity();
    (pde_stable(*m, F) ? lo : hi) = mid;
  }
  record("rubber equibiaxial stretch at loss of ellipticity", lo);
  record("rubber J = stretch^2 there", lo * lo);
  // Moderate states are stable.
  for (auto [l1, l2] : {std::pair{1.2, 1.0}, std::pair{0.9, 0.9}, std::pair{1.3, 0.8}}) {
    Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
    F(0, 0) = l1;
    F(1, 1) = l2;
    EXPECT_TRUE(pde_stable(*m, F)) << l1 << " " << l2;
  }
}

}  // namespace
}  // namespace mfv

namespace mfv {
namespace {

// 000 eq 3.18's w_{,xx} read two ways (closed_forms.hpp, Normalization): frozen (eq 3.16's
// w_I(x_J − x_I), 0.500 at σ̄ = 1, D_mx = 1.5) and the Shepard function's own second
// derivative (eq 2.7, 0.471); the three-point arccos form gives the same onsets without a scan.
TEST(ClosedForm1D, Eq318OnsetInBothReadingsOfItsSecondDerivative) {
  const auto W = test_catalogue().kernels.create("quartic-spline");
  namespace cf = closed_form;
  using N = cf::Normalization;
  EXPECT_NEAR(cf::onset_wavenumber_eulerian_1d(*W, 1.5, 1.0, N::frozen), 0.5, 1e-9);
  EXPECT_NEAR(cf::onset_wavenumber_eulerian_1d(*W, 1.5, 1.0, N::shepard), 0.47102, 1e-4);
  for (double sb : {0.1, 0.16, 1.0, 2.0})
    for (N n : {N::frozen, N::shepard})
      EXPECT_NEAR(cf::onset_wavenumber_eulerian_three_point(*W, 1.5, sb, n),
                  cf::onset_wavenumber_eulerian_1d(*W, 1.5, sb, n), 1e-9)
          << sb;
  // The frozen reading is the one omega2_eulerian_nodal_1d always evaluated.
  for (int i = 1; i <= 20; ++i) {
    const double k = M_PI * i / 20;
    EXPECT_DOUBLE_EQ(cf::omega2_eulerian_nodal_1d(*W, 1.5, 1, k, 1, 0.7, 1, N::frozen),
                     cf::omega2_eulerian_nodal_1d(*W, 1.5, 1, k, 1, 0.7, 1));
  }
  EXPECT_THROW(cf::onset_wavenumber_eulerian_three_point(*W, 2.5, 1.0, N::frozen),
               std::invalid_argument);
}

}  // namespace
}  // namespace mfv
