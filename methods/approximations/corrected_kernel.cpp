/// Moment-corrected kernel approximation: Shepard, MLS/EFG, RKPM and SPH in one composition.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "methods/approximations/approximation.hpp"
#include "methods/core/errors.hpp"
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

ShapeTable CorrectedKernelApproximation::evaluate(const ParticleSet& particles,
                                                  const Eigen::MatrixXd& points, int order) const {
  const int dim = particles.dim;
  if (points.rows() != dim)
    throw std::logic_error("evaluation points and particles differ in dimension");
  if (particles.size() == 0) throw InputError("no particles to build shape functions from");
  const double support = kernel_->support();
  const double amax = particles.dilation.maxCoeff();
  if (!(particles.dilation.minCoeff() > 0))
    throw InputError(fmt::format("{}: every particle needs a positive dilation (support size); "
                                 "got a minimum of {}: raise the support parameter (dmax, radius, "
                                 "or j for RKPM windows 2^j)",
                                 name_, particles.dilation.minCoeff()));
  const double kernel_scale = options_.normalize_kernel ? 1.0 / kernel_->integral(dim) : 1.0;
  const int nb = options_.correct ? basis_size(options_.basis_order, dim) : 0;
  const int nh = dim * dim;

  NeighbourSearch search(particles);
  ShapeTable t;
  t.dim = dim;
  t.order = order;
  t.offsets.assign(1, 0);
  t.offsets.reserve(points.cols() + 1);

  std::vector<int> nbrs;
  std::vector<double> s, W, dW, d2W, w, gw, hw, r;
  Eigen::MatrixXd P;  // nb × k basis at neighbours
  Eigen::MatrixXd M(nb, nb), Md[3], Mdd[9];
  for (int i = 0; i < dim; ++i) Md[i].resize(nb, nb);
  for (int i = 0; i < nh; ++i) Mdd[i].resize(nb, nb);

  for (Eigen::Index q = 0; q < points.cols(); ++q) {
    const double* x = points.col(q).data();
    search.within(x, support * amax, nbrs);
    // Keep particles whose own support (dilation a_J) covers x.
    const std::size_t n0 = nbrs.size();
    s.resize(n0);
    r.resize(n0 * dim);
    std::size_t k = 0;
    for (std::size_t m = 0; m < n0; ++m) {
      const int J = nbrs[m];
      double dist2 = 0;
      for (int d = 0; d < dim; ++d) {
        const double dd = x[d] - particles.x(d, J);
        r[k * dim + d] = dd;
        dist2 += dd * dd;
      }
      const double sj = std::sqrt(dist2) / particles.dilation[J];
      if (sj < support) {
        nbrs[k] = J;
        s[k] = sj;
        ++k;
      }
    }
    nbrs.resize(k);
    s.resize(k);
    if (static_cast<int>(k) < std::max(1, minimum_support_count(dim)))
      throw SingularError(fmt::format(
          "{}: the point {} lies in the support of only {} particle(s) but the basis needs {}; "
          "increase the dilation (support size) or add particles",
          name_, point_text(x, dim), k, std::max(1, minimum_support_count(dim))));
    W.resize(k);
    dW.resize(k);
    d2W.resize(k);
    kernel_->evaluate(s, W, order >= 1 ? std::span<double>(dW) : std::span<double>{},
                      order >= 2 ? std::span<double>(d2W) : std::span<double>{});
    // Weights w_J(x) and their x-derivatives.
    w.assign(k, 0);
    gw.assign(k * dim, 0);
    hw.assign(k * nh, 0);
    for (std::size_t m = 0; m < k; ++m) {
      const int J = nbrs[m];
      const double a = particles.dilation[J];
      double c = kernel_scale / std::pow(a, dim);
      if (options_.volume_weighted) c *= particles.volume[J];
      w[m] = c * W[m];
      if (order < 1) continue;
      const double dist = s[m] * a;
      const double* rr = &r[m * dim];
      if (dist < 1e-14 * a) {
        for (int i = 0; i < dim; ++i) hw[m * nh + i * dim + i] = c * d2W[m] / (a * a);
        continue;
      }
      for (int i = 0; i < dim; ++i) gw[m * dim + i] = c * dW[m] * rr[i] / (dist * a);
      if (order < 2) continue;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          const double ninj = rr[i] * rr[j] / (dist * dist);
          hw[m * nh + i * dim + j] =
              c * (d2W[m] * ninj / (a * a) + dW[m] / (a * dist) * ((i == j) - ninj));
        }
    }

    const int row0 = t.entries();
    t.index.insert(t.index.end(), nbrs.begin(), nbrs.end());
    t.value.resize(row0 + k);
    if (order >= 1) t.grad.resize((row0 + k) * dim);
    if (order >= 2) t.hess.resize((row0 + k) * nh);

    if (!options_.correct) {
      for (std::size_t m = 0; m < k; ++m) {
        t.value[row0 + m] = w[m];
        for (int i = 0; i < dim && order >= 1; ++i) t.grad[(row0 + m) * dim + i] = gw[m * dim + i];
        for (int i = 0; i < nh && order >= 2; ++i) t.hess[(row0 + m) * nh + i] = hw[m * nh + i];
      }
      t.offsets.push_back(t.entries());
      continue;
    }

    // Basis at the neighbours in coordinates centred on x and scaled by amax (conditioning).
    P.resize(nb, static_cast<Eigen::Index>(k));
    double xi[3];
    for (std::size_t m = 0; m < k; ++m) {
      for (int d = 0; d < dim; ++d) xi[d] = -r[m * dim + d] / amax;
      basis_at(options_.basis_order, dim, xi, P.col(static_cast<Eigen::Index>(m)).data());
    }
    M.setZero();
    for (std::size_t m = 0; m < k; ++m) M.noalias() += w[m] * P.col(m) * P.col(m).transpose();
    Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
    const double rc = ldlt.rcond();
    if (ldlt.info() != Eigen::Success || !(rc > 1e-13))
      throw SingularError(fmt::format(
          "{}: the moment matrix at {} is singular (reciprocal condition {:.2e}) with {} "
          "particles in the support; they are too few or collinear for the basis: increase the "
          "dilation or the particle count",
          name_, point_text(x, dim), rc, k));

    // p(x) and its derivatives at ξ = 0.
    Eigen::VectorXd p0 = Eigen::VectorXd::Zero(nb);
    p0[0] = 1;
    Eigen::VectorXd gamma = ldlt.solve(p0);
    std::vector<Eigen::VectorXd> pd(dim, Eigen::VectorXd::Zero(nb)), gd(dim);
    std::vector<Eigen::VectorXd> pdd(nh, Eigen::VectorXd::Zero(nb)), gdd(nh);
    if (options_.basis_order >= 1)
      for (int i = 0; i < dim; ++i) pd[i][1 + i] = 1 / amax;
    if (options_.basis_order >= 2) {
      int kk = 1 + dim;
      for (int i = 0; i < dim; ++i)
        for (int j = i; j < dim; ++j, ++kk) {
          const double v = (i == j ? 2.0 : 1.0) / (amax * amax);
          pdd[i * dim + j][kk] = v;
          pdd[j * dim + i][kk] = v;
        }
    }
    if (order >= 1) {
      for (int i = 0; i < dim; ++i) {
        if (options_.diffuse_derivative) {
          gd[i] = ldlt.solve(pd[i]);
          continue;
        }
        Md[i].setZero();
        for (std::size_t m = 0; m < k; ++m)
          Md[i].noalias() += gw[m * dim + i] * P.col(m) * P.col(m).transpose();
        gd[i] = ldlt.solve(pd[i] - Md[i] * gamma);
      }
    }
    if (order >= 2) {
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          const int ij = i * dim + j;
          if (options_.diffuse_derivative) {
            gdd[ij] = ldlt.solve(pdd[ij]);
            continue;
          }
          Mdd[ij].setZero();
          for (std::size_t m = 0; m < k; ++m)
            Mdd[ij].noalias() += hw[m * nh + ij] * P.col(m) * P.col(m).transpose();
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
          if (!options_.diffuse_derivative) v += gp * gw[m * dim + i];
          t.grad[(row0 + m) * dim + i] = v;
        }
      if (order >= 2)
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) {
            const int ij = i * dim + j;
            double v = gdd[ij].dot(pj) * w[m];
            if (!options_.diffuse_derivative)
              v += gd[i].dot(pj) * gw[m * dim + j] + gd[j].dot(pj) * gw[m * dim + i] +
                   gp * hw[m * nh + ij];
            t.hess[(row0 + m) * nh + ij] = v;
          }
    }
    t.offsets.push_back(t.entries());
  }
  return t;
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
