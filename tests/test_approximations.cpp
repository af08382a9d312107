/// Approximation conformance over every registered approximation: partition of unity and
/// linear reproduction of values, first and second derivatives to round-off, on uniform and
/// on randomly perturbed particles; SPH is held to its known boundary defect instead.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

struct Layout {
  double perturbation;
  const char* name;
};

class ApproximationConformance
    : public ::testing::TestWithParam<std::tuple<std::string, Layout>> {
 protected:
  void SetUp() override {
    const auto& [name, layout] = GetParam();
    approx = test_catalogue().approximations.create(name);
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

INSTANTIATE_TEST_SUITE_P(
    AllApproximations, ApproximationConformance,
    ::testing::Combine(::testing::ValuesIn(test_catalogue().approximations.keys()),
                       ::testing::ValuesIn(kLayouts)),
    [](const auto& info) {
      std::string n = std::get<0>(info.param) + "_" + std::get<1>(info.param).name;
      for (auto& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

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
