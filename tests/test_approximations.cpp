/// Approximation conformance over every registered approximation: partition of unity and
/// linear reproduction of values, first and second derivatives to round-off, on uniform and
/// on randomly perturbed particles; SPH is held to its known boundary defect instead.
#include <cmath>
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "methods/core/parallel.hpp"
#include "methods/approximations/particle_gradients.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

struct Layout {
  double perturbation;
  const char* name;
};

/// (approximation, kernel, layout): the kernel "" is the approximation's default.
class ApproximationConformance
    : public ::testing::TestWithParam<std::tuple<std::string, std::string, Layout>> {
 protected:
  void SetUp() override {
    const auto& [name, kernel, layout] = GetParam();
    Params p;
    if (!kernel.empty()) p.set("kernel", ParamValue{kernel});
    approx = test_catalogue().approximations.create(name, p);
    particles = uniform_line(Domain::interval(0, 1), 21, layout.perturbation, 7);
    // 2.2 spacings: every point is covered by at least three particles for any kernel here.
    particles.dilation.setConstant(2.2 * particles.spacing);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    points.resize(1, 60);
    for (int i = 0; i < 60; ++i) points(0, i) = i < 2 ? i : u(rng);
    table = approx->evaluate(particles, points, 2);
  }
  std::unique_ptr<Approximation> approx;
  ParticleSet particles;
  Eigen::MatrixXd points;
  ShapeTable table;
};

TEST_P(ApproximationConformance, PartitionOfUnity) {
  if (approx->reproduction_order() < 0) GTEST_SKIP() << "uncorrected kernel: see SphBoundaryDefect";
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(particles.size());
  const Eigen::VectorXd s = table.interpolate(one), ds = table.interpolate_derivative(one),
                        d2s = table.interpolate_second_derivative(one);
  const double h = particles.spacing;
  for (int q = 0; q < table.points(); ++q) {
    EXPECT_NEAR(s[q], 1.0, 1e-12) << "x = " << points(0, q);
    EXPECT_NEAR(ds[q] * h, 0.0, 1e-10) << "x = " << points(0, q);
    EXPECT_NEAR(d2s[q] * h * h, 0.0, 1e-8) << "x = " << points(0, q);
  }
}

TEST_P(ApproximationConformance, LinearReproduction) {
  if (approx->reproduction_order() < 1) GTEST_SKIP() << "no linear consistency claimed";
  const Eigen::VectorXd lin = (2.0 + 3.0 * particles.x.row(0).array()).matrix().transpose();
  const Eigen::VectorXd v = table.interpolate(lin), dv = table.interpolate_derivative(lin),
                        d2v = table.interpolate_second_derivative(lin);
  const double h = particles.spacing;
  for (int q = 0; q < table.points(); ++q) {
    EXPECT_NEAR(v[q], 2.0 + 3.0 * points(0, q), 1e-12) << "x = " << points(0, q);
    EXPECT_NEAR(dv[q], 3.0, 1e-10 / h) << "x = " << points(0, q);
    EXPECT_NEAR(d2v[q] * h * h, 0.0, 1e-8) << "x = " << points(0, q);
  }
}

TEST_P(ApproximationConformance, DerivativesMatchFiniteDifferences) {
  // The exact derivative option must be the derivative of the values (the diffuse one is not).
  const double e = 1e-6;
  // Interior points only (the first two are the ends): the stencil stays inside [0, 1],
  // where element-based approximations are defined.
  const int n = static_cast<int>(points.cols()) - 2;
  const Eigen::MatrixXd interior = points.rightCols(n);
  Eigen::MatrixXd shifted(1, 2 * n);
  shifted << interior.array() + e, interior.array() - e;
  const ShapeTable t = approx->evaluate(particles, shifted, 1);
  Eigen::VectorXd u(particles.size());
  for (int J = 0; J < particles.size(); ++J) u[J] = std::sin(3 * particles.x(0, J));
  const Eigen::VectorXd v = t.interpolate(u), dv = t.interpolate_derivative(u);
  const Eigen::VectorXd d = table.interpolate_derivative(u), d2 = table.interpolate_second_derivative(u);
  for (int k = 0; k < n; ++k) {
    const int q = k + 2;
    EXPECT_NEAR(d[q], (v[k] - v[n + k]) / (2 * e), 1e-5 * (1 + std::abs(d[q])));
    EXPECT_NEAR(d2[q], (dv[k] - dv[n + k]) / (2 * e), 1e-3 * (1 + std::abs(d2[q])));
  }
}

