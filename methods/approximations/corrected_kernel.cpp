/// Moment-corrected kernel approximation: Shepard, MLS/EFG, RKPM and SPH in one composition.
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "methods/approximations/approximation.hpp"
#include "methods/core/resources.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/parallel.hpp"
#include "methods/neighbours.hpp"

namespace mfv {

namespace {

int basis_size(int order, int dim) {
  if (order == 0) return 1;
  if (order == 1) return 1 + dim;
  return 1 + dim + dim * (dim + 1) / 2;
}

/// Monomial basis in ξ = (y - x̄)/ā: 1, ξ_i, ξ_iξ_j (i <= j).
void basis_at(int order, int dim, const double* xi, double* p) {
  p[0] = 1;
  if (order < 1) return;
  for (int i = 0; i < dim; ++i) p[1 + i] = xi[i];
  if (order < 2) return;
  int k = 1 + dim;
  for (int i = 0; i < dim; ++i)
    for (int j = i; j < dim; ++j) p[k++] = xi[i] * xi[j];
}

/// M += c p pᵀ, element by element as Eigen's outer product M += (c p) pᵀ does it (the
/// scaled column first, then times p_j), without its dynamic-size dispatch per call. `Matrix`
/// is square and column-major, of fixed or dynamic size.
template <class Matrix>
void add_outer(Matrix& M, double c, const double* p) {
  const Eigen::Index n = M.rows();
  double cp[10];  // the largest basis: quadratic in 3D (basis_size(2, 3))
  for (Eigen::Index i = 0; i < n; ++i) cp[i] = c * p[i];
  double* m = M.data();
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i) m[i + n * j] += p[j] * cp[i];
}

std::string point_text(const double* x, int dim) {
  std::string s = "(";
  for (int d = 0; d < dim; ++d) s += fmt::format("{}{:.6g}", d ? ", " : "", x[d]);
  return s + ")";
}

}  // namespace

CorrectedKernelApproximation::CorrectedKernelApproximation(std::shared_ptr<const Kernel> kernel,
                                                           CorrectedKernelOptions opts,
                                                           std::string name)
    : kernel_(std::move(kernel)), options_(opts), name_(std::move(name)) {}

int CorrectedKernelApproximation::minimum_support_count(int dim) const {
  return options_.correct ? basis_size(options_.basis_order, dim) : 1;
}

double CorrectedKernelApproximation::search_radius(const ParticleSet& particles) const {
  return kernel_->support() * particles.dilation.maxCoeff();
}

void CorrectedKernelApproximation::check_table_size(std::int64_t entries, int points,
                                                    const ParticleSet& particles,
                                                    int order) const {
  const int dim = particles.dim;
  const std::int64_t n = particles.size();
  const double per_entry =
      4.0 + 8.0 * (1 + (order >= 1 ? dim : 0) + (order >= 2 ? dim * dim : 0));
  const double bytes = static_cast<double>(entries) * per_entry;
  const double mean = points > 0 ? static_cast<double>(entries) / points : 0.0;
  const double radius = search_radius(particles);
  const std::string support =
      fmt::format("search radius {:.4g} = {:.3g} particle spacings", radius,
                  particles.spacing > 0 ? radius / particles.spacing : NAN);
  if (n >= kDenseFromParticles && mean > kDenseFraction * static_cast<double>(n))
    throw InputError(fmt::format(
        "{}: each point's support holds {:.0f} of the {} particles on average ({:.0f} %; {}): "
        "the system would be dense, which a support of a few spacings never is; give a "
        "smaller support (dmax 2-4, radius or h of a few spacings, j for RKPM windows)",
        name_, mean, n, 100 * mean / static_cast<double>(n), support));
  if (entries > std::numeric_limits<int>::max())
    throw InputError(fmt::format("{}: the shape-function table would hold {} entries ({}), more "
                                 "than its int offsets can index; give a smaller support or fewer "
                                 "nodes",
                                 name_, entries, support));
  const std::uint64_t have = available_memory_bytes();
  if (have > 0 && bytes > static_cast<double>(have))
    throw InputError(fmt::format(
        "{}: the shape-function table needs {:.3g} GB ({} entries: {:.0f} particles per point at "
        "{} points; {}), more than the {:.3g} GB of memory available (the smaller of free memory "
        "and the address-space limit); give a smaller support or fewer nodes",
        name_, bytes / 1e9, entries, mean, points, support, static_cast<double>(have) / 1e9));
}

