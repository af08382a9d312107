#include "stability/critical_step.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <Spectra/GenEigsSolver.h>
#include <Spectra/MatOp/SparseCholesky.h>
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>
#include <Spectra/SymGEigsSolver.h>
#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

using SpMat = Eigen::SparseMatrix<double>;

/// Largest distance between an integration point and a particle its table involves.
/// For every particle, the particles within `radius` (itself included), from a bucket grid of
/// cell size `radius`.
std::vector<std::vector<int>> neighbours_within(const Eigen::MatrixXd& X, double radius) {
  const int dim = static_cast<int>(X.rows()), n = static_cast<int>(X.cols());
  std::vector<std::vector<int>> out(n);
  if (n == 0) return out;
  const Eigen::VectorXd lo = X.rowwise().minCoeff();
  const double cell = std::max(radius, 1e-300);
  auto key = [&](const Eigen::VectorXd& x) {
    std::array<long, 3> k{0, 0, 0};
    for (int d = 0; d < dim; ++d) k[d] = static_cast<long>(std::floor((x[d] - lo[d]) / cell));
    return k;
  };
  std::map<std::array<long, 3>, std::vector<int>> buckets;
  for (int I = 0; I < n; ++I) buckets[key(X.col(I))].push_back(I);
  const double r2 = radius * radius * (1 + 1e-12) + 1e-300;
  for (int I = 0; I < n; ++I) {
    const std::array<long, 3> k = key(X.col(I));
    const int span[3] = {1, dim > 1 ? 1 : 0, dim > 2 ? 1 : 0};
    for (long a = -span[0]; a <= span[0]; ++a)
      for (long b = -span[1]; b <= span[1]; ++b)
        for (long c = -span[2]; c <= span[2]; ++c) {
          const auto it = buckets.find({k[0] + a, k[1] + b, k[2] + c});
          if (it == buckets.end()) continue;
          for (int J : it->second)
            if ((X.col(I) - X.col(J)).squaredNorm() <= r2) out[I].push_back(J);
        }
    std::sort(out[I].begin(), out[I].end());
  }
  return out;
}

double mean_spacing(const ParticleSet& p) {
  if (p.spacing > 0) return p.spacing;
  return std::pow(p.volume.sum() / std::max(1, p.size()), 1.0 / p.dim);
}

double max_abs(const SpMat& A) {
  double m = 0;
  for (int k = 0; k < A.outerSize(); ++k)
    for (SpMat::InnerIterator it(A, k); it; ++it) m = std::max(m, std::abs(it.value()));
  return m;
}

bool is_diagonal(const SpMat& A) {
  for (int k = 0; k < A.outerSize(); ++k)
    for (SpMat::InnerIterator it(A, k); it; ++it)
      if (it.row() != it.col() && it.value() != 0) return false;
  return true;
}

/// y = M⁻¹ K x for Spectra's general solver (M factorized once by sparse LU).
class InverseMassStiffness {
 public:
  using Scalar = double;
  InverseMassStiffness(const SpMat& K, const SpMat& M) : K_(K) {
    lu_.compute(M);
    if (lu_.info() != Eigen::Success) throw SingularError("the mass matrix is singular");
  }
  Eigen::Index rows() const { return K_.rows(); }
  Eigen::Index cols() const { return K_.cols(); }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<const Eigen::VectorXd> xv(x, K_.cols());
    Eigen::Map<Eigen::VectorXd> yv(y, K_.rows());
    yv = lu_.solve(K_ * xv);
  }

 private:
  const SpMat& K_;
  mutable Eigen::SparseLU<SpMat> lu_;
};

}  // namespace

double table_radius(const ShapeTable& t, const Eigen::MatrixXd& points, const Eigen::MatrixXd& X) {
  double r = 0;
  for (int q = 0; q < t.points(); ++q)
    for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e)
      r = std::max(r, (points.col(q) - X.col(t.index[e])).norm());
  return r;
}

MassKind mass_kind_from(const std::string& name) {
  if (name == "lumped") return MassKind::lumped;
  if (name == "consistent") return MassKind::consistent;
  if (name == "row-sum") return MassKind::row_sum;
  throw InputError(fmt::format("unknown mass '{}': use lumped, consistent or row-sum", name));
}

std::string to_string(MassKind kind) {
  switch (kind) {
    case MassKind::lumped: return "lumped";
    case MassKind::consistent: return "consistent";
    case MassKind::row_sum: return "row-sum";
  }
  return "?";
}

std::vector<int> free_unknowns(int unknowns, const std::vector<int>& fixed) {
  std::vector<char> is_fixed(unknowns, 0);
  for (int f : fixed) {
    if (f < 0 || f >= unknowns)
      throw InputError(fmt::format("fixed unknown {} is outside 0..{}", f, unknowns - 1));
    is_fixed[f] = 1;
  }
  std::vector<int> out;
  for (int i = 0; i < unknowns; ++i)
    if (!is_fixed[i]) out.push_back(i);
  return out;
}

