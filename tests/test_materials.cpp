/// The materials of the rings (000 §5.2–5.3, 001 §9.5–9.6): j2-jaumann (J2 flow, Jaumann rate
/// of Kirchhoff stress, 001 eq 76) and rubber (000 eq 5.1) — objectivity under rigid rotation,
/// consistency of the return mapping, the hardening/softening slope H and its floor, the
/// small-strain limit, the seeded yield imperfection, bad parameters, and the explicit engine's
/// one call of initial_state; j2-viscoplastic (Needleman 1989, 001 §9.4): its rate law, rate
/// sensitivity, softening branch and floor, objectivity with flow, the elastic dt = 0 step, bad
/// parameters, and the engine's dt reaching it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "dynamics/explicit.hpp"
#include "methods/core/errors.hpp"
#include "methods/materials/j2_viscoplastic.hpp"
#include "methods/particles.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

constexpr double kE = 2e11, kNu = 0.3, kYield = 2e8;
const double kMu = kE / (2 * (1 + kNu)), kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu));

std::shared_ptr<const Material> j2(const std::string& params = "") {
  return test_catalogue().materials.create("j2-jaumann", Params::parse(params));
}

/// Index of the history slot `name` (state_names), failing the test when it is missing.
int slot(const Material& m, int dim, const std::string& name) {
  const std::vector<std::string> names = m.state_names(dim);
  EXPECT_EQ(static_cast<int>(names.size()), m.state_size(dim));
  const auto it = std::find(names.begin(), names.end(), name);
  EXPECT_NE(it, names.end()) << name;
  return static_cast<int>(it - names.begin());
}

/// One 2D j2-jaumann point: its history, started as the engine starts it.
struct Point2D {
  std::shared_ptr<const Material> m;
  std::vector<double> state;
  Eigen::Matrix2d P = Eigen::Matrix2d::Zero();

  explicit Point2D(std::shared_ptr<const Material> mat) : m(std::move(mat)) {
    state.assign(m->state_size(2), 0.0);
    m->initial_state(2, 1, state.data());
  }
  void to(const Eigen::Matrix2d& F) { m->first_piola(2, 1, F.data(), P.data(), state.data()); }
  double ebar() const { return state[slot(*m, 2, "plastic_strain")]; }
  double factor() const { return 1 + state[slot(*m, 2, "yield_factor_minus_1")]; }
  /// The 3D Kirchhoff stress from the history (plane strain: τ33 kept, τ13 = τ23 = 0).
  Eigen::Matrix3d tau() const {
    Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
    t(0, 0) = state[slot(*m, 2, "tau_xx")];
    t(1, 1) = state[slot(*m, 2, "tau_yy")];
    t(2, 2) = state[slot(*m, 2, "tau_zz")];
    t(0, 1) = t(1, 0) = state[slot(*m, 2, "tau_xy")];
    return t;
  }
};

double von_mises(const Eigen::Matrix3d& tau) {
  const Eigen::Matrix3d dev = tau - tau.trace() / 3 * Eigen::Matrix3d::Identity();
  return std::sqrt(1.5 * dev.squaredNorm());
}

Eigen::Matrix2d rotation(double a) {
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}

Eigen::Matrix2d simple_shear(double gamma) {
  Eigen::Matrix2d F;
  F << 1, gamma, 0, 1;
  return F;
}

TEST(J2Jaumann, RigidRotationOfAPlasticallyStressedStateIsObjective) {
  Point2D p(j2());
  // Plastic prestrain (yield strain ~1e-3) in 50 increments, then 2000 increments of a
  // rigid rotation F(t) = R(ωt) F_pre through 3 rad.
  Eigen::Matrix2d F_pre;
  F_pre << 1.004, 0.003, 0.001, 0.997;
  for (int k = 1; k <= 50; ++k)
    p.to(Eigen::Matrix2d::Identity() + k / 50.0 * (F_pre - Eigen::Matrix2d::Identity()));
  const Eigen::Matrix3d tau0 = p.tau();
  const Eigen::Matrix2d P0 = p.P;
  const double ebar0 = p.ebar();
  ASSERT_GT(ebar0, 1e-3);
  double tau_error = 0, P_error = 0, ebar_error = 0;
  for (int k = 1; k <= 2000; ++k) {
    const Eigen::Matrix2d R2 = rotation(3.0 * k / 2000);
    p.to(R2 * F_pre);
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    R.topLeftCorner<2, 2>() = R2;
    tau_error = std::max(tau_error, (R.transpose() * p.tau() * R - tau0).norm() / tau0.norm());
    P_error = std::max(P_error, (p.P - R2 * P0).norm() / P0.norm());
    ebar_error = std::max(ebar_error, std::abs(p.ebar() - ebar0) / ebar0);
  }
  RecordProperty("max relative error of R^T tau R", fmt::format("{:.3g}", tau_error));
  std::printf("j2-jaumann rigid rotation: max |R^T tau R - tau0|/|tau0| = %.3g, |P - R P0|/|P0| "
              "= %.3g, |ebar - ebar0|/ebar0 = %.3g\n",
              tau_error, P_error, ebar_error);
  EXPECT_LT(tau_error, 1e-10);
  EXPECT_LT(P_error, 1e-10);
  // On the yield surface: round-off may add a plastic increment of its own size.
  EXPECT_LT(ebar_error, 1e-10);
}