namespace {

/// One thread's work space for the points it evaluates: sized on the first point, reused by
/// the next ones (no allocation per point once the largest support has been seen).
struct PointScratch {
  std::vector<int> nbrs;
  std::vector<double> s, W, dW, d2W, w, gw, hw, r;
  Eigen::MatrixXd P, M, Md[3], Mdd[9];  // basis at the neighbours; moment matrix, derivatives
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  Eigen::VectorXd p0, gamma, gd[3], gdd[9];
};

}  // namespace

/// The moment-corrected shape functions at x into the table's rows starting at entry row0,
/// from the candidate particles `cand` (ascending index, a superset of the support).
struct CorrectedKernelApproximation::PointEvaluator {
  const CorrectedKernelApproximation& a;
  const ParticleSet& particles;
  int order, dim, nb, nh;
  double support, amax, kernel_scale;
  Eigen::VectorXd pd[3], pdd[9];  // derivatives of p at ξ = 0 (constant: scaled by amax)
  /// The weight factor of each particle, kernel_scale / a_J^d [ΔV_J], when the points are
  /// many (one pow per particle instead of one per entry); empty: computed per entry.
  std::vector<double> factor;
  /// (support · a_J)²: x lies in particle J's support when |x − x_J|² is below it (a square
  /// root and a division only for the particles that are in).
  std::vector<double> reach2;

  PointEvaluator(const CorrectedKernelApproximation& approx, const ParticleSet& p, int ord,
                 Eigen::Index points)
      : a(approx), particles(p), order(ord), dim(p.dim) {
    const CorrectedKernelOptions& o = a.options_;
    support = a.kernel_->support();
    amax = particles.dilation.maxCoeff();
    kernel_scale = o.normalize_kernel ? 1.0 / a.kernel_->integral(dim) : 1.0;
    if (4 * points >= particles.size()) {
      factor.resize(particles.size());
      // Dilations are mostly one value: pow once per run of equal ones (the same number).
      double a_last = std::nan(""), scaled = 0;
      for (int J = 0; J < particles.size(); ++J) {
        const double aj = particles.dilation[J];
        if (!(aj == a_last)) {
          a_last = aj;
          scaled = kernel_scale / std::pow(aj, dim);
        }
        factor[J] = o.volume_weighted ? scaled * particles.volume[J] : scaled;
      }
    }
    reach2.resize(particles.size());
    for (int J = 0; J < particles.size(); ++J) {
      const double reach = support * particles.dilation[J];
      reach2[J] = reach * reach;
    }
    nb = o.correct ? basis_size(o.basis_order, dim) : 0;
    nh = dim * dim;
    for (int i = 0; i < dim; ++i) pd[i] = Eigen::VectorXd::Zero(nb);
    for (int i = 0; i < nh; ++i) pdd[i] = Eigen::VectorXd::Zero(nb);
    if (o.correct && o.basis_order >= 1)
      for (int i = 0; i < dim; ++i) pd[i][1 + i] = 1 / amax;
    if (o.correct && o.basis_order >= 2) {
      int kk = 1 + dim;
      for (int i = 0; i < dim; ++i)
        for (int j = i; j < dim; ++j, ++kk) {
          const double v = (i == j ? 2.0 : 1.0) / (amax * amax);
          pdd[i * dim + j][kk] = v;
          pdd[j * dim + i][kk] = v;
        }
    }
  }

  double weight_factor(int J) const {
    double c = kernel_scale / std::pow(particles.dilation[J], dim);
    if (a.options_.volume_weighted) c *= particles.volume[J];
    return c;
  }

