/// Galerkin / least-squares-stabilized assembly of -k u'' + c u' = f in 1D (004 I eq 6.3).
#include <vector>

#include "problems/problem.hpp"

namespace mfv {

namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// The table as a (points × particles) sparse matrix of the quantity `pick(entry)`.
template <class Pick>
RowSparse table_matrix(const ShapeTable& t, int n, Pick pick) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(t.entries());
  for (int q = 0; q < t.points(); ++q)
    for (int a = t.offsets[q]; a < t.offsets[q + 1]; ++a) trip.emplace_back(q, t.index[a], pick(a));
  RowSparse m(t.points(), n);
  m.setFromTriplets(trip.begin(), trip.end());
  return m;
}

}  // namespace

AssembledSystem assemble_scalar_1d(const Discretization& d, const ScalarForm1D& form,
                                   const std::function<double(double)>& source) {
  // K = B_testᵀ W k B + N_testᵀ W c B + τ R_testᵀ W R with R = -k H + c B, as sparse products
  // of the shape tables: one product per term rather than one triplet per particle pair and
  // point, which matters for the wide wavelet windows (every pair of a 241-node line).
  const int n = d.particles.size();
  const ShapeTable& tr = d.trial_q;
  const ShapeTable& te = d.test_q;
  const bool stabilized = form.tau != 0;
  const int nq = tr.points();
  Eigen::VectorXd w(nq), fq(nq);
  for (int q = 0; q < nq; ++q) {
    w[q] = d.quadrature.weights[q];
    fq[q] = source(d.quadrature.points(0, q));
  }
  const auto W = w.asDiagonal();

  const RowSparse B = table_matrix(tr, n, [&](int a) { return tr.grad[a]; });
  const RowSparse Bt = table_matrix(te, n, [&](int a) { return te.grad[a]; });
  const RowSparse Nt = table_matrix(te, n, [&](int a) { return te.value[a]; });

  RowSparse WB = W * B;
  Eigen::SparseMatrix<double> K = Eigen::SparseMatrix<double>(Bt.transpose()) * WB * form.diffusion;
  if (form.advection != 0)
    K += Eigen::SparseMatrix<double>(Nt.transpose()) * WB * form.advection;
  Eigen::VectorXd f = Nt.transpose() * (W * fq);

  if (stabilized) {
    // Residual operator R(v) = -k v'' + c v' on trial and test functions.
    const RowSparse R = table_matrix(tr, n, [&](int a) {
      return -form.diffusion * tr.hess[a] + form.advection * tr.grad[a];
    });
    const RowSparse Rt = table_matrix(te, n, [&](int a) {
      return -form.diffusion * te.hess[a] + form.advection * te.grad[a];
    });
    const RowSparse WR = W * R;
    K += Eigen::SparseMatrix<double>(Rt.transpose()) * WR * form.tau;
    f += form.tau * (Rt.transpose() * (W * fq));
  }
  AssembledSystem s;
  s.K = K;
  s.K.makeCompressed();
  s.f = std::move(f);
  return s;
}

}  // namespace mfv