TEST(Rubber, FirstPiolaIsObjective) {
  const auto m = test_catalogue().materials.create("rubber", {});
  Eigen::Matrix2d F;
  F << 1.3, 0.2, -0.1, 0.8;
  Eigen::Matrix2d P0, P;
  m->first_piola(2, 1, F.data(), P0.data(), nullptr);
  double error = 0;
  for (double a : {0.1, 1.0, 2.5, -0.7}) {
    const Eigen::Matrix2d RF = rotation(a) * F;
    m->first_piola(2, 1, RF.data(), P.data(), nullptr);
    error = std::max(error, (P - rotation(a) * P0).norm() / P0.norm());
  }
  std::printf("rubber: max |P(RF) - R P(F)|/|P(F)| = %.3g\n", error);
  EXPECT_LT(error, 1e-12);
}

TEST(J2Jaumann, PlasticStepsStayOnTheYieldSurfaceAndElasticStepsDoNotYield) {
  for (const char* params : {"hardening=2e10", "hardening=-2e10", "hardening=0",
                             "hardening=-2e10,imperfection=0.3,seed=5"}) {
    SCOPED_TRACE(params);
    Point2D p(j2(params));
    const double H = Params::parse(params).number("hardening");
    // Below yield (σ̄ ≈ √3 μ γ ≤ 0.7e8, under the weakest point's 0.7 σ_Y0): elastic, ε̄
    // stays exactly 0.
    for (int k = 1; k <= 10; ++k) {
      p.to(simple_shear(5e-5 * k) * Eigen::Vector2d(1 + 1e-6 * k, 1).asDiagonal());
      EXPECT_EQ(p.ebar(), 0.0);
    }
    int plastic = 0;
    double worst = 0;
    for (int k = 1; k <= 300; ++k) {
      const double before = p.ebar();
      p.to(simple_shear(1e-3 + 2e-5 * k) * Eigen::Vector2d(1.0002 + 1e-6 * k, 1).asDiagonal());
      if (p.ebar() > before) {
        ++plastic;
        const double sy = std::max(kYield * p.factor() + H * p.ebar(), 0.0);
        worst = std::max(worst, std::abs(von_mises(p.tau()) - sy) / (kYield * p.factor()));
      }
    }
    EXPECT_GT(plastic, 100);
    EXPECT_LT(worst, 1e-10);
  }
}

/// (ε̄, σ̄) after each plastic step of plane-strain simple shear in `steps` increments to γ.
std::vector<std::pair<double, double>> shear_curve(const std::string& params, double gamma,
                                                   int steps) {
  Point2D p(j2(params));
  std::vector<std::pair<double, double>> curve;
  for (int k = 1; k <= steps; ++k) {
    const double before = p.ebar();
    p.to(simple_shear(gamma * k / steps));
    if (p.ebar() > before) curve.emplace_back(p.ebar(), von_mises(p.tau()));
  }
  return curve;
}

TEST(J2Jaumann, HardeningAndSofteningSlopesAreH) {
  for (double H : {2e10, -2e10, 5e9}) {
    SCOPED_TRACE(H);
    const auto curve = shear_curve(fmt::format("hardening={}", H), 0.006, 600);
    ASSERT_GT(curve.size(), 100u);
    double worst = 0;
    for (std::size_t i = 1; i < curve.size(); ++i) {
      const double slope =
          (curve[i].second - curve[i - 1].second) / (curve[i].first - curve[i - 1].first);
      worst = std::max(worst, std::abs(slope / H - 1));
    }
    std::printf("hardening %g: max relative slope error %.3g over %zu plastic steps\n", H, worst,
                curve.size());
    EXPECT_LT(worst, 1e-6);
  }
}

TEST(J2Jaumann, SofteningStopsAtAZeroYieldStress) {
  // H = −E/10: σ_Y reaches 0 at ε̄ = σ_Y0/|H| = 0.01; shear on to γ = 0.3.
  Point2D p(j2("hardening=-2e10"));
  double max_after_floor = 0;
  bool floored = false;
  for (int k = 1; k <= 3000; ++k) {
    p.to(simple_shear(1e-4 * k));
    ASSERT_TRUE(p.P.allFinite());
    if (p.ebar() > kYield / 2e10) {
      floored = true;
      max_after_floor = std::max(max_after_floor, von_mises(p.tau()));
    }
  }
  EXPECT_TRUE(floored);
  EXPECT_LT(max_after_floor, 1e-6 * kYield);
  EXPECT_TRUE(std::isfinite(p.ebar()));
  // The stress left is the pressure alone: τ = p I.
  const Eigen::Matrix3d tau = p.tau();
  EXPECT_LT((tau - tau.trace() / 3 * Eigen::Matrix3d::Identity()).norm(), 1e-6 * kYield);
  // One step crossing the floor from the elastic state lands on σ̄ = 0 too.
  Point2D jump(j2("hardening=-2e10"));
  jump.to(simple_shear(0.1));
  EXPECT_GT(jump.ebar(), kYield / 2e10);
  EXPECT_LT(von_mises(jump.tau()), 1e-6 * kYield);
}