  /// Particles of `cand` whose own support (dilation a_J) covers x, with their offsets
  /// r = x − x_J and scaled distances s = |r|/a_J, into the scratch.
  std::size_t support_of(const double* x, std::span<const int> cand, PointScratch& sc) const {
    const std::size_t n0 = cand.size();
    sc.nbrs.resize(n0);
    sc.s.resize(n0);
    sc.r.resize(n0 * dim);
    std::size_t k = 0;
    for (std::size_t m = 0; m < n0; ++m) {
      const int J = cand[m];
      const double dist2 = offset_from(x, J, &sc.r[k * dim]);
      if (dist2 < reach2[J]) {
        sc.nbrs[k] = J;
        sc.s[k] = std::sqrt(dist2) / particles.dilation[J];
        ++k;
      }
    }
    sc.nbrs.resize(k);
    sc.s.resize(k);
    return k;
  }

  /// How many particles of `cand` support_of would keep: the same test, nothing kept (the
  /// first of evaluate_into's two passes only sizes the rows).
  std::size_t support_count(const double* x, std::span<const int> cand) const {
    std::size_t k = 0;
    double r[3];
    for (const int J : cand) k += offset_from(x, J, r) < reach2[J];
    return k;
  }

  /// r = x − x_J into `r` (dim entries); returns |r|², summed in the order d = 0, 1, …
  double offset_from(const double* x, int J, double* r) const {
    double dist2 = 0;
    for (int d = 0; d < dim; ++d) {
      r[d] = x[d] - particles.x(d, J);
      dist2 += r[d] * r[d];
    }
    return dist2;
  }

  void check_count(const double* x, std::size_t k) const {
    const int need = std::max(1, a.minimum_support_count(dim));
    if (static_cast<int>(k) < need)
      throw SingularError(fmt::format(
          "{}: the point {} lies in the support of only {} particle(s) but the basis needs {}; "
          "increase the dilation (support size) or add particles",
          a.name_, point_text(x, dim), k, need));
  }

  /// The Shepard row (basis 1, order <= 1, exact derivatives): the moment matrix is the
  /// number M = Σ w_J, its LDLT is M itself and the solves below are divisions by it, so this
  /// is the general path's arithmetic, operation for operation, without the dynamic-size
  /// machinery (1/M, then (0 − M_i γ)/M for the derivatives, M_i = Σ ∂_i w_J). Returns false,
  /// leaving the row to the general path, where M is not a normal positive number (that path
  /// then reports it exactly as before).
  bool shepard(const PointScratch& sc, ShapeTable& t, int row0) const {
    const std::size_t k = sc.nbrs.size();
    const std::vector<double>&w = sc.w, &gw = sc.gw;
    double M = 0;
    for (std::size_t m = 0; m < k; ++m) M += w[m];
    if (!(M >= std::numeric_limits<double>::min() && M <= std::numeric_limits<double>::max()))
      return false;
    const double gamma = 1.0 / M;
    double gd[3] = {};
    if (order >= 1)
      for (int i = 0; i < dim; ++i) {
        double Mi = 0;
        for (std::size_t m = 0; m < k; ++m) Mi += gw[m * dim + i];
        gd[i] = (0.0 - Mi * gamma) / M;
      }
    for (std::size_t m = 0; m < k; ++m) {
      t.value[row0 + m] = gamma * w[m];
      if (order >= 1)
        for (int i = 0; i < dim; ++i)
          t.grad[(row0 + m) * dim + i] = gd[i] * w[m] + gamma * gw[m * dim + i];
    }
    return true;
  }

  /// The basis at the support's particles into sc.P (nb × k), in coordinates centred on x and
  /// scaled by amax (conditioning).
  void basis_at_neighbours(PointScratch& sc) const {
    const std::size_t k = sc.nbrs.size();
    Eigen::MatrixXd& P = sc.P;
    P.resize(nb, static_cast<Eigen::Index>(k));
    double xi[3];
    for (std::size_t m = 0; m < k; ++m) {
      for (int d = 0; d < dim; ++d) xi[d] = -sc.r[m * dim + d] / amax;
      basis_at(a.options_.basis_order, dim, xi, P.col(static_cast<Eigen::Index>(m)).data());
    }
  }

