#include "stability/enriched_mass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "methods/approximations/enriched.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

namespace {

int columns(const Discretization& d) { return d.particles.size() + d.enriched_unknowns; }

}  // namespace

Eigen::MatrixXd enriched_stiffness(const Discretization& d, const BarMaterial& m) {
  const ShapeTable& t = d.trial_q;
  const int dim = t.dim, nc = dim, n = columns(d) * nc;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  if (dim == 2) {
    const double E = m.E, v = m.nu;
    if (m.plane_strain) {
      const double c = E / ((1 + v) * (1 - 2 * v));
      D << c * (1 - v), c * v, 0, c * v, c * (1 - v), 0, 0, 0, c * (1 - 2 * v) / 2;
    } else {
      const double c = E / (1 - v * v);
      D << c, c * v, 0, c * v, c, 0, 0, 0, c * (1 - v) / 2;
    }
  }
  for (int q = 0; q < t.points(); ++q) {
    const int a = t.offsets[q], k = t.offsets[q + 1] - a;
    const double w = d.quadrature.weights[q];
    if (dim == 1) {
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j)
          K(t.index[a + i], t.index[a + j]) += w * m.E * t.grad[a + i] * t.grad[a + j];
      continue;
    }
    // B (3 × 2k): ε = (u_x,x, u_y,y, u_x,y + u_y,x).
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3, 2 * k);
    for (int i = 0; i < k; ++i) {
      const double gx = t.grad[(a + i) * 2], gy = t.grad[(a + i) * 2 + 1];
      B(0, 2 * i) = gx;
      B(1, 2 * i + 1) = gy;
      B(2, 2 * i) = gy;
      B(2, 2 * i + 1) = gx;
    }
    const Eigen::MatrixXd Kq = w * B.transpose() * D * B;
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j)
        K.block<2, 2>(2 * t.index[a + i], 2 * t.index[a + j]) += Kq.block<2, 2>(2 * i, 2 * j);
  }
  return K;
}

Eigen::MatrixXd enriched_mass(const Discretization& d, const BarMaterial& m, MassScheme s,
                              bool mls1_per_point) {
  const ShapeTable& t = d.trial_q;
  const int dim = t.dim, nc = columns(d), N = d.particles.size();
  // One component's matrix, expanded to the interleaved components at the end.
  Eigen::MatrixXd M1 = Eigen::MatrixXd::Zero(nc, nc);
  for (int q = 0; q < t.points(); ++q) {
    const double w = m.rho * d.quadrature.weights[q];
    for (int i = t.offsets[q]; i < t.offsets[q + 1]; ++i)
      for (int j = t.offsets[q]; j < t.offsets[q + 1]; ++j)
        M1(t.index[i], t.index[j]) += w * t.value[i] * t.value[j];
  }
  Eigen::VectorXd lumped;
  switch (s) {
    case MassScheme::consistent: break;
    case MassScheme::row_sum: lumped = M1.rowwise().sum(); break;
    case MassScheme::mls1: {
      if (d.quadrature.cell.size() != static_cast<std::size_t>(d.quadrature.size()))
        throw std::logic_error("MLS1 lumping needs the integration cell of every point");
      const int cells =
          mls1_per_point ? d.quadrature.size()
                         : *std::max_element(d.quadrature.cell.begin(), d.quadrature.cell.end()) + 1;
      Eigen::MatrixXd diag = Eigen::MatrixXd::Zero(nc, cells);  // ∫_h ρ Ñ_I²
      Eigen::VectorXd mass = Eigen::VectorXd::Zero(cells);      // M_h
      for (int q = 0; q < t.points(); ++q) {
        const double w = m.rho * d.quadrature.weights[q];
        const int h = mls1_per_point ? q : d.quadrature.cell[q];
        mass[h] += w;
        for (int i = t.offsets[q]; i < t.offsets[q + 1]; ++i)
          diag(t.index[i], h) += w * t.value[i] * t.value[i];
      }
      lumped = Eigen::VectorXd::Zero(nc);
      for (int h = 0; h < cells; ++h) {
        const double sum = diag.col(h).sum();
        if (sum > 0) lumped += mass[h] / sum * diag.col(h);  // eq 16's ϑ_h
      }
      break;
    }
    case MassScheme::mls2: {
      lumped = Eigen::VectorXd::Zero(nc);
      lumped.head(N) = M1.topLeftCorner(N, N).rowwise().sum();
      if (d.enriched_unknowns > 0) {
        const auto* e = dynamic_cast<const EnrichedApproximation*>(d.trial.get());
        if (!e) throw std::logic_error("MLS2 lumping of enrichment columns needs xefg");
        const std::vector<Enrichment> enr = e->enrichments(d.particles);
        for (int c = 0; c < static_cast<int>(enr.size()); ++c) {
          const int I = enr[c].node;
          lumped[N + c] = lumped[I] * M1(N + c, N + c) / M1(I, I);
        }
      }
      break;
    }
  }
  const int n = nc * dim;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < nc; ++i)
    for (int c = 0; c < dim; ++c) {
      if (s == MassScheme::consistent) {
        for (int j = 0; j < nc; ++j) M(i * dim + c, j * dim + c) = M1(i, j);
      } else {
        M(i * dim + c, i * dim + c) = lumped[i];
      }
    }
  return M;
}