SpMat tangent_stiffness(const ExplicitDynamics& engine, const std::vector<int>& free,
                        double relative_step, bool coloured, StiffnessProbe* probe) {
  if (!(relative_step > 0 && relative_step < 1e-2))
    throw InputError(fmt::format("finite-difference step {} must lie in (0, 1e-2)", relative_step));
  const Discretization& d = engine.discretization();
  const int dim = engine.dim(), n = engine.particles(), m = dim * n;
  const Eigen::MatrixXd& X = d.particles.x;
  std::vector<int> position(m, -1);  // unknown → row/column of the reduced K
  for (std::size_t k = 0; k < free.size(); ++k) {
    if (free[k] < 0 || free[k] >= m)
      throw InputError(fmt::format("free unknown {} is outside 0..{}", free[k], m - 1));
    position[free[k]] = static_cast<int>(k);
  }
  StiffnessProbe info;
  info.step = relative_step * mean_spacing(d.particles);
  const double eps = info.step;
  // The reach of a column: its trial functions touch points within r_trial, whose test
  // functions touch particles within r_test. A leak check below widens it if the force moves
  // further (the Eulerian kernel's retabulation reaches one more trial radius).
  const double r_trial = table_radius(d.trial_q, d.quadrature.points, X);
  const double r_test = table_radius(d.test_q, d.quadrature.points, X);
  double reach = r_trial + r_test;
  const int free_n = static_cast<int>(free.size());
  std::vector<Eigen::Triplet<double>> triplets;
  for (int attempt = 0;; ++attempt) {
    triplets.clear();
    info.force_evaluations = 0;
    // Colours of particles: any two within 2·reach differ (one colour per particle when
    // probing column by column).
    std::vector<int> colour(n, -1);
    const std::vector<std::vector<int>> near = neighbours_within(X, coloured ? 2 * reach : reach);
    int colours = 0;
    if (coloured) {
      std::vector<int> seen(n + 1, -1);
      for (int I = 0; I < n; ++I) {
        for (int J : near[I])
          if (colour[J] >= 0) seen[colour[J]] = I;
        int c = 0;
        while (seen[c] == I) ++c;
        colour[I] = c;
        colours = std::max(colours, c + 1);
      }
    } else {
      for (int I = 0; I < n; ++I) colour[I] = I;
      colours = n;
    }
    std::vector<std::vector<int>> members(colours);
    for (int I = 0; I < n; ++I) members[colour[I]].push_back(I);
    info.colours = colours;
    double leak = 0, scale = 0;
    Eigen::VectorXd du = Eigen::VectorXd::Zero(m);
    std::vector<char> assigned(n, 0);
    for (int c = 0; c < colours; ++c)
      for (int k = 0; k < dim; ++k) {
        bool any = false;
        for (int J : members[c])
          if (position[dim * J + k] >= 0) du[dim * J + k] = eps, any = true;
        if (!any) continue;
        const Eigen::VectorXd fp = engine.trial_force(du);
        const Eigen::VectorXd fm = engine.trial_force(-du);
        info.force_evaluations += 2;
        du.setZero();
        const Eigen::VectorXd df = (fp - fm) / (2 * eps);
        scale = std::max(scale, df.cwiseAbs().maxCoeff());
        std::fill(assigned.begin(), assigned.end(), 0);
        for (int J : members[c]) {
          const int col = position[dim * J + k];
          if (col < 0) continue;
          for (int I : near[J]) {
            if ((X.col(I) - X.col(J)).norm() > reach * (1 + 1e-9)) continue;
            assigned[I] = 1;
            for (int r = 0; r < dim; ++r) {
              const int row = position[dim * I + r];
              const double v = df[dim * I + r];
              if (row >= 0 && v != 0) triplets.emplace_back(row, col, v);
            }
          }
        }
        for (int I = 0; I < n; ++I)
          if (!assigned[I]) leak = std::max(leak, df.segment(dim * I, dim).cwiseAbs().maxCoeff());
      }
    if (leak <= 1e-7 * scale || attempt >= 3) {
      if (leak > 1e-7 * scale)
        throw std::logic_error(fmt::format("tangent_stiffness: the force reaches further than "
                                           "{:g} (leak {:g} of {:g})",
                                           reach, leak, scale));
      break;
    }
    reach += r_trial;  // widen and probe again
  }
  info.reach = reach;
  SpMat K(free_n, free_n);
  K.setFromTriplets(triplets.begin(), triplets.end());
  if (probe) *probe = info;
  return K;
}