  /// The values (order 0) of a three-term basis (linear in 2D: KBM's MLS trial values;
  /// quadratic on a line) with a fixed-size moment matrix: the general path's arithmetic (the
  /// same basis, sums, LDLT and solve) without its dynamic-size allocations per point. Returns
  /// false, leaving the row to the general path, where the moment matrix is singular or
  /// ill-conditioned (that path then reports it or falls back exactly as before).
  bool three_term_values(PointScratch& sc, ShapeTable& t, int row0) const {
    const std::size_t k = sc.nbrs.size();
    basis_at_neighbours(sc);
    const Eigen::MatrixXd& P = sc.P;
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (std::size_t m = 0; m < k; ++m) add_outer(M, sc.w[m], P.col(m).data());
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(M);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-13)) return false;
    const Eigen::Vector3d gamma = ldlt.solve(Eigen::Vector3d::UnitX());
    for (std::size_t m = 0; m < k; ++m)
      t.value[row0 + m] = gamma.dot(P.col(static_cast<Eigen::Index>(m))) * sc.w[m];
    return true;
  }

  /// The fallback row of a degenerate support (the class comment says when): the Shepard
  /// functions N_J = γ w_J, γ = 1/S, S = Σ w_J, with their exact derivatives
  /// ∂_i γ = -S_i/S², ∂_ij γ = -S_ij/S² + 2 S_i S_j/S³; a zero row where S is not a normal
  /// positive number (an empty support has nothing to normalize).
  void shepard_fallback(const PointScratch& sc, ShapeTable& t, int row0) const {
    const std::size_t k = sc.nbrs.size();
    const std::vector<double>&w = sc.w, &gw = sc.gw, &hw = sc.hw;
    double S = 0, Si[3] = {}, Sij[9] = {};
    for (std::size_t m = 0; m < k; ++m) {
      S += w[m];
      for (int i = 0; i < dim && order >= 1; ++i) Si[i] += gw[m * dim + i];
      for (int i = 0; i < nh && order >= 2; ++i) Sij[i] += hw[m * nh + i];
    }
    const bool empty =
        !(S >= std::numeric_limits<double>::min() && S <= std::numeric_limits<double>::max());
    const double gamma = empty ? 0.0 : 1.0 / S;
    double gd[3] = {}, gdd[9] = {};
    for (int i = 0; i < dim && order >= 1 && !empty; ++i) gd[i] = -Si[i] * gamma / S;
    for (int i = 0; i < dim && order >= 2 && !empty; ++i)
      for (int j = 0; j < dim; ++j)
        gdd[i * dim + j] = (-Sij[i * dim + j] + 2 * Si[i] * Si[j] * gamma) * gamma / S;
    for (std::size_t m = 0; m < k; ++m) {
      t.value[row0 + m] = gamma * w[m];
      for (int i = 0; i < dim && order >= 1; ++i)
        t.grad[(row0 + m) * dim + i] = gd[i] * w[m] + gamma * gw[m * dim + i];
      for (int i = 0; i < dim && order >= 2; ++i)
        for (int j = 0; j < dim; ++j) {
          const int ij = i * dim + j;
          t.hess[(row0 + m) * nh + ij] = gdd[ij] * w[m] + gd[i] * gw[m * dim + j] +
                                         gd[j] * gw[m * dim + i] + gamma * hw[m * nh + ij];
        }
    }
  }

  /// Row of point x (its support already in sc, k = sc.nbrs.size()) into t from entry row0.
  /// With `fallback`, a support that would throw SingularError takes shepard_fallback's row
  /// instead, and the call returns true; every other row is computed as without it.
  bool fill(const double* x, PointScratch& sc, ShapeTable& t, int row0, bool fallback) const {
    const CorrectedKernelOptions& o = a.options_;
    const std::size_t k = sc.nbrs.size();
    if (!fallback) check_count(x, k);
    std::vector<double>&s = sc.s, &W = sc.W, &dW = sc.dW, &d2W = sc.d2W, &w = sc.w, &gw = sc.gw,
                       &hw = sc.hw, &r = sc.r;
    W.resize(k);
    dW.resize(k);
    d2W.resize(order >= 2 ? k : 0);
    a.kernel_->evaluate(s, W, order >= 1 ? std::span<double>(dW) : std::span<double>{},
                        order >= 2 ? std::span<double>(d2W) : std::span<double>{});
    // The plain kernel sums (sph) up to first derivatives: straight into the table, the same
    // arithmetic as the weights below (the Eulerian recomputation's hot loop).
    if (!o.correct && order <= 1 &&
        !(fallback && static_cast<int>(k) < std::max(1, a.minimum_support_count(dim)))) {
      for (std::size_t m = 0; m < k; ++m) {
        const int J = sc.nbrs[m];
        const double aj = particles.dilation[J];
        const double c = factor.empty() ? weight_factor(J) : factor[J];
        const std::size_t e = row0 + m;
        t.index[e] = J;
        t.value[e] = c * W[m];
        if (order < 1) continue;
        const double dist = s[m] * aj;
        const double* rr = &r[m * dim];
        const bool centre = dist < 1e-14 * aj;
        for (int i = 0; i < dim; ++i)
          t.grad[e * dim + i] = centre ? 0.0 : c * dW[m] * rr[i] / (dist * aj);
      }
      return false;
    }
    // Weights w_J(x) and their x-derivatives. The second derivatives are read only at
    // order 2 and at a coincident particle, where they are written below.
    w.resize(k);
    gw.assign(k * dim, 0);
    hw.assign(order >= 2 ? k * nh : 0, 0);
    for (std::size_t m = 0; m < k; ++m) {
      const int J = sc.nbrs[m];
      const double aj = particles.dilation[J];
      const double c = factor.empty() ? weight_factor(J) : factor[J];
      w[m] = c * W[m];
      if (order < 1) continue;
      const double dist = s[m] * aj;
      const double* rr = &r[m * dim];
      if (dist < 1e-14 * aj) {
        if (order >= 2)
          for (int i = 0; i < dim; ++i) hw[m * nh + i * dim + i] = c * d2W[m] / (aj * aj);
        continue;
      }
      for (int i = 0; i < dim; ++i) gw[m * dim + i] = c * dW[m] * rr[i] / (dist * aj);
      if (order < 2) continue;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          const double ninj = rr[i] * rr[j] / (dist * dist);
          hw[m * nh + i * dim + j] =
              c * (d2W[m] * ninj / (aj * aj) + dW[m] / (aj * dist) * ((i == j) - ninj));
        }
    }

    std::copy(sc.nbrs.begin(), sc.nbrs.end(), t.index.begin() + row0);
    if (fallback && static_cast<int>(k) < std::max(1, a.minimum_support_count(dim))) {
      shepard_fallback(sc, t, row0);
      return true;
    }
    if (!o.correct) {
      for (std::size_t m = 0; m < k; ++m) {
        t.value[row0 + m] = w[m];
        for (int i = 0; i < dim && order >= 1; ++i) t.grad[(row0 + m) * dim + i] = gw[m * dim + i];
        for (int i = 0; i < nh && order >= 2; ++i) t.hess[(row0 + m) * nh + i] = hw[m * nh + i];
      }
      return false;
    }

    if (nb == 1 && order <= 1 && !o.diffuse_derivative && shepard(sc, t, row0)) return false;
    if (nb == 3 && order == 0 && three_term_values(sc, t, row0)) return false;

    basis_at_neighbours(sc);
    const Eigen::MatrixXd& P = sc.P;
    Eigen::MatrixXd& M = sc.M;
    M.resize(nb, nb);
    M.setZero();
    for (std::size_t m = 0; m < k; ++m) add_outer(M, w[m], P.col(m).data());
    Eigen::LDLT<Eigen::MatrixXd>& ldlt = sc.ldlt;
    ldlt.compute(M);
    const double rc = ldlt.rcond();
    if (fallback && (ldlt.info() != Eigen::Success || !(rc > 1e-13))) {
      shepard_fallback(sc, t, row0);
      return true;
    }
    if (ldlt.info() != Eigen::Success || !(rc > 1e-13))
      throw SingularError(fmt::format(
          "{}: the moment matrix at {} is singular (reciprocal condition {:.2e}) with {} "
          "particles in the support; they are too few or collinear for the basis: increase the "
          "dilation or the particle count",
          a.name_, point_text(x, dim), rc, k));

    // p(x) and its derivatives at ξ = 0.
    sc.p0.setZero(nb);
    sc.p0[0] = 1;
    Eigen::VectorXd& gamma = sc.gamma;
    gamma = ldlt.solve(sc.p0);
    Eigen::VectorXd* gd = sc.gd;
    Eigen::VectorXd* gdd = sc.gdd;
    Eigen::MatrixXd* Md = sc.Md;
    Eigen::MatrixXd* Mdd = sc.Mdd;
    if (order >= 1) {
      for (int i = 0; i < dim; ++i) {
        if (o.diffuse_derivative) {
          gd[i] = ldlt.solve(pd[i]);
          continue;
        }
        Md[i].resize(nb, nb);
        Md[i].setZero();
        for (std::size_t m = 0; m < k; ++m)
          add_outer(Md[i], gw[m * dim + i], P.col(m).data());
        gd[i] = ldlt.solve(pd[i] - Md[i] * gamma);
      }
    }
    if (order >= 2) {
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          const int ij = i * dim + j;
          if (o.diffuse_derivative) {
            gdd[ij] = ldlt.solve(pdd[ij]);
            continue;
          }
          Mdd[ij].resize(nb, nb);
          Mdd[ij].setZero();
          for (std::size_t m = 0; m < k; ++m)
            add_outer(Mdd[ij], hw[m * nh + ij], P.col(m).data());
          gdd[ij] = ldlt.solve(pdd[ij] - Md[i] * gd[j] - Md[j] * gd[i] - Mdd[ij] * gamma);
        }
    }
    for (std::size_t m = 0; m < k; ++m) {
      const auto pj = P.col(static_cast<Eigen::Index>(m));
      const double gp = gamma.dot(pj);
      t.value[row0 + m] = gp * w[m];
      if (order >= 1)
        for (int i = 0; i < dim; ++i) {
          double v = gd[i].dot(pj) * w[m];
          if (!o.diffuse_derivative) v += gp * gw[m * dim + i];
          t.grad[(row0 + m) * dim + i] = v;
        }
      if (order >= 2)
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) {
            const int ij = i * dim + j;
            double v = gdd[ij].dot(pj) * w[m];
            if (!o.diffuse_derivative)
              v += gd[i].dot(pj) * gw[m * dim + j] + gd[j].dot(pj) * gw[m * dim + i] +
                   gp * hw[m * nh + ij];
            t.hess[(row0 + m) * nh + ij] = v;
          }
    }
    return false;
  }
};