const Layout kLayouts[] = {{0.0, "uniform"}, {0.3, "perturbed"}};

std::string conformance_name(
    const ::testing::TestParamInfo<std::tuple<std::string, std::string, Layout>>& info) {
  const auto& [approx, kernel, layout] = info.param;
  return test_name(approx + (kernel.empty() ? "" : "_" + kernel) + "_" + layout.name);
}

/// The approximations whose schema declares `kernel`, each with every registered kernel: a
/// kernel registered (or loaded from a plugin) is checked through every approximation built
/// on it, with no list to edit.
std::vector<std::tuple<std::string, std::string>> approximation_kernel_pairs() {
  std::vector<std::tuple<std::string, std::string>> out;
  const auto& c = test_catalogue();
  for (const std::string& a : c.approximations.keys())
    for (const ParamSpec& s : c.approximations.entry(a).schema)
      if (s.name == "kernel")
        for (const std::string& k : c.kernels.keys()) out.emplace_back(a, k);
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllApproximations, ApproximationConformance,
                         ::testing::Combine(::testing::ValuesIn(test_catalogue().approximations.keys()),
                                            ::testing::Values(std::string()),
                                            ::testing::ValuesIn(kLayouts)),
                         conformance_name);

class KernelApproximation
    : public ::testing::TestWithParam<std::tuple<std::tuple<std::string, std::string>, Layout>> {};

TEST_P(KernelApproximation, ReproducesWhatItClaimsAndDifferentiatesItsValues) {
  // The conformance checks of ApproximationConformance, run through a fixture per pair.
  const auto& [pair, layout] = GetParam();
  const auto& [approx_name, kernel] = pair;
  Params p;
  p.set("kernel", ParamValue{kernel});
  const auto approx = test_catalogue().approximations.create(approx_name, p);
  ParticleSet particles = uniform_line(Domain::interval(0, 1), 21, layout.perturbation, 7);
  // A dilation of 2.2 spacings: at least three particles cover every point for a kernel of
  // support 1 (the narrowest registered), more for wider ones.
  particles.dilation.setConstant(2.2 * particles.spacing);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::MatrixXd points(1, 40);
  for (int i = 0; i < 40; ++i) points(0, i) = i < 2 ? i : u(rng);
  const ShapeTable t = approx->evaluate(particles, points, 2);
  const double h = particles.spacing;
  const int order = approx->reproduction_order();
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(particles.size());
  const Eigen::VectorXd lin = (2.0 + 3.0 * particles.x.row(0).array()).matrix().transpose();
  const Eigen::VectorXd s = t.interpolate(one), ds = t.interpolate_derivative(one);
  const Eigen::VectorXd v = t.interpolate(lin), dv = t.interpolate_derivative(lin);
  for (int q = 0; q < t.points(); ++q) {
    if (order >= 0) {
      EXPECT_NEAR(s[q], 1.0, 1e-11) << kernel << " x = " << points(0, q);
      EXPECT_NEAR(ds[q] * h, 0.0, 1e-9) << kernel << " x = " << points(0, q);
    } else {
      // Uncorrected: no consistency claimed, but a kernel estimate of 1 stays positive and
      // bounded (each weight is W ≥ 0 over a normalization).
      EXPECT_GT(s[q], 0.0) << kernel << " x = " << points(0, q);
      EXPECT_LT(s[q], 2.0) << kernel << " x = " << points(0, q);
    }
    if (order >= 1) {
      EXPECT_NEAR(v[q], 2.0 + 3.0 * points(0, q), 1e-11) << kernel << " x = " << points(0, q);
      EXPECT_NEAR(dv[q], 3.0, 1e-9 / h) << kernel << " x = " << points(0, q);
    }
  }
  // The derivative is the derivative of the values (interior points; central differences).
  const double e = 1e-6;
  Eigen::MatrixXd shifted(1, 2 * (points.cols() - 2));
  const Eigen::MatrixXd interior = points.rightCols(points.cols() - 2);
  shifted << interior.array() + e, interior.array() - e;
  const ShapeTable ts = approx->evaluate(particles, shifted, 1);
  Eigen::VectorXd f(particles.size());
  for (int J = 0; J < particles.size(); ++J) f[J] = std::sin(3 * particles.x(0, J));
  const Eigen::VectorXd fv = ts.interpolate(f), df = t.interpolate_derivative(f);
  const int n = static_cast<int>(interior.cols());
  for (int k = 0; k < n; ++k)
    EXPECT_NEAR(df[k + 2], (fv[k] - fv[n + k]) / (2 * e), 1e-5 * (1 + std::abs(df[k + 2])))
        << kernel << " x = " << interior(0, k);
}

