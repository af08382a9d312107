/// Eulerian recomputations at degenerate supports (splashes and jets: a point's support holds
/// 0, 1 or 2 collinear particles): without Retabulation::degenerate_fallback every corrected
/// method throws SingularError as before; with it the run goes on, the points that fell back
/// are counted, every entry is finite, isolated points get zero gradients and empty supports
/// zero rows, and the rows of healthy points are those of a healthy set bit for bit.
#include <cmath>
#include <cstdio>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "methods/approximations/approximation.hpp"
#include "methods/core/errors.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

/// One 2D method under test and what it does with the configuration below.
struct Case {
  std::string method;
  bool corrected;  ///< false: uncorrected kernel sums (sph, sph-galerkin)
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.method; }

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return test_name(info.param.method);
}

constexpr int kSide = 9;  // 9 × 9 lattice on the unit square, Δx = 1/8
// Interior particles (i, j) = (2, 2), (6, 2), (2, 6), (6, 6), four spacings apart, so no
// lattice support loses more than one of them.
constexpr int kIsolatedA = 2 + kSide * 2, kIsolatedB = 6 + kSide * 2;
constexpr int kPairA = 2 + kSide * 6, kPairB = 6 + kSide * 6;

/// The discretization of `method` on the lattice (its rule built there), or nothing when the
/// method does not run in 2D.
std::optional<Discretization> lattice(const Method& m) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  try {
    return m.discretize(p->domain(), p->particles(kSide, 0), 1);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

/// Moves particle I to x, and its nodal integration point with it (point I is particle I
/// when the rule has nodal points).
void move_particle(Discretization& d, int I, double x, double y) {
  d.particles.x.col(I) << x, y;
  if (I < d.quadrature.nodal_points) d.quadrature.points.col(I) << x, y;
}

/// The first non-nodal integration points (stress points, Gauss points): the ones this test
/// moves; none for nodal rules.
std::vector<int> free_points(const Discretization& d) {
  std::vector<int> q;
  for (int k = d.quadrature.nodal_points; k < d.quadrature.size() && q.size() < 3; ++k)
    q.push_back(k);
  return q;
}

/// The degenerate set: two particles isolated far away (their supports: only themselves), two
/// as a collinear pair; non-nodal points moved to an empty spot, next to an isolated particle
/// and between the pair.
void degenerate(Discretization& d) {
  const double h = d.particles.spacing;
  move_particle(d, kIsolatedA, 10, 10);
  move_particle(d, kIsolatedB, -10, 5);
  move_particle(d, kPairA, 20, 0);
  move_particle(d, kPairB, 20 + h, 0);
  const std::vector<int> q = free_points(d);
  const double where[3][2] = {{50, 50}, {10 + 0.3 * h, 10}, {20 + 0.5 * h, 0}};
  for (std::size_t k = 0; k < q.size(); ++k) d.quadrature.points.col(q[k]) << where[k][0], where[k][1];
}

/// The same particles and points moved far away into a healthy cluster: a square of four
/// particles with the points inside it, so the lattice rows see the same supports.
void healthy_far_away(Discretization& d) {
  const double h = d.particles.spacing;
  move_particle(d, kIsolatedA, 20, 0);
  move_particle(d, kIsolatedB, 20 + h, 0);
  move_particle(d, kPairA, 20, h);
  move_particle(d, kPairB, 20 + h, h);
  const std::vector<int> q = free_points(d);
  const double where[3][2] = {{20 + 0.5 * h, 0.5 * h}, {20 + 0.3 * h, 0.3 * h},
                              {20 + 0.5 * h, 0.2 * h}};
  for (std::size_t k = 0; k < q.size(); ++k) d.quadrature.points.col(q[k]) << where[k][0], where[k][1];
}

/// The points the moves touched: moved nodal points and moved free points.
std::set<int> moved_points(const Discretization& d) {
  std::set<int> s;
  for (int I : {kIsolatedA, kIsolatedB, kPairA, kPairB})
    if (I < d.quadrature.nodal_points) s.insert(I);
  for (int q : free_points(d)) s.insert(q);
  return s;
}

Retabulation with_fallback(bool on, int threads = 1) {
  Retabulation r(0, threads);
  r.degenerate_fallback = on;
  return r;
}

bool all_finite(const ShapeTable& t) {
  for (const std::vector<double>* v : {&t.value, &t.grad, &t.hess})
    for (double x : *v)
      if (!std::isfinite(x)) return false;
  return true;
}

/// Row q of a and b: the same particles, values, gradients (and Hessians) bit for bit.
bool same_row(const ShapeTable& a, const ShapeTable& b, int q) {
  const int na = a.offsets[q + 1] - a.offsets[q], nb = b.offsets[q + 1] - b.offsets[q];
  if (na != nb) return false;
  for (int m = 0; m < na; ++m) {
    const int ka = a.offsets[q] + m, kb = b.offsets[q] + m;
    if (a.index[ka] != b.index[kb] || a.value[ka] != b.value[kb]) return false;
    for (int d = 0; d < a.dim; ++d)
      if (a.grad[ka * a.dim + d] != b.grad[kb * b.dim + d]) return false;
  }
  return true;
}

bool same_table(const ShapeTable& a, const ShapeTable& b) {
  return a.offsets == b.offsets && a.index == b.index && a.value == b.value && a.grad == b.grad &&
         a.hess == b.hess;
}

class DegenerateSupports : public ::testing::TestWithParam<Case> {};

TEST_P(DegenerateSupports, ThrowsWithoutTheFallbackAsBefore) {
  const Case& c = GetParam();
  const auto m = test_catalogue().methods.create(c.method, Params{});
  auto d = lattice(*m);
  if (!d) GTEST_SKIP() << c.method << " does not run in 2D";
  degenerate(*d);
  Retabulation off = with_fallback(false);
  if (c.method == "sph") {
    // Symmetrized SPH inverts nothing and every particle is in its own support.
    EXPECT_NO_THROW(m->retabulate(*d, 1, off));
  } else {
    EXPECT_THROW(m->retabulate(*d, 1, off), SingularError);
  }
  EXPECT_EQ(off.degenerate_points, 0);
}

TEST_P(DegenerateSupports, FallsBackCountsAndLeavesHealthyRowsAlone) {
  const Case& c = GetParam();
  const auto m = test_catalogue().methods.create(c.method, Params{});
  auto d = lattice(*m);
  if (!d) GTEST_SKIP() << c.method << " does not run in 2D";
  Discretization ref = *d;
  degenerate(*d);
  Retabulation on = with_fallback(true);
  ASSERT_NO_THROW(m->retabulate(*d, 1, on));

  // Expected count: corrected methods fall back at every moved nodal particle (isolated: no
  // neighbour to correct with; the pair: collinear) and at every moved free point (empty,
  // one particle, collinear pair); uncorrected kernel sums only at the empty support.
  const std::vector<int> free = free_points(*d);
  const int nodal_moved = d->quadrature.nodal_points > 0 ? 4 : 0;
  const long expected = c.corrected ? nodal_moved + static_cast<long>(free.size())
                                    : (free.empty() ? 0 : 1);
  std::printf("[ fallback ] %-12s %ld of %d points fell back\n", c.method.c_str(),
              on.degenerate_points, d->trial_q.points());
  EXPECT_EQ(on.degenerate_points, expected) << c.method;
  if (c.method != "sph") {
    EXPECT_GT(on.degenerate_points, 0);
  }

  for (const ShapeTable* t : {&d->trial_q, &d->test_q}) {
    EXPECT_TRUE(all_finite(*t));
    // Isolated particles: their row holds only themselves, with zero gradients.
    for (int I : {kIsolatedA, kIsolatedB}) {
      if (I >= d->quadrature.nodal_points) continue;
      ASSERT_EQ(t->offsets[I + 1] - t->offsets[I], 1);
      EXPECT_EQ(t->index[t->offsets[I]], I);
      for (int dd = 0; dd < 2; ++dd) EXPECT_EQ(t->grad[t->offsets[I] * 2 + dd], 0.0);
    }
    // The empty support: a zero row (no entries at all).
    if (!free.empty()) {
      EXPECT_EQ(t->offsets[free[0] + 1] - t->offsets[free[0]], 0);
    }
  }
  // Fallback rows of the trial functions keep zero-order consistency: Σ N = 1 (particle
  // values: δ), Σ ∇N = 0.
  if (c.corrected) {
    std::set<int> fell_back = moved_points(*d);
    if (!free.empty()) fell_back.erase(free[0]);
    const ShapeTable& t = d->trial_q;
    for (int q : fell_back) {
      double sum = 0, g[2] = {0, 0}, scale = 0;
      for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
        sum += t.value[k];
        for (int dd = 0; dd < 2; ++dd) {
          g[dd] += t.grad[k * 2 + dd];
          scale += std::abs(t.grad[k * 2 + dd]);
        }
      }
      EXPECT_NEAR(sum, 1.0, 1e-12) << "point " << q;
      for (int dd = 0; dd < 2; ++dd) EXPECT_LE(std::abs(g[dd]), 1e-12 * (1 + scale)) << q;
      // kbm's a = I: the corrected gradient is the Shepard test functions' gradient.
      if (c.method.rfind("kbm", 0) == 0) {
        const ShapeTable& shepard = d->test_q;
        for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k)
          for (int dd = 0; dd < 2; ++dd) EXPECT_EQ(t.grad[k * 2 + dd], shepard.grad[k * 2 + dd]);
      }
    }
  }
  // rlm's B = I: the collinear pair's gradients are symmetrized SPH's (same kernel, support).
  if (c.method == "rlm") {
    const auto sph = test_catalogue().methods.create("sph", Params{});
    auto ds = lattice(*sph);
    ASSERT_TRUE(ds);
    degenerate(*ds);
    Retabulation plain = with_fallback(false);
    sph->retabulate(*ds, 1, plain);
    for (int I : {kPairA, kPairB})
      for (const ShapeTable* t : {&d->trial_q, &ds->trial_q})
        EXPECT_EQ(t->offsets[I + 1] - t->offsets[I], 2) << "the pair sees only itself";
    for (int I : {kPairA, kPairB}) EXPECT_TRUE(same_row(d->trial_q, ds->trial_q, I)) << I;
  }

  // Healthy points: the rows of the same lattice with the moved particles and points in a
  // healthy cluster far away, retabulated without the fallback, bit for bit.
  healthy_far_away(ref);
  Retabulation off = with_fallback(false);
  ASSERT_NO_THROW(m->retabulate(ref, 1, off));
  const std::set<int> moved = moved_points(*d);
  int compared = 0;
  for (int q = 0; q < d->trial_q.points(); ++q) {
    if (moved.count(q)) continue;
    EXPECT_TRUE(same_row(d->trial_q, ref.trial_q, q)) << c.method << " trial row " << q;
    EXPECT_TRUE(same_row(d->test_q, ref.test_q, q)) << c.method << " test row " << q;
    ++compared;
  }
  EXPECT_GT(compared, 40);

  // The count and tables do not depend on the thread count.
  Discretization d2 = *d;
  Retabulation on2 = with_fallback(true, 2);
  m->retabulate(d2, 1, on2);
  EXPECT_EQ(on2.degenerate_points, on.degenerate_points);
  EXPECT_TRUE(same_table(d2.trial_q, d->trial_q));
  EXPECT_TRUE(same_table(d2.test_q, d->test_q));
}