ShapeTable CorrectedKernelApproximation::evaluate(const ParticleSet& particles,
                                                  const Eigen::MatrixXd& points, int order) const {
  // A fresh search (skin 0) on one thread: the table every caller has always had.
  NeighbourLists lists(0);
  ShapeTable t;
  evaluate_into(particles, points, order, lists, 1, t);
  return t;
}

void CorrectedKernelApproximation::evaluate_into(const ParticleSet& particles,
                                                 const Eigen::MatrixXd& points, int order,
                                                 NeighbourLists& lists, int threads,
                                                 ShapeTable& t, DegenerateMarks* degenerate) const {
  const int dim = particles.dim;
  if (points.rows() != dim)
    throw std::logic_error("evaluation points and particles differ in dimension");
  if (particles.size() == 0) throw InputError("no particles to build shape functions from");
  if (!(particles.dilation.minCoeff() > 0))
    throw InputError(fmt::format("{}: every particle needs a positive dilation (support size); "
                                 "got a minimum of {}: raise the support parameter (dmax, radius, "
                                 "or j for RKPM windows 2^j)",
                                 name_, particles.dilation.minCoeff()));
  threads = std::max(1, threads);
  lists.update(particles.x, points, search_radius(particles), threads);
  const PointEvaluator eval(*this, particles, order, points.cols());
  const int nq = static_cast<int>(points.cols());
  t.dim = dim;
  t.order = order;
  t.offsets.resize(nq + 1);
  t.offsets[0] = 0;
  // Two passes so every thread writes its rows in place: the support sizes, their prefix sums
  // (the row offsets), then the rows. The table is the serial one on any thread count.
  FirstError error;
  const bool parallel = run_parallel(threads, nq);
#pragma omp parallel for schedule(static) num_threads(threads) if (parallel)
    for (int q = 0; q < nq; ++q) {
      const double* x = points.col(q).data();
      t.offsets[q + 1] = static_cast<int>(eval.support_count(x, lists.candidates(q)));
    }
  // The table's size is known now, before its values are allocated: a support that makes it
  // dense, or larger than the memory there is, is refused with the estimate (issue 26).
  std::int64_t total = 0;
  for (int q = 0; q < nq; ++q) total += t.offsets[q + 1];
  check_table_size(total, nq, particles, order);
  for (int q = 0; q < nq; ++q) t.offsets[q + 1] += t.offsets[q];
  const std::size_t entries = t.offsets[nq];
  t.index.resize(entries);
  t.value.resize(entries);
  t.grad.resize(order >= 1 ? entries * dim : 0);
  t.hess.resize(order >= 2 ? entries * dim * dim : 0);
  if (degenerate) degenerate->cover(nq);
#pragma omp parallel num_threads(threads) if (parallel)
  {
    PointScratch sc;
#pragma omp for schedule(dynamic, 64)
    for (int q = 0; q < nq; ++q) {
      const double* x = points.col(q).data();
      try {
        eval.support_of(x, lists.candidates(q), sc);
        if (eval.fill(x, sc, t, t.offsets[q], degenerate != nullptr)) degenerate->mark(q);
      } catch (...) {
        error.keep(q, std::current_exception());
      }
    }
  }
  error.rethrow();
}