SpMat consistent_mass(const Discretization& d, double density, const std::vector<int>& free) {
  const ShapeTable& trial = d.trial_q;
  const ShapeTable& test = d.test_q;
  if (d.particle_values || static_cast<int>(trial.value.size()) != trial.entries() ||
      static_cast<int>(test.value.size()) != test.entries())
    throw InputError(fmt::format("{} has no shape-function values at its integration points "
                                 "(a collocation method), so no consistent mass; use mass=lumped",
                                 d.description));
  if (!(density > 0)) throw InputError(fmt::format("density {} must be positive", density));
  const int dim = d.particles.dim, m = dim * d.particles.size();
  std::vector<int> position(m, -1);
  for (std::size_t k = 0; k < free.size(); ++k) position.at(free[k]) = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> t;
  for (int q = 0; q < trial.points(); ++q) {
    const double w = density * d.quadrature.weights[q];
    for (int a = test.offsets[q]; a < test.offsets[q + 1]; ++a)
      for (int b = trial.offsets[q]; b < trial.offsets[q + 1]; ++b) {
        const double v = w * test.value[a] * trial.value[b];
        for (int c = 0; c < dim; ++c) {
          const int row = position[dim * test.index[a] + c];
          const int col = position[dim * trial.index[b] + c];
          if (row >= 0 && col >= 0) t.emplace_back(row, col, v);
        }
      }
  }
  SpMat M(static_cast<int>(free.size()), static_cast<int>(free.size()));
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

Eigen::VectorXd row_sum_masses(const Discretization& d, double density) {
  // Every unknown free: the row sum runs over the fixed particles' columns too (a fixed
  // particle still carries the mass its neighbours share with it).
  const int dim = d.particles.dim, n = d.particles.size();
  std::vector<int> all(dim * n);
  for (int k = 0; k < dim * n; ++k) all[k] = k;
  const SpMat M = consistent_mass(d, density, all);
  Eigen::VectorXd m = Eigen::VectorXd::Zero(n);
  // Component 0's rows: the components share one scalar mass per particle.
  for (int k = 0; k < M.outerSize(); ++k)
    for (SpMat::InnerIterator it(M, k); it; ++it)
      if (it.row() % dim == 0) m[it.row() / dim] += it.value();
  return m;
}

SpMat lumped_mass(const Eigen::VectorXd& particle_mass, int dim, const std::vector<int>& free) {
  SpMat M(static_cast<int>(free.size()), static_cast<int>(free.size()));
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t k = 0; k < free.size(); ++k) {
    const int I = free[k] / dim;
    if (I >= particle_mass.size())
      throw InputError(fmt::format("unknown {} has no particle mass ({} given)", free[k],
                                   particle_mass.size()));
    if (!(particle_mass[I] > 0))
      throw InputError(fmt::format("particle {} has mass {}: masses must be positive", I,
                                   particle_mass[I]));
    t.emplace_back(static_cast<int>(k), static_cast<int>(k), particle_mass[I]);
  }
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

GeneralizedEigen largest_eigenvalue(const SpMat& K, const SpMat& M, const EigenOptions& o) {
  const int n = static_cast<int>(K.rows());
  if (K.cols() != n || M.rows() != n || M.cols() != n)
    throw InputError(fmt::format("K ({}×{}) and M ({}×{}) must be square of one size", K.rows(),
                                 K.cols(), M.rows(), M.cols()));
  GeneralizedEigen g;
  if (n == 0) return g;
  const SpMat Kt = K.transpose(), Mt = M.transpose();
  const double kmax = max_abs(K), mmax = max_abs(M);
  g.asymmetry = kmax > 0 ? max_abs(SpMat(K - Kt)) / kmax : 0;
  const double m_asym = mmax > 0 ? max_abs(SpMat(M - Mt)) / mmax : 0;
  const SpMat Ks = 0.5 * (K + Kt), Ms = 0.5 * (M + Mt);
  bool spd = false;
  if (m_asym <= 1e-12) {
    Eigen::SimplicialLLT<SpMat> llt(Ms);
    spd = llt.info() == Eigen::Success;
  }
  g.symmetric = g.asymmetry <= o.symmetry_tolerance && spd;
  const bool dense = o.solver == EigenSolverKind::dense ||
                     (o.solver == EigenSolverKind::automatic && n <= o.dense_limit) || n < 4;
  if (dense) {
    if (g.symmetric) {
      Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(
          Eigen::MatrixXd(Ks), Eigen::MatrixXd(Ms), Eigen::EigenvaluesOnly | Eigen::Ax_lBx);
      if (es.info() != Eigen::Success) throw SingularError("the dense generalized eigensolver failed");
      g.lambda_max = es.eigenvalues().maxCoeff();
      g.solver = "dense generalized self-adjoint (Eigen)";
      if (o.keep_spectrum)
        g.spectrum.assign(es.eigenvalues().data(), es.eigenvalues().data() + n);
    } else {
      Eigen::PartialPivLU<Eigen::MatrixXd> lu{Eigen::MatrixXd(M)};
      const Eigen::MatrixXd A = lu.solve(Eigen::MatrixXd(K));
      if (!A.allFinite()) throw SingularError("the mass matrix is singular");
      Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
      if (es.info() != Eigen::Success) throw SingularError("the dense eigensolver of M⁻¹K failed");
      const Eigen::VectorXcd ev = es.eigenvalues();
      g.lambda_max = ev.real().maxCoeff();
      g.max_imaginary = ev.imag().cwiseAbs().maxCoeff();
      g.solver = "dense eigenvalues of M⁻¹K (Eigen)";
      if (o.keep_spectrum) {
        const Eigen::VectorXd re = ev.real();
        g.spectrum.assign(re.data(), re.data() + n);
        std::sort(g.spectrum.begin(), g.spectrum.end());
      }
    }
    return g;
  }
  const int ncv = std::min(n, 40);
  const int maxit = 5000;
  const double tol = 1e-12;
  if (g.symmetric && is_diagonal(Ms)) {
    // Lumped mass: the symmetric standard problem D^{-1/2} K D^{-1/2}.
    const Eigen::VectorXd s = Ms.diagonal().cwiseSqrt().cwiseInverse();
    const SpMat A = s.asDiagonal() * Ks * s.asDiagonal();
    Spectra::SparseSymMatProd<double> op(A);
    Spectra::SymEigsSolver<Spectra::SparseSymMatProd<double>> eigs(op, 1, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, maxit, tol);
    if (eigs.info() != Spectra::CompInfo::Successful)
      throw SingularError("Spectra SymEigsSolver did not converge");
    g.lambda_max = eigs.eigenvalues()[0];
    g.solver = "Spectra SymEigsSolver on M^{-1/2} K M^{-1/2}";
  } else if (g.symmetric) {
    Spectra::SparseSymMatProd<double> op(Ks);
    Spectra::SparseCholesky<double> bop(Ms);
    Spectra::SymGEigsSolver<Spectra::SparseSymMatProd<double>, Spectra::SparseCholesky<double>,
                            Spectra::GEigsMode::Cholesky>
        eigs(op, bop, 1, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, maxit, tol);
    if (eigs.info() != Spectra::CompInfo::Successful)
      throw SingularError("Spectra SymGEigsSolver did not converge");
    g.lambda_max = eigs.eigenvalues()[0];
    g.solver = "Spectra SymGEigsSolver (Cholesky)";
  } else {
    InverseMassStiffness op(K, M);
    const int nev = std::min(3, n - 2);
    Spectra::GenEigsSolver<InverseMassStiffness> eigs(op, nev, std::max(ncv, nev + 2));
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestReal, maxit, tol);
    if (eigs.info() != Spectra::CompInfo::Successful)
      throw SingularError("Spectra GenEigsSolver did not converge");
    const Eigen::VectorXcd ev = eigs.eigenvalues();
    g.lambda_max = ev.real().maxCoeff();
    g.max_imaginary = ev.imag().cwiseAbs().maxCoeff();
    g.solver = "Spectra GenEigsSolver on M⁻¹K (largest real parts)";
  }
  return g;
}