TEST_P(DegenerateSupports, HealthySetIsUnchangedByTheOption) {
  // A perturbed lattice, no degenerate support: nothing falls back and the tables are those
  // without the option, bit for bit.
  const Case& c = GetParam();
  const auto m = test_catalogue().methods.create(c.method, Params{});
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  std::optional<Discretization> d;
  try {
    d = m->discretize(p->domain(), p->particles(kSide, 0.2), 1);
  } catch (const InputError&) {
    GTEST_SKIP() << c.method << " does not run in 2D";
  }
  // Move every particle and point a little, as a step of a flow does.
  Discretization a = *d;
  for (int I = 0; I < a.particles.size(); ++I)
    move_particle(a, I, a.particles.x(0, I) + 0.01 * std::sin(7.0 * I),
                  a.particles.x(1, I) + 0.01 * std::cos(5.0 * I));
  Discretization b = a;
  Retabulation off = with_fallback(false), on = with_fallback(true);
  m->retabulate(a, 1, off);
  m->retabulate(b, 1, on);
  EXPECT_EQ(on.degenerate_points, 0);
  EXPECT_TRUE(same_table(a.trial_q, b.trial_q));
  EXPECT_TRUE(same_table(a.test_q, b.test_q));
}

TEST(DegenerateSupportsMls, FallbackRowsAreTheShepardFunctionsWithTheirDerivatives) {
  // Second derivatives too: a point of a collinear pair's support and one with a single
  // particle, linear MLS with the fallback against the Shepard approximation of the same
  // weight (basis 1), values, gradients and Hessians to 1e-12 relative.
  const auto& approximations = test_catalogue().approximations;
  const Params kernel = Params::parse("kernel=cubic-window");
  const auto mls = approximations.create("mls", kernel);
  const auto shepard = approximations.create("shepard", kernel);
  ParticleSet p;
  p.dim = 2;
  p.x.resize(2, 3);
  p.x << 0, 1, 10,  //
      0, 0, 0;
  p.volume = Eigen::VectorXd::Ones(3);
  p.dilation = Eigen::VectorXd::Constant(3, 1.0);
  p.spacing = 1;
  Eigen::MatrixXd points(2, 3);
  points << 0.4, 10.2, 40,  //
      0.3, 0.1, 0;
  NeighbourLists lists(0);
  ShapeTable t;
  DegenerateMarks marks;
  EXPECT_THROW(mls->evaluate_into(p, points, 2, lists, 1, t), SingularError);
  mls->evaluate_into(p, points, 2, lists, 1, t, &marks);
  EXPECT_EQ(marks.count(), 3);
  // The Shepard functions where the support is not empty (point 3's is).
  const ShapeTable s = shepard->evaluate(p, points.leftCols(2), 2);
  ASSERT_EQ(t.offsets[2], s.offsets[2]);
  EXPECT_EQ(t.offsets[3] - t.offsets[2], 0) << "an empty support: a zero row";
  for (int k = 0; k < s.entries(); ++k) {
    EXPECT_EQ(t.index[k], s.index[k]);
    EXPECT_NEAR(t.value[k], s.value[k], 1e-12);
    for (int i = 0; i < 2; ++i)
      EXPECT_NEAR(t.grad[k * 2 + i], s.grad[k * 2 + i], 1e-12 * (1 + std::abs(s.grad[k * 2 + i])));
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(t.hess[k * 4 + i], s.hess[k * 4 + i], 1e-12 * (1 + std::abs(s.hess[k * 4 + i])));
  }
}

INSTANTIATE_TEST_SUITE_P(EveryEulerianMethod, DegenerateSupports,
                         ::testing::Values(Case{"sph", false}, Case{"sph-galerkin", false},
                                           Case{"rlm", true}, Case{"kbm-ni", true},
                                           Case{"kbm-si", true}, Case{"kbm-ci", true},
                                           Case{"efg", true}, Case{"efg-ni", true},
                                           Case{"efg-ci", true}, Case{"rkpm", true}),
                         case_name);

}  // namespace
}  // namespace mfv