ShapeTable LinearElementApproximation::evaluate(const ParticleSet& particles,
                                                const Eigen::MatrixXd& points, int order) const {
  if (particles.dim != 1)
    throw InputError("the linear element approximation is 1D only (2D Q4 arrives with 2D)");
  const Eigen::VectorXd xs = particles.x.row(0).transpose();
  const int n = static_cast<int>(xs.size());
  for (int i = 1; i < n; ++i)
    if (!(xs[i] > xs[i - 1]))
      throw InputError("linear elements need particles in increasing order along the line");
  ShapeTable t;
  t.dim = 1;
  t.order = order;
  for (Eigen::Index q = 0; q < points.cols(); ++q) {
    const double x = points(0, q);
    if (x < xs[0] - 1e-12 * (xs[n - 1] - xs[0]) || x > xs[n - 1] + 1e-12 * (xs[n - 1] - xs[0]))
      throw InputError(fmt::format("point x = {} lies outside the element mesh [{}, {}]", x,
                                   xs[0], xs[n - 1]));
    int e = static_cast<int>(std::upper_bound(xs.data(), xs.data() + n, x) - xs.data()) - 1;
    e = std::clamp(e, 0, n - 2);
    const double h = xs[e + 1] - xs[e];
    t.index.push_back(e);
    t.index.push_back(e + 1);
    t.value.push_back((xs[e + 1] - x) / h);
    t.value.push_back((x - xs[e]) / h);
    if (order >= 1) {
      t.grad.push_back(-1 / h);
      t.grad.push_back(1 / h);
    }
    if (order >= 2) {
      t.hess.push_back(0);
      t.hess.push_back(0);
    }
    t.offsets.push_back(t.entries());
  }
  return t;
}

}  // namespace mfv