CriticalStep critical_step(const ExplicitDynamics& engine, const Eigen::VectorXd& particle_mass,
                           double density, const CriticalStepOptions& o) {
  const Discretization& d = engine.discretization();
  const int dim = engine.dim();
  const std::vector<int> free = free_unknowns(dim * engine.particles(), o.fixed);
  CriticalStep out;
  out.unknowns = static_cast<int>(free.size());
  // The mass first: a consistent mass of a collocation method fails before any probing.
  const SpMat M = o.mass == MassKind::lumped    ? lumped_mass(particle_mass, dim, free)
                  : o.mass == MassKind::row_sum ? lumped_mass(row_sum_masses(d, density), dim, free)
                                                : consistent_mass(d, density, free);
  const SpMat K = tangent_stiffness(engine, free, o.relative_step, true, &out.probe);
  out.eigen = largest_eigenvalue(K, M, o.eigen);
  out.lambda_max = out.eigen.lambda_max;
  out.dt = out.lambda_max > 0 ? 2 / std::sqrt(out.lambda_max) : 0;
  return out;
}

double gaussian_window_nodes(double j, double R) {
  if (!(R > 0 && R < 1))
    throw InputError(fmt::format("the height ratio R = {} must lie in (0, 1)", R));
  return 1 + std::sqrt(-2 * std::log(R) / std::numbers::pi) * std::pow(2.0, j + 1);
}

}  // namespace mfv