std::string kernel_approximation_name(
    const ::testing::TestParamInfo<std::tuple<std::tuple<std::string, std::string>, Layout>>& info) {
  const auto& pair = std::get<0>(info.param);
  return test_name(std::get<0>(pair) + "_" + std::get<1>(pair) + "_" +
                   std::get<1>(info.param).name);
}

INSTANTIATE_TEST_SUITE_P(
    EveryKernel, KernelApproximation,
    ::testing::Combine(::testing::ValuesIn(approximation_kernel_pairs()),
                       ::testing::ValuesIn(kLayouts)),
    kernel_approximation_name);

TEST(Approximations, SphBoundaryDefect) {
  // 004 II §2.1: the kernel estimate loses half its weight at a boundary; in the interior it
  // is close to a partition of unity.
  const auto sph = test_catalogue().approximations.create("sph");
  ParticleSet p = uniform_line(Domain::interval(0, 1), 41);
  p.dilation.setConstant(1.5 * p.spacing);
  Eigen::MatrixXd x(1, 2);
  x << 0.0, 0.5;
  const Eigen::VectorXd s = sph->evaluate(p, x, 0).interpolate(Eigen::VectorXd::Ones(41));
  EXPECT_NEAR(s[0], 0.5, 0.05);
  EXPECT_NEAR(s[1], 1.0, 1e-3);
}

TEST(Approximations, DiffuseDerivativeDiffersNearBoundaryOnly) {
  // 004 II §6: the DEM derivative (eq 6.6) matches the exact one (6.2) where the window is
  // inside the domain (m1 = 0) and departs from it at the boundary for large dilations.
  Params exact, diffuse;
  exact.set("kernel", "cubic-window");
  diffuse.set("kernel", "cubic-window");
  diffuse.set("derivative", "diffuse");
  const auto a = test_catalogue().approximations.create("rkpm", exact);
  const auto b = test_catalogue().approximations.create("rkpm", diffuse);
  ParticleSet p = uniform_line(Domain::interval(0, 6), 21);
  p.dilation.setConstant(std::pow(2.0, 2.5) * p.spacing);
  Eigen::MatrixXd x(1, 2);
  x << 3.0, 0.0;
  Eigen::VectorXd u(21);
  for (int J = 0; J < 21; ++J) u[J] = std::pow(p.x(0, J), 2);
  const Eigen::VectorXd da = a->evaluate(p, x, 1).interpolate_derivative(u);
  const Eigen::VectorXd db = b->evaluate(p, x, 1).interpolate_derivative(u);
  EXPECT_NEAR(da[0], db[0], 1e-9);
  EXPECT_GT(std::abs(da[1] - db[1]), 0.05);
}

