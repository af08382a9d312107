/// The direct assembly of 2D elasticity (problems/elasticity.cpp) against the sparse-product
/// reference K = B_testᵀ (W⊗D) B_trial it replaced: the same values to round-off for a
/// Galerkin, a Petrov–Galerkin, a collocation (particle-value) method and fem, a valid
/// compressed pattern (sorted, unique row indices), and the same K on any thread count.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "test_support.hpp"

namespace mfv {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// Voigt strain operator of a table (rows 3q..3q+2: ε_xx, ε_yy, γ_xy at point q), built from
/// triplets as the assembly did before it was made direct.
RowSparse strain_operator(const ShapeTable& t, int particles) {
  std::vector<Eigen::Triplet<double>> trip;
  for (int q = 0; q < t.points(); ++q)
    for (int k = t.offsets[q]; k < t.offsets[q + 1]; ++k) {
      const int J = t.index[k];
      const double gx = t.grad[2 * k], gy = t.grad[2 * k + 1];
      trip.emplace_back(3 * q, 2 * J, gx);
      trip.emplace_back(3 * q + 1, 2 * J + 1, gy);
      trip.emplace_back(3 * q + 2, 2 * J, gy);
      trip.emplace_back(3 * q + 2, 2 * J + 1, gx);
    }
  RowSparse B(3 * t.points(), 2 * particles);
  B.setFromTriplets(trip.begin(), trip.end());
  return B;
}

/// The reference: two sparse products through the block diagonal W⊗D.
Eigen::SparseMatrix<double> reference_stiffness(const Discretization& d, const Eigen::Matrix3d& D) {
  const int n = d.particles.size(), nq = d.quadrature.size();
  std::vector<Eigen::Triplet<double>> trip;
  for (int q = 0; q < nq; ++q)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (D(a, b) != 0) trip.emplace_back(3 * q + a, 3 * q + b, d.quadrature.weights[q] * D(a, b));
  RowSparse WD(3 * nq, 3 * nq);
  WD.setFromTriplets(trip.begin(), trip.end());
  const RowSparse WDB = WD * strain_operator(d.trial_q, n);
  return Eigen::SparseMatrix<double>(
      Eigen::SparseMatrix<double>(strain_operator(d.test_q, n).transpose()) * WDB);
}

/// The cantilever's material (E = 3e7, ν = 0.3, plane stress), no loads or supports: only K
/// is compared.
ElasticityBVP cantilever_material() {
  ElasticityBVP bvp;
  bvp.material.E = 3e7;
  bvp.material.nu = 0.3;
  return bvp;
}

/// Every column's row indices strictly increasing and inside the matrix, offsets consistent.
void expect_valid_compressed_pattern(const Eigen::SparseMatrix<double>& K, const std::string& what) {
  ASSERT_TRUE(K.isCompressed()) << what;
  const int* outer = K.outerIndexPtr();
  const int* inner = K.innerIndexPtr();
  EXPECT_EQ(outer[0], 0) << what;
  EXPECT_EQ(outer[K.outerSize()], K.nonZeros()) << what;
  long unsorted = 0, outside = 0;
  for (Eigen::Index j = 0; j < K.outerSize(); ++j) {
    ASSERT_LE(outer[j], outer[j + 1]) << what << " column " << j;
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      if (inner[p] < 0 || inner[p] >= K.rows()) ++outside;
      if (p > outer[j] && inner[p] <= inner[p - 1]) ++unsorted;
    }
  }
  EXPECT_EQ(unsorted, 0) << what << ": duplicate or unsorted row indices";
  EXPECT_EQ(outside, 0) << what << ": row indices outside the matrix";
}

class DirectAssembly : public ::testing::TestWithParam<std::string> {};

TEST_P(DirectAssembly, EqualsTheSparseProductToRoundOff) {
  // A perturbed lattice, so no two supports look alike; 9 across the depth: 297 particles.
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  std::string refusal;
  const auto d =
      discretize_if_supported(GetParam(), {}, p->domain(), p->particles(9, 0.2), refusal);
  ASSERT_TRUE(d) << refusal;
  if (GetParam() == "kbm-si")  // the Petrov–Galerkin case must use a test table of its own
    ASSERT_NE(d->test_q.grad, d->trial_q.grad);
  const ElasticityBVP bvp = cantilever_material();
  const Eigen::SparseMatrix<double> K = assemble_elasticity(*d, bvp).K;
  expect_valid_compressed_pattern(K, GetParam());
  const Eigen::SparseMatrix<double> R = reference_stiffness(*d, bvp.material.D());
  ASSERT_EQ(K.rows(), R.rows());
  ASSERT_EQ(K.cols(), R.cols());
  const double scale = Eigen::MatrixXd(R).cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  const double diff = Eigen::MatrixXd(K - R).cwiseAbs().maxCoeff();
  EXPECT_LE(diff / scale, 1e-12) << GetParam();
  // Every structural entry of the reference is one of K's: the patterns agree (K never drops
  // a coupling the product had).
  EXPECT_EQ(K.nonZeros(), R.nonZeros()) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Methods, DirectAssembly,
                         ::testing::Values("efg-ni", "kbm-si", "sph", "fem"),
                         [](const auto& info) { return test_name(info.param); });

TEST(DirectAssembly, SameMatrixOnOneAndTwoThreads) {
  // 33 across the depth: 4,257 particles, above the parallel threshold (methods/core/parallel.hpp).
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  const ElasticityBVP bvp = cantilever_material();
  std::string refusal;
  const auto d = discretize_if_supported("kbm-si", {}, p->domain(), p->particles(33, 0.2), refusal);
  ASSERT_TRUE(d) << refusal;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Eigen::SparseMatrix<double> K1 = assemble_elasticity(*d, bvp).K;
  omp_set_num_threads(2);
  const Eigen::SparseMatrix<double> K2 = assemble_elasticity(*d, bvp).K;
  omp_set_num_threads(threads);
  expect_valid_compressed_pattern(K2, "kbm-si, 2 threads");
  ASSERT_EQ(K1.nonZeros(), K2.nonZeros());
  const auto inner1 = std::vector<int>(K1.innerIndexPtr(), K1.innerIndexPtr() + K1.nonZeros());
  const auto inner2 = std::vector<int>(K2.innerIndexPtr(), K2.innerIndexPtr() + K2.nonZeros());
  EXPECT_EQ(inner1, inner2);
  const auto value1 = std::vector<double>(K1.valuePtr(), K1.valuePtr() + K1.nonZeros());
  const auto value2 = std::vector<double>(K2.valuePtr(), K2.valuePtr() + K2.nonZeros());
  EXPECT_EQ(value1, value2);
}

}  // namespace
}  // namespace mfv