TEST(J2Jaumann, UniaxialStrainIn1DHasTheSlopeAndYieldOfTheReturnMapping) {
  const auto m = j2("hardening=2e10");
  std::vector<double> state(m->state_size(1), 0.0);
  m->initial_state(1, 1, state.data());
  const int e = slot(*m, 1, "plastic_strain"), txx = slot(*m, 1, "tau_xx"),
            tyy = slot(*m, 1, "tau_yy"), tzz = slot(*m, 1, "tau_zz");
  double F = 1 - 1e-7, P = 0;
  m->first_piola(1, 1, &F, &P, state.data());
  EXPECT_NEAR(P / (-1e-7 * (kLambda + 2 * kMu)), 1.0, 1e-4);
  double prev_e = 0, prev_s = 0;
  int plastic = 0;
  for (int k = 1; k <= 400; ++k) {
    F = 1 - 2e-5 * k;
    m->first_piola(1, 1, &F, &P, state.data());
    // Uniaxial strain: σ̄ = |τ11 − τ22|, τ22 = τ33.
    EXPECT_EQ(state[tyy], state[tzz]);
    const double s = std::abs(state[txx] - state[tyy]);
    if (state[e] > prev_e) {
      EXPECT_NEAR(s / (kYield + 2e10 * state[e]), 1.0, 1e-10);
      if (prev_e > 0) {
        EXPECT_NEAR((s - prev_s) / (state[e] - prev_e) / 2e10, 1.0, 1e-6);
      }
      ++plastic;
    }
    prev_e = state[e];
    prev_s = s;
    EXPECT_NEAR(P, state[txx] / F, 1e-9 * std::abs(P));
  }
  EXPECT_GT(plastic, 100);
}

TEST(J2Jaumann, SmallStrainIsLinearElasticity) {
  Point2D p(j2());
  Eigen::Matrix2d H;
  H << 1e-7, 3e-7, -2e-7, 4e-7;
  p.to(Eigen::Matrix2d::Identity() + H);
  const Eigen::Matrix2d eps = 0.5 * (H + H.transpose());
  const Eigen::Matrix2d hooke = kLambda * eps.trace() * Eigen::Matrix2d::Identity() + 2 * kMu * eps;
  EXPECT_LT((p.P - hooke).norm(), 1e-4 * hooke.norm());
  EXPECT_NEAR(p.tau()(2, 2) / (kLambda * eps.trace()), 1.0, 1e-4);  // plane strain σ33
  EXPECT_EQ(p.ebar(), 0.0);
  EXPECT_DOUBLE_EQ(j2()->wave_speed(2, 7800), std::sqrt((kLambda + 2 * kMu) / 7800));
}

TEST(Rubber, SmallStrainIsLinearElasticityWithTheDerivedLameConstants) {
  const double c1 = 1.265e5, c2 = 1.012e4, lambda = 1.012e7;
  const auto m = test_catalogue().materials.create("rubber", {});
  const double mu0 = c1 + c2, lambda0 = 2 * lambda - 2 * (c1 + c2) / 3;
  Eigen::Matrix2d H;
  H << 1e-7, 3e-7, -2e-7, 4e-7;
  const Eigen::Matrix2d F = Eigen::Matrix2d::Identity() + H;
  Eigen::Matrix2d P;
  m->first_piola(2, 1, F.data(), P.data(), nullptr);
  const Eigen::Matrix2d eps = 0.5 * (H + H.transpose());
  const Eigen::Matrix2d hooke = lambda0 * eps.trace() * Eigen::Matrix2d::Identity() + 2 * mu0 * eps;
  EXPECT_LT((P - hooke).norm(), 1e-4 * hooke.norm());
  const double F1 = 1 + 1e-7;
  double P1 = 0;
  m->first_piola(1, 1, &F1, &P1, nullptr);
  EXPECT_NEAR(P1 / ((lambda0 + 2 * mu0) * 1e-7), 1.0, 1e-4);
  EXPECT_DOUBLE_EQ(m->wave_speed(2, 125.4), std::sqrt((lambda0 + 2 * mu0) / 125.4));
}