TEST(Approximations, SingularMomentMatrixNamesThePoint) {
  const auto mls = test_catalogue().approximations.create("mls");
  ParticleSet p = uniform_line(Domain::interval(0, 1), 11);
  p.dilation.setConstant(0.4 * p.spacing);  // supports do not overlap
  Eigen::MatrixXd x(1, 1);
  x << 0.05;
  try {
    mls->evaluate(p, x, 1);
    FAIL() << "expected SingularError";
  } catch (const SingularError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("(0.05)"), std::string::npos) << m;
    EXPECT_NE(m.find("increase the dilation"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace mfv

namespace mfv {
namespace {

/// A random cloud of n points in the unit square.
Eigen::MatrixXd random_cloud(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::MatrixXd x(2, n);
  for (int j = 0; j < n; ++j) x.col(j) = Eigen::Vector2d(u(rng), u(rng));
  return x;
}

/// Every column moved by a random vector of length exactly `length`.
void move_by(Eigen::MatrixXd& x, double length, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    const double a = angle(rng);
    x.col(j) += length * Eigen::Vector2d(std::cos(a), std::sin(a));
  }
}

/// The lists' candidates hold every particle within r of each point (the brute-force set).
void expect_complete(const NeighbourLists& lists, const Eigen::MatrixXd& particles,
                     const Eigen::MatrixXd& points, double r, const char* when) {
  for (Eigen::Index q = 0; q < points.cols(); ++q) {
    const auto c = lists.candidates(static_cast<int>(q));
    EXPECT_TRUE(std::is_sorted(c.begin(), c.end())) << when << ", point " << q;
    for (Eigen::Index J = 0; J < particles.cols(); ++J) {
      if ((points.col(q) - particles.col(J)).norm() < r) {
        EXPECT_TRUE(std::binary_search(c.begin(), c.end(), static_cast<int>(J)))
            << when << ": particle " << J << " missing from point " << q;
      }
    }
  }
}

TEST(NeighbourLists, HoldTheBruteForceSetsBelowAndAboveHalfTheSkin) {
  Eigen::MatrixXd x = random_cloud(500, 3), y = random_cloud(300, 4);
  const double r = 0.1, skin = 0.04;
  NeighbourLists lists(skin);
  EXPECT_TRUE(lists.update(x, y, r));
  expect_complete(lists, x, y, r, "fresh");
  // Candidates stop at r + skin: the lists are Verlet lists, not every particle.
  for (Eigen::Index q = 0; q < y.cols(); ++q)
    for (int J : lists.candidates(static_cast<int>(q)))
      EXPECT_LE((y.col(q) - x.col(J)).norm(), (r + skin) * (1 + 1e-9));
  // Points and particles each moved by 0.45 skin: 0.9 skin together, no search.
  move_by(x, 0.45 * skin, 5);
  move_by(y, 0.45 * skin, 6);
  EXPECT_FALSE(lists.update(x, y, r));
  EXPECT_EQ(lists.rebuilds(), 1);
  expect_complete(lists, x, y, r, "after 0.45 skin");
  // Another 0.1 skin each: 1.1 skin since the search, past what the lists guarantee.
  move_by(x, 0.1 * skin, 7);
  move_by(y, 0.1 * skin, 8);
  EXPECT_TRUE(lists.update(x, y, r));
  EXPECT_EQ(lists.rebuilds(), 2);
  expect_complete(lists, x, y, r, "after 0.55 skin");
  // A larger radius, or another point count, searches again.
  EXPECT_TRUE(lists.update(x, y, 1.5 * r));
  EXPECT_TRUE(lists.update(x, y.leftCols(10), 1.5 * r));
  EXPECT_EQ(lists.rebuilds(), 4);
  // Skin 0 searches whenever anything moved, and only then.
  NeighbourLists fresh(0);
  EXPECT_TRUE(fresh.update(x, y, r));
  EXPECT_FALSE(fresh.update(x, y, r));
  move_by(x, 1e-12, 9);
  EXPECT_TRUE(fresh.update(x, y, r));
  for (double bad : {-0.1, std::nan(""), HUGE_VAL}) EXPECT_THROW(NeighbourLists{bad}, InputError);
}

/// Every corrected-kernel variant: the in-place evaluation with stale (skin) lists on 1 and 2
/// threads gives the fresh evaluate()'s table bit for bit.
struct Variant {
  const char* approximation;
  const char* params;
};

class FastEvaluate : public ::testing::TestWithParam<Variant> {};

void expect_identical(const ShapeTable& a, const ShapeTable& b, const std::string& what) {
  EXPECT_EQ(a.dim, b.dim) << what;
  EXPECT_EQ(a.order, b.order) << what;
  EXPECT_EQ(a.offsets, b.offsets) << what;
  EXPECT_EQ(a.index, b.index) << what;
  // == on doubles: bit for bit (no NaN in these tables).
  EXPECT_EQ(a.value, b.value) << what;
  EXPECT_EQ(a.grad, b.grad) << what;
  EXPECT_EQ(a.hess, b.hess) << what;
}

TEST_P(FastEvaluate, EqualsTheFreshEvaluationBitForBit) {
  const Variant v = GetParam();
  const auto approx = test_catalogue().approximations.create(v.approximation, Params::parse(v.params));
  ParticleSet p;
  p.dim = 2;
  p.x = random_cloud(400, 21);
  p.volume = Eigen::VectorXd::Constant(400, 1.0 / 400);
  p.spacing = 0.05;
  // Dilations that differ per particle: supports not symmetric, the search radius the largest.
  p.dilation = Eigen::VectorXd::LinSpaced(400, 0.11, 0.14);
  // More points than kParallelMinimum: the 2-thread evaluation runs in parallel.
  Eigen::MatrixXd points = random_cloud(5000, 22).array() * 0.8 + 0.1;
  ASSERT_GT(points.cols(), kParallelMinimum);
  NeighbourLists lists1(0.02), lists2(0.02);
  ShapeTable t1, t2;
  for (int round = 0; round < 3; ++round) {
    // Moves of 0.004 per round: the first two rounds reuse the lists of round 0.
    if (round > 0) {
      move_by(p.x, 0.004, 30 + round);
      move_by(points, 0.004, 40 + round);
    }
    const std::string what = fmt::format("{} {} round {}", v.approximation, v.params, round);
    const ShapeTable fresh = approx->evaluate(p, points, 2);
    approx->evaluate_into(p, points, 2, lists1, 1, t1);
    approx->evaluate_into(p, points, 2, lists2, 2, t2);
    expect_identical(fresh, t1, what + ", 1 thread");
    expect_identical(fresh, t2, what + ", 2 threads");
  }
  EXPECT_EQ(lists1.rebuilds(), 1);
  EXPECT_EQ(lists2.rebuilds(), 1);
}

INSTANTIATE_TEST_SUITE_P(
    EveryCorrectedKernel, FastEvaluate,
    ::testing::Values(Variant{"shepard", ""}, Variant{"mls", ""}, Variant{"mls", "basis=2"},
                      Variant{"mls", "derivative=diffuse"}, Variant{"mls", "basis=0"},
                      Variant{"rkpm", "kernel=cubic-window"},
                      Variant{"rkpm", "kernel=cubic-window,derivative=diffuse"},
                      Variant{"sph", "kernel=cubic-spline"}),
    [](const auto& info) {
      std::string n = std::string(info.param.approximation) + "_" + info.param.params;
      for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

/// The plain kernel sums' first-order rows (written straight into the table, the Eulerian
/// SPH recomputation's path) equal the general path's (order 2) bit for bit, and the SPH
/// gradient built in place equals the one built into a second table.
/// 400 random particles in the unit square with dilations 0.11–0.14 (supports not symmetric).
ParticleSet varied_cloud(unsigned seed) {
  ParticleSet p;
  p.dim = 2;
  p.x = random_cloud(400, seed);
  p.volume = Eigen::VectorXd::Constant(400, 1.0 / 400);
  p.dilation = Eigen::VectorXd::LinSpaced(400, 0.11, 0.14);
  return p;
}

const char* const kFastPathKernels[] = {"cubic-spline", "quartic-spline", "gaussian"};

TEST(FastEvaluate, PlainKernelRowsAndTheInPlaceSphGradientAreTheGeneralOnes) {
  const ParticleSet p = varied_cloud(23);
  for (const char* kernel : kFastPathKernels) {
    const auto sph =
        test_catalogue().approximations.create("sph", Params::parse(fmt::format("kernel={}", kernel)));
    // Points: the particles themselves (a coincident particle per row) and a cloud.
    for (const Eigen::MatrixXd& points : {p.x, Eigen::MatrixXd(random_cloud(900, 24))}) {
      const ShapeTable first = sph->evaluate(p, points, 1);
      const ShapeTable second = sph->evaluate(p, points, 2);
      EXPECT_EQ(first.offsets, second.offsets) << kernel;
      EXPECT_EQ(first.index, second.index) << kernel;
      EXPECT_EQ(first.value, second.value) << kernel;
      EXPECT_EQ(first.grad, second.grad) << kernel;
    }
    ShapeTable in_place = sph->evaluate(p, p.x, 1);
    const ShapeTable copied = sph_symmetric_gradient(in_place);
    sph_symmetric_gradient_in_place(in_place, 2);
    expect_identical(copied, in_place, kernel);
  }
}

/// KBM's MLS trial values (2D linear basis, order 0) on fixed-size matrices equal the values
/// of the general path (order 1, dynamic-size matrices) bit for bit.
TEST(FastEvaluate, LinearMlsValuesOnFixedSizeMatricesAreTheGeneralOnes) {
  const ParticleSet p = varied_cloud(25);
  for (const char* kernel : kFastPathKernels) {
    const auto mls =
        test_catalogue().approximations.create("mls", Params::parse(fmt::format("kernel={}", kernel)));
    for (const Eigen::MatrixXd& points : {p.x, Eigen::MatrixXd(random_cloud(900, 26).array() * 0.8 + 0.1)}) {
      const ShapeTable values = mls->evaluate(p, points, 0);
      const ShapeTable general = mls->evaluate(p, points, 1);
      EXPECT_EQ(values.index, general.index) << kernel;
      EXPECT_EQ(values.value, general.value) << kernel;
    }
  }
}

/// The other three-term basis, quadratic on a line, takes the same fixed-size path: its
/// values are the general path's bit for bit too (the path reads the basis of the dimension
/// it is in).
TEST(FastEvaluate, QuadraticMlsValuesOnALineAreTheGeneralOnes) {
  ParticleSet p;
  p.dim = 1;
  p.x = Eigen::RowVectorXd::LinSpaced(41, 0, 1);
  p.x(0, 7) += 0.004;  // not a lattice: the moment matrices differ from point to point
  p.volume = Eigen::VectorXd::Constant(41, 1.0 / 40);
  p.dilation = Eigen::VectorXd::Constant(41, 0.09);
  const auto mls = test_catalogue().approximations.create("mls", Params::parse("basis=2"));
  const Eigen::MatrixXd points = Eigen::RowVectorXd::LinSpaced(97, 0, 1);
  const ShapeTable values = mls->evaluate(p, points, 0);
  const ShapeTable general = mls->evaluate(p, points, 1);
  EXPECT_EQ(values.index, general.index);
  EXPECT_EQ(values.value, general.value);
}

TEST(FastEvaluate, ThrowsTheLowestPointsErrorOnAnyThreadCount) {
  const auto mls = test_catalogue().approximations.create("mls");
  ParticleSet p;
  p.dim = 2;
  p.x = random_cloud(300, 50);
  p.volume = Eigen::VectorXd::Constant(300, 1.0 / 300);
  p.dilation = Eigen::VectorXd::Constant(300, 0.12);
  // Points 2500 and 4500 (of 5000: a parallel loop) lie far outside the cloud: no particle
  // covers them.
  // The others inside [0.1, 0.9]², where every point has a support of ~40 particles.
  Eigen::MatrixXd points = random_cloud(5000, 51).array() * 0.8 + 0.1;
  points.col(4500) << 5, 5;
  points.col(2500) << 3, 3;
  std::string serial, parallel;
  NeighbourLists l1(0.01), l2(0.01);
  ShapeTable t;
  try {
    mls->evaluate_into(p, points, 1, l1, 1, t);
  } catch (const SingularError& e) {
    serial = e.what();
  }
  try {
    mls->evaluate_into(p, points, 1, l2, 2, t);
  } catch (const SingularError& e) {
    parallel = e.what();
  }
  EXPECT_NE(serial.find("(3, 3)"), std::string::npos) << serial;
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace mfv