Eigen::MatrixXd enriched_mass_mls2_region(const Discretization& d, const BarMaterial& m) {
  Eigen::MatrixXd M = enriched_mass(d, m, MassScheme::mls2);
  if (d.enriched_unknowns == 0) return M;
  const auto* e = dynamic_cast<const EnrichedApproximation*>(d.trial.get());
  if (!e) throw std::logic_error("MLS2 lumping of enrichment columns needs xefg");
  const std::vector<Enrichment> enr = e->enrichments(d.particles);
  const int N = d.particles.size(), dim = d.trial_q.dim;
  // ψ of each enrichment kind at the points of a table: the enriched column's value over its
  // node's, from the entry whose node's shape function is largest there (NaN: not acting).
  const auto psi_at = [&](const ShapeTable& t, int q, EnrichmentKind kind) {
    double best = 0, psi = NAN;
    for (int i = t.offsets[q]; i < t.offsets[q + 1]; ++i) {
      const int col = t.index[i];
      if (col < N || enr[col - N].kind != kind) continue;
      for (int j = t.offsets[q]; j < t.offsets[q + 1]; ++j)
        if (t.index[j] == enr[col - N].node && std::abs(t.value[j]) > best) {
          best = std::abs(t.value[j]);
          psi = t.value[i] / t.value[j];
        }
    }
    return best > 1e-12 ? psi : NAN;
  };
  const ShapeTable at_nodes = d.trial->evaluate(d.particles, d.particles.x, 0);
  for (EnrichmentKind kind : {EnrichmentKind::step, EnrichmentKind::branch1,
                              EnrichmentKind::branch2, EnrichmentKind::branch3,
                              EnrichmentKind::branch4}) {
    double area = 0, integral = 0, nodal = 0;
    int count = 0;
    for (int q = 0; q < d.trial_q.points(); ++q) {
      const double p = psi_at(d.trial_q, q, kind);
      if (std::isnan(p)) continue;
      area += d.quadrature.weights[q];
      integral += d.quadrature.weights[q] * p * p;
    }
    for (int J = 0; J < N; ++J) {
      const double p = psi_at(at_nodes, J, kind);
      if (std::isnan(p)) continue;
      nodal += p * p;
      ++count;
    }
    if (!(area > 0) || count == 0 || !(nodal > 0)) continue;
    const double ratio = (integral / area) / (nodal / count);
    for (int c = 0; c < static_cast<int>(enr.size()); ++c) {
      if (enr[c].kind != kind) continue;
      for (int k = 0; k < dim; ++k)
        M((N + c) * dim + k, (N + c) * dim + k) =
            M(enr[c].node * dim + k, enr[c].node * dim + k) * ratio;
    }
  }
  return M;
}

double largest_eigenvalue(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, bool diagonal) {
  const double inf = std::numeric_limits<double>::infinity();
  if (diagonal) {
    const Eigen::VectorXd m = M.diagonal();
    if (!(m.minCoeff() > 0)) return inf;
    const Eigen::VectorXd s = m.cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd A = s.asDiagonal() * K * s.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A, Eigen::EigenvaluesOnly);
    return es.eigenvalues().maxCoeff();
  }
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return inf;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return inf;
  return es.eigenvalues().maxCoeff();
}

double critical_step(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, bool diagonal) {
  return 2 / std::sqrt(largest_eigenvalue(K, M, diagonal));
}

}  // namespace mfv