/// The yield factors ξ of n points as initial_state sets them.
std::vector<double> factors(const std::string& params, int n) {
  const auto m = j2(params);
  const int ns = m->state_size(2), k = slot(*m, 2, "yield_factor_minus_1");
  std::vector<double> state(static_cast<std::size_t>(ns) * n, 0.0);
  m->initial_state(2, n, state.data());
  std::vector<double> xi(n);
  for (int q = 0; q < n; ++q) {
    xi[q] = 1 + state[ns * q + k];
    for (int s = 0; s < ns; ++s) {
      if (s == k) continue;
      EXPECT_EQ(state[ns * q + s], 0.0) << "slot " << s << " of point " << q;
    }
  }
  return xi;
}

TEST(J2Jaumann, ImperfectionIsSeededAndBounded) {
  const int n = 2000;
  const double a = 0.01;
  const auto x = factors("imperfection=0.01,seed=7", n);
  EXPECT_EQ(x, factors("imperfection=0.01,seed=7", n));
  const auto y = factors("imperfection=0.01,seed=8", n);
  int same = 0;
  for (int q = 0; q < n; ++q) same += x[q] == y[q];
  EXPECT_LT(same, 5);
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  EXPECT_GE(*lo, 1 - a);
  EXPECT_LE(*hi, 1 + a);
  // Uniform on [1 − a, 1 + a]: 2000 draws come within 1% of a of both ends.
  EXPECT_LT(*lo, 1 - 0.99 * a);
  EXPECT_GT(*hi, 1 + 0.99 * a);
  for (double f : factors("imperfection=0", 100)) EXPECT_EQ(f, 1.0);
  // A point's yield is its factor times σ_Y0: the first plastic step starts there.
  Point2D p(j2("imperfection=0.5,seed=3"));
  p.to(simple_shear(0.01));
  EXPECT_NEAR(von_mises(p.tau()) / (p.factor() * kYield - 2e10 * p.ebar()), 1.0, 1e-10);
  EXPECT_NE(p.factor(), 1.0);
}

/// Expects InputError from j2-jaumann with `params`, naming `name`.
void expect_refused(const Params& params, const std::string& name) {
  try {
    test_catalogue().materials.create("j2-jaumann", params);
    ADD_FAILURE() << "accepted " << name;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(J2Jaumann, BadParametersAreRefusedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, double>> bad = {
      {"E", nan},           {"E", -2e11},         {"E", 0.0},          {"E", 1e308},
      {"nu", 0.5},          {"nu", -0.1},         {"nu", nan},         {"yield", -1.0},
      {"yield", 0.0},       {"hardening", nan},   {"hardening", -3e11}, {"imperfection", 1.0},
      {"imperfection", -0.01}, {"imperfection", nan}, {"seed", 0.0},   {"seed", 1.5},
      {"seed", -3.0}};
  for (const auto& [name, value] : bad) {
    SCOPED_TRACE(fmt::format("{} = {}", name, value));
    Params p;
    p.set(name, value);
    expect_refused(p, name);
  }
  const auto m = j2();
  std::vector<double> state(m->state_size(2), 0.0);
  double F[4] = {1, 0, 0, 1}, P[4];
  EXPECT_THROW(m->first_piola(4, 1, F, P, state.data()), InputError);
  EXPECT_NE(m->description(2).find("plane strain"), std::string::npos);
}

/// A material that counts the engine's initial_state calls and forwards everything.
class CountingMaterial final : public Material {
 public:
  explicit CountingMaterial(std::shared_ptr<const Material> m) : m_(std::move(m)) {}
  int state_size(int dim) const override { return m_->state_size(dim); }
  void initial_state(int dim, int n, double* state) const override {
    ++calls;
    points = n;
    m_->initial_state(dim, n, state);
  }
  std::vector<std::string> state_names(int dim) const override { return m_->state_names(dim); }
  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    m_->first_piola(dim, n, F, P, state);
  }
  double wave_speed(int dim, double rho) const override { return m_->wave_speed(dim, rho); }
  std::string description(int dim) const override { return m_->description(dim); }

  mutable int calls = 0, points = 0;

 private:
  std::shared_ptr<const Material> m_;
};

/// A 7 × 7 steel block (60 mm) stretched along x and squeezed along y at 1000/s, 40 steps:
/// a strain of a few 1e-2, beyond the yield strain ~1e-3.
struct Block {
  std::unique_ptr<Method> method;
  std::shared_ptr<const CountingMaterial> material;
  std::unique_ptr<ExplicitDynamics> engine;
};

Block stretched_block(const std::string& params) {
  Block b;
  b.method = test_catalogue().methods.create("efg-ni", {});
  const Domain dom = Domain::rectangle(0, 0, 0.06, 0.06);
  const ParticleSet particles = rectangle_lattice(dom, 7, 7, Placement::boundary);
  Discretization d = b.method->discretize(dom, particles, 1);
  DynamicsModel model;
  b.material = std::make_shared<CountingMaterial>(j2(params));
  model.material = b.material;
  model.density = 7800;
  model.mass = lumped_masses(d.particles, model.density, MassLumping::volume);
  DynamicsOptions o;
  o.threads = 1;
  b.engine = std::make_unique<ExplicitDynamics>(*b.method, std::move(d), std::move(model), o);
  Eigen::MatrixXd v(2, particles.size());
  for (int I = 0; I < particles.size(); ++I) {
    v(0, I) = 1000 * (particles.x(0, I) - 0.03);
    v(1, I) = -1000 * (particles.x(1, I) - 0.03);
  }
  b.engine->set_particle_velocity(v);
  const double dt = 0.5 * b.engine->critical_time_step();
  for (int s = 0; s < 40; ++s) b.engine->step(dt);
  return b;
}

TEST(MaterialInitialState, TheEngineSetsItOnceAndTheImperfectionChangesThePlasticRun) {
  const Block a = stretched_block("imperfection=0.2,seed=3");
  EXPECT_EQ(a.material->calls, 1);
  EXPECT_EQ(a.material->points, static_cast<int>(a.engine->discretization().quadrature.size()));
  EXPECT_TRUE(a.engine->displacement().allFinite());
  EXPECT_TRUE(a.engine->velocity().allFinite());
  const Eigen::MatrixXd sigma = a.engine->point_cauchy_stress();
  EXPECT_TRUE(sigma.allFinite());
  // The yield factors matter only once a point yields: an elastic run would match a = 0 bit
  // for bit, so a difference shows both that the run went plastic and that the factors were set.
  const Block b = stretched_block("imperfection=0");
  const double diff = (a.engine->displacement() - b.engine->displacement()).norm();
  std::printf("engine: |u(a=0.2) - u(a=0)| / |u| = %.3g\n",
              diff / b.engine->displacement().norm());
  EXPECT_GT(diff, 1e-6 * b.engine->displacement().norm());
  EXPECT_TRUE(b.engine->displacement().allFinite());
}

// ---- j2-viscoplastic -------------------------------------------------------------------------

std::shared_ptr<const Material> visco(const std::string& params = "") {
  return test_catalogue().materials.create("j2-viscoplastic", Params::parse(params));
}

/// The flow-stress law g(ε̄) written out from the model (j2_viscoplastic.hpp), independently of
/// the material's code: rational or linear softening, floored at the residual.
struct FlowLaw {
  double sigma0 = 460e6, eps0 = 460e6 / 211e9, N = 0.1, eps1 = 0.436, h1 = -2.11e9,
         residual = 4.6e6;
  bool linear = false;
  double g(double e) const {
    double v;
    if (!linear)
      v = sigma0 * std::pow(1 + e / eps0, N) / (1 + (e / eps1) * (e / eps1));
    else if (e <= eps1)
      v = sigma0 * std::pow(1 + e / eps0, N);
    else
      v = sigma0 * std::pow(1 + eps1 / eps0, N) + h1 * (e - eps1);
    return std::max(v, residual);
  }
};

/// One j2-viscoplastic point (2D plane strain or 1D uniaxial strain) stepped with a time step.
struct VPoint {
  std::shared_ptr<const Material> m;
  int dim;
  std::vector<double> state;
  Eigen::Matrix2d P = Eigen::Matrix2d::Zero();

  VPoint(std::shared_ptr<const Material> mat, int d) : m(std::move(mat)), dim(d) {
    state.assign(m->state_size(dim), 0.0);
    m->initial_state(dim, 1, state.data());
  }
  void to(const Eigen::Matrix2d& F, double dt) {
    if (dim == 2) {
      m->first_piola(2, 1, F.data(), P.data(), state.data(), dt);
    } else {
      const double F11 = F(0, 0);
      m->first_piola(1, 1, &F11, P.data(), state.data(), dt);
    }
  }
  double get(const std::string& name) const { return state[slot(*m, dim, name)]; }
  double ebar() const { return get("plastic_strain"); }
  double rate() const { return get("plastic_strain_rate"); }
  Eigen::Matrix3d tau() const {
    Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
    t(0, 0) = get("tau_xx");
    t(1, 1) = get("tau_yy");
    t(2, 2) = get("tau_zz");
    if (dim == 2) t(0, 1) = t(1, 0) = get("tau_xy");
    return t;
  }
};

/// The deformation of a constant-rate test at time t: 2D simple shear γ = γ̇ t (effective
/// rate γ̇/√3), 1D uniaxial compression F11 = 1 − ε̇ t (effective rate ≈ 2/3 ε̇).
Eigen::Matrix2d straining(int dim, double rate, double t) {
  return dim == 2 ? simple_shear(rate * t)
                  : Eigen::Matrix2d(Eigen::Vector2d(1 - rate * t, 1).asDiagonal());
}

/// Effective total strain rate of `straining` at time t.
double effective_rate(int dim, double rate, double t) {
  return dim == 2 ? rate / std::sqrt(3.0) : 2.0 / 3.0 * rate / (1 - rate * t);
}

TEST(J2Viscoplastic, SteadyFlowFollowsTheRateLaw) {
  // σ̄ = g(ε̄) (ε̄̇/ε̇0)^m: exactly (round-off) with the step's own rate Δε̄/Δt (the backward-Euler
  // equation), and to 1e-3 with the imposed rate once the flow is steady (the elastic share
  // of the rate is then g'/3μ ~ 1e-2 of it, which moves σ̄ by m times that).
  struct Case {
    int dim;
    std::string params;
    FlowLaw law;
    double m;
  };
  FlowLaw linear;
  linear.linear = true;
  linear.eps1 = 0.05;
  const std::vector<Case> cases = {{2, "", FlowLaw{}, 0.01},
                                   {1, "", FlowLaw{}, 0.01},
                                   {2, "softening=linear,eps1=0.05", linear, 0.01},
                                   {2, "m=0.05", FlowLaw{}, 0.05}};
  for (const Case& c : cases) {
    const double m = c.m;
    SCOPED_TRACE(fmt::format("{}D {}", c.dim, c.params));
    VPoint p(visco(c.params), c.dim);
    const double rate = 1e3, dt = 1e-7;  // 1e6 × ε̇0; 2000 steps to a strain of 0.2
    double worst_step = 0, worst_imposed = 0;
    int steady = 0;
    for (int k = 1; k <= 2000; ++k) {
      p.to(straining(c.dim, rate, k * dt), dt);
      ASSERT_TRUE(p.P.allFinite());
      if (p.rate() <= 0) continue;
      const double sbar = von_mises(p.tau()), g = c.law.g(p.ebar());
      worst_step = std::max(worst_step, std::abs(sbar / (g * std::pow(p.rate() / 1e-3, m)) - 1));
      if (p.ebar() > 0.02) {
        ++steady;
        const double imposed = effective_rate(c.dim, rate, k * dt);
        worst_imposed =
            std::max(worst_imposed, std::abs(sbar / (g * std::pow(imposed / 1e-3, m)) - 1));
      }
    }
    std::printf("j2-viscoplastic %dD %s: rate law with the step's rate %.3g, with the imposed "
                "rate %.3g (%d steady steps)\n",
                c.dim, c.params.c_str(), worst_step, worst_imposed, steady);
    EXPECT_GT(steady, 1000);
    EXPECT_LT(worst_step, 1e-9);
    EXPECT_LT(worst_imposed, 1e-3);
  }
}

TEST(J2Viscoplastic, TenTimesTheRateRaisesTheFlowStressByTenToTheM) {
  for (const double m : {0.01, 0.05}) {
    SCOPED_TRACE(m);
    // Same strain path in the same number of steps, 10× faster; σ̄/g(ε̄) at the end.
    double ratio[2];
    for (int i = 0; i < 2; ++i) {
      VPoint p(visco(fmt::format("m={}", m)), 2);
      const double rate = 1e3 * (i == 0 ? 1 : 10), dt = 1e-4 / rate;
      for (int k = 1; k <= 2000; ++k) p.to(straining(2, rate, k * dt), dt);
      ratio[i] = von_mises(p.tau()) / FlowLaw{}.g(p.ebar());
    }
    const double measured = ratio[1] / ratio[0], expected = std::pow(10.0, m);
    std::printf("j2-viscoplastic m = %g: flow stress ratio at 10x the rate %.6f, 10^m = %.6f\n",
                m, measured, expected);
    EXPECT_NEAR(measured / expected, 1.0, 2e-4);
  }
}

TEST(J2Viscoplastic, LinearSofteningHasSlopeH1DownToTheResidual) {
  // Linear law from ε1 = 0.05 with h1 = −2e9 Pa down to the floor 4.6e7 Pa (reached at
  // ε̄ ≈ 0.34): the flow stress divided by the rate factor, σ̄ / (ε̄̇/ε̇0)^m, is g.
  FlowLaw law;
  law.linear = true;
  law.eps1 = 0.05;
  law.h1 = -2e9;
  law.residual = 4.6e7;
  VPoint p(visco("softening=linear,eps1=0.05,h1=-2e9,residual=4.6e7"), 2);
  const double rate = 1e3, dt = 1e-7;
  std::vector<std::pair<double, double>> curve;  // (ε̄, σ̄ / rate factor) past ε1
  for (int k = 1; k <= 7000; ++k) {
    p.to(straining(2, rate, k * dt), dt);
    ASSERT_TRUE(p.P.allFinite());
    if (p.ebar() > law.eps1 && p.rate() > 0)
      curve.emplace_back(p.ebar(), von_mises(p.tau()) / std::pow(p.rate() / 1e-3, 0.01));
  }
  double worst_slope = 0, worst_floor = 0;
  int softening = 0, floored = 0;
  for (std::size_t i = 1; i < curve.size(); ++i) {
    const auto [e0, g0] = curve[i - 1];
    const auto [e1, g1] = curve[i];
    if (law.g(e0) > law.residual && law.g(e1) > law.residual) {
      worst_slope = std::max(worst_slope, std::abs((g1 - g0) / (e1 - e0) / law.h1 - 1));
      ++softening;
    } else if (law.g(e0) == law.residual) {
      worst_floor = std::max(worst_floor, std::abs(g1 / law.residual - 1));
      ++floored;
    }
  }
  std::printf("j2-viscoplastic linear softening: slope/h1 - 1 up to %.3g over %d steps, floor "
              "error %.3g over %d steps\n",
              worst_slope, softening, worst_floor, floored);
  EXPECT_GT(softening, 500);
  EXPECT_GT(floored, 100);
  EXPECT_LT(worst_slope, 1e-5);
  EXPECT_LT(worst_floor, 1e-9);
}

TEST(J2Viscoplastic, RigidRotationWhileFlowingIsObjective) {
  // Plastic prestrain, then the same 2000 steps of time twice: held at F_pre (the stress
  // relaxes by flow) and rotated through 3 rad, F = R(ωt) F_pre. Objectivity: Rᵀ τ R and ε̄ of
  // the rotated point follow the held one.
  Eigen::Matrix2d F_pre;
  F_pre << 1.004, 0.003, 0.001, 0.997;
  const double dt = 1e-7;
  VPoint held(visco(), 2);
  for (int k = 1; k <= 50; ++k)
    held.to(Eigen::Matrix2d::Identity() + k / 50.0 * (F_pre - Eigen::Matrix2d::Identity()), dt);
  ASSERT_GT(held.ebar(), 1e-3);
  VPoint rotated = held;
  double tau_error = 0, ebar_error = 0, relaxed = 0;
  const Eigen::Matrix3d tau_pre = held.tau();
  for (int k = 1; k <= 2000; ++k) {
    const Eigen::Matrix2d R2 = rotation(3.0 * k / 2000);
    held.to(F_pre, dt);
    rotated.to(R2 * F_pre, dt);
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    R.topLeftCorner<2, 2>() = R2;
    const Eigen::Matrix3d tau = held.tau();
    tau_error = std::max(tau_error, (R.transpose() * rotated.tau() * R - tau).norm() / tau.norm());
    ebar_error = std::max(ebar_error, std::abs(rotated.ebar() - held.ebar()) / held.ebar());
    relaxed = (tau - tau_pre).norm() / tau_pre.norm();
  }
  std::printf("j2-viscoplastic rigid rotation: max |R^T tau R - tau_held|/|tau_held| = %.3g, "
              "ebar %.3g; the held stress relaxed by %.3g\n",
              tau_error, ebar_error, relaxed);
  EXPECT_GT(relaxed, 1e-4);  // the flow went on during the rotation
  EXPECT_LT(tau_error, 1e-9);
  EXPECT_LT(ebar_error, 1e-9);
}

TEST(J2Viscoplastic, ZeroTimeStepIsElastic) {
  // A step of dt = 0 (a trial evaluation) or one without dt: no flow, the hypoelastic trial of
  // j2-jaumann with a yield stress never reached, bit for bit.
  Eigen::Matrix2d F;
  F << 1.01, 0.004, -0.002, 0.995;  // 5 times the yield strain
  VPoint p(visco(), 2);
  p.to(F, 0.0);
  Point2D elastic(j2("E=2.11e11,yield=1e15"));
  elastic.to(F);
  EXPECT_EQ(p.ebar(), 0.0);
  EXPECT_EQ(p.rate(), 0.0);
  EXPECT_EQ((p.P - elastic.P).norm(), 0.0);
  EXPECT_GT(von_mises(p.tau()), 3 * 460e6);
  // From a flowing state: dt = 0 keeps ε̄, and the 5-argument call is the same elastic step.
  VPoint q(visco(), 2);
  for (int k = 1; k <= 50; ++k) q.to(straining(2, 1e3, k * 1e-7), 1e-7);
  ASSERT_GT(q.ebar(), 0.0);
  VPoint r = q;
  const double before = q.ebar();
  const Eigen::Matrix2d F1 = straining(2, 1e3, 60 * 1e-7);
  q.to(F1, 0.0);
  r.m->first_piola(2, 1, F1.data(), r.P.data(), r.state.data());
  EXPECT_EQ(q.ebar(), before);
  EXPECT_EQ(q.rate(), 0.0);
  EXPECT_EQ(q.state, r.state);
  EXPECT_TRUE(visco()->rate_dependent());
  EXPECT_FALSE(j2()->rate_dependent());
}

TEST(J2Viscoplastic, DefaultsAreTheSourcedTable) {
  const Needleman1989Parameters t = needleman_1989_parameters();
  for (const SourcedParameter& e : t.entries) {
    SCOPED_TRACE(e.name);
    EXPECT_FALSE(e.source.empty());
    EXPECT_FALSE(e.unit.empty());
    EXPECT_TRUE(std::isfinite(e.value));
  }
  EXPECT_NEAR(t.value("eps0") / (t.value("sigma0") / t.value("E")), 1.0, 1e-2);
  EXPECT_THROW(t.value("no-such"), std::out_of_range);
  const std::string d = visco()->description(2);
  for (const char* name : {"E", "sigma0", "N", "m", "rate0", "eps1", "residual"})
    EXPECT_NE(d.find(fmt::format("{}={:g}", name, t.value(name))), std::string::npos) << d;
  EXPECT_NE(d.find("softening=" + t.softening_law), std::string::npos) << d;
  EXPECT_NE(d.find("plane strain"), std::string::npos);
}

TEST(J2Viscoplastic, BadParametersAreRefusedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"E", "E=0"},          {"E", "E=-1"},          {"E", "E=1e308"},
      {"nu", "nu=0.5"},      {"nu", "nu=-0.1"},      {"sigma0", "sigma0=0"},
      {"sigma0", "sigma0=-4.6e8"},                   {"sigma0", "sigma0=3e11"},
      {"eps0", "eps0=-0.002"},                       {"N", "N=-0.1"},
      {"N", "N=2"},          {"m", "m=0"},           {"m", "m=-0.01"},
      {"m", "m=100"},        {"rate0", "rate0=0"},   {"rate0", "rate0=-1"},
      {"rate0", "rate0=1e20"},                       {"eps1", "eps1=0"},
      {"eps1", "eps1=-0.1"}, {"h1", "softening=linear,h1=1e9"},
      {"h1", "h1=-1e12"},    {"residual", "residual=0"},
      {"residual", "residual=-1"},                   {"residual", "residual=5e8"},
      {"imperfection", "imperfection=1"},            {"imperfection", "imperfection=-0.1"},
      {"softening", "softening=cubic"},              {"seed", "seed=0"}};
  for (const auto& [name, params] : bad) {
    SCOPED_TRACE(params);
    try {
      visco(params);
      ADD_FAILURE() << "accepted " << params;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  for (const char* name : {"E", "nu", "sigma0", "eps0", "N", "m", "rate0", "eps1", "h1",
                           "residual", "imperfection"}) {
    SCOPED_TRACE(name);
    Params p;
    p.set(name, nan);
    try {
      test_catalogue().materials.create("j2-viscoplastic", p);
      ADD_FAILURE() << "accepted NaN";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  const auto m = visco();
  std::vector<double> state(m->state_size(2), 0.0);
  double F[4] = {1, 0, 0, 1}, P[4];
  EXPECT_THROW(m->first_piola(4, 1, F, P, state.data(), 1e-7), InputError);
}

TEST(J2Viscoplastic, TheEngineStepPassesItsTimeStep) {
  // The block of stretched_block with j2-viscoplastic: through the engine the points flow
  // (an engine that passed dt = 0 would leave ε̄ = 0), at a plastic strain rate of the order
  // of the imposed effective rate 1000/s × √(4/3) ≈ 1150/s.
  auto method = test_catalogue().methods.create("efg-ni", {});
  const Domain dom = Domain::rectangle(0, 0, 0.06, 0.06);
  const ParticleSet particles = rectangle_lattice(dom, 7, 7, Placement::boundary);
  Discretization d = method->discretize(dom, particles, 1);
  DynamicsModel model;
  model.material = visco();
  model.density = 7800;
  model.mass = lumped_masses(d.particles, model.density, MassLumping::volume);
  DynamicsOptions o;
  o.threads = 1;
  ExplicitDynamics engine(*method, std::move(d), std::move(model), o);
  Eigen::MatrixXd v(2, particles.size());
  for (int I = 0; I < particles.size(); ++I) {
    v(0, I) = 1000 * (particles.x(0, I) - 0.03);
    v(1, I) = -1000 * (particles.x(1, I) - 0.03);
  }
  engine.set_particle_velocity(v);
  const double dt = 0.5 * engine.critical_time_step();
  // The block is free: the initial motion loads it and then unloads it by waves, so the
  // largest rate is taken over the steps.
  double max_rate = 0;
  for (int s = 0; s < 40; ++s) {
    engine.step(dt);
    max_rate = std::max(max_rate, engine.point_state("plastic_strain_rate").maxCoeff());
  }
  const Eigen::VectorXd ebar = engine.point_state("plastic_strain");
  std::printf("engine j2-viscoplastic: max ebar %.3g, max rate %.3g /s over %d steps of %.3g s\n",
              ebar.maxCoeff(), max_rate, 40, dt);
  EXPECT_TRUE(engine.displacement().allFinite());
  EXPECT_GT(ebar.maxCoeff(), 1e-4);
  EXPECT_GT(max_rate, 100.0);
  EXPECT_GE(ebar.minCoeff(), 0.0);
}

}  // namespace
}  // namespace mfv
