/// Critical time step of any method on any particle set: the largest eigenvalue of
/// K φ = λ M φ, K = ∂f_int/∂u the tangent stiffness of the explicit engine's own force
/// (central differences of ExplicitDynamics::trial_force, the operator the engine steps) and
/// M the lumped or the consistent mass; central differences are stable for
/// Δt ≤ Δt_crit = 2/√λ_max.
///
/// K is built sparse: unknowns whose influence regions cannot overlap share one perturbation
/// (a greedy colouring of the particles at distance 2·reach, reach measured from the method's
/// own trial and test tables), so the cost is 2·dim·(colours) force evaluations instead of
/// 2·dim·N. Small systems are solved dense (Eigen), large ones with Spectra.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "dynamics/explicit.hpp"

namespace mfv {

enum class MassKind {
  lumped,      ///< diagonal: the particle masses of the engine (lumped_masses)
  consistent,  ///< M_IJ = Σ_q w_q ρ N^test_I(x_q) N_J(x_q) per component (Galerkin methods)
  row_sum      ///< diagonal: the row sums of the consistent mass, m_I = Σ_J M_IJ (row_sum_masses)
};
/// "lumped" / "consistent" / "row-sum", else InputError.
MassKind mass_kind_from(const std::string& name);
std::string to_string(MassKind kind);

enum class EigenSolverKind {
  automatic,  ///< dense up to `dense_limit` free unknowns, Spectra above
  dense,      ///< Eigen: GeneralizedSelfAdjointEigenSolver, or eigenvalues of M⁻¹K
  spectra     ///< Spectra: SymGEigsSolver (Cholesky) / SymEigsSolver on M^{-1/2}KM^{-1/2} /
              ///< GenEigsSolver on M⁻¹K
};

/// How the tangent stiffness was probed.
struct StiffnessProbe {
  double reach = 0;      ///< largest distance at which an unknown moves a force (rows of a column)
  double step = 0;       ///< the central-difference step (length)
  int colours = 0;       ///< perturbation groups (per component)
  int force_evaluations = 0;
};

/// The unknowns (dim·I + c, interleaved as the engine's) that are not fixed, increasing.
/// `fixed` lists fixed unknowns; the engine's own prescribed velocities are not read.
std::vector<int> free_unknowns(int unknowns, const std::vector<int>& fixed);

/// K restricted to `free` (rows and columns in that order) by central differences of
/// engine.trial_force with step `relative_step` × the mean particle spacing. `coloured`:
/// probe non-interacting unknowns together (the default); false: one column at a time (the
/// reference the colouring is tested against).
Eigen::SparseMatrix<double> tangent_stiffness(const ExplicitDynamics& engine,
                                              const std::vector<int>& free,
                                              double relative_step = 1e-6, bool coloured = true,
                                              StiffnessProbe* probe = nullptr);

/// The largest distance between an integration point and a particle of its row in table t:
/// the support radius the table really uses (the reach of stiffness columns is built from it).
double table_radius(const ShapeTable& t, const Eigen::MatrixXd& points, const Eigen::MatrixXd& X);

/// Consistent mass on `free`: per component, M_IJ = Σ_q w_q ρ N^test_I(x_q) N^trial_J(x_q)
/// from the t = 0 tables (symmetric for Galerkin methods). Throws InputError for methods
/// without shape-function values at their points (collocation: sph, rlm).
Eigen::SparseMatrix<double> consistent_mass(const Discretization& d, double density,
                                            const std::vector<int>& free);
/// Row-sum lumping of the consistent mass, one mass per particle: m_I = Σ_J M_IJ over every
/// particle J (fixed ones too) = Σ_q w_q ρ N^test_I(x_q) Σ_J N^trial_J(x_q), i.e. ρ ∫ N_I for
/// trial functions that form a partition of unity. For the GRK bar this is the lumped form of
/// 004 III eq 4.0.2's element mass ("the element matrices are simple, included a lumped mass
/// matrix", §4.0); the particle volumes ρΔV_J (lumped_masses) are the other reading. Throws
/// InputError where consistent_mass does (collocation methods).
Eigen::VectorXd row_sum_masses(const Discretization& d, double density);
/// Lumped (diagonal) mass on `free` from the particle masses (one per particle).
Eigen::SparseMatrix<double> lumped_mass(const Eigen::VectorXd& particle_mass, int dim,
                                        const std::vector<int>& free);

struct EigenOptions {
  EigenSolverKind solver = EigenSolverKind::automatic;
  int dense_limit = 1500;          ///< automatic: dense up to this many unknowns
  double symmetry_tolerance = 1e-6;  ///< max |K − Kᵀ| / max |K| below which K counts symmetric
  bool keep_spectrum = false;      ///< dense: return every eigenvalue (real parts, increasing)
};

struct GeneralizedEigen {
  double lambda_max = 0;      ///< largest real part
  double max_imaginary = 0;   ///< largest |imaginary part| (0 on the symmetric paths)
  double asymmetry = 0;       ///< max |K − Kᵀ| / max |K|
  bool symmetric = false;     ///< K symmetric to `symmetry_tolerance` and M SPD
  std::string solver;         ///< which path ran ("dense generalized self-adjoint", ...)
  std::vector<double> spectrum;  ///< keep_spectrum and dense only
};

/// λ_max of K φ = λ M φ (K, M square of the same size).
GeneralizedEigen largest_eigenvalue(const Eigen::SparseMatrix<double>& K,
                                    const Eigen::SparseMatrix<double>& M,
                                    const EigenOptions& options = {});

struct CriticalStepOptions {
  MassKind mass = MassKind::lumped;
  std::vector<int> fixed;        ///< fixed unknowns (dim·I + c), removed from K and M
  double relative_step = 1e-6;   ///< finite-difference step over the mean spacing
  EigenOptions eigen;
};

struct CriticalStep {
  double dt = 0;          ///< 2/√λ_max (0 when λ_max ≤ 0: no positive frequency)
  double lambda_max = 0;  ///< ω²_max
  int unknowns = 0;       ///< free unknowns
  GeneralizedEigen eigen;
  StiffnessProbe probe;
};

/// The critical step of central differences for the engine's current state. `particle_mass`:
/// the lumped masses the engine was given (lumped_masses); `density` the ρ of the consistent
/// and the row-sum mass (in 1D times the cross-section, as the lumped masses).
CriticalStep critical_step(const ExplicitDynamics& engine, const Eigen::VectorXd& particle_mass,
                           double density, const CriticalStepOptions& options = {});

/// 004 III §5.1 eq 5.1.3: nodes under a Gaussian window e^{−(x−s)²/r²} with r = 2^j Δx √(2/π)
/// (eq 2.5.2), n = 1 + √(−2 ln R/π)·2^{j+1}. R is the height of the window at the edge of its
/// "significant" support over its peak height, Φ(Δx_c)/Φ(0) = e^{−Δx_c²/r²}, and the support
/// spans n nodes: Δx_c = Δx (n − 1)/2 (eq 5.1.2). The paper's columns "2s" and "3s" are
/// R = e^{−4} = 1.83e-2 and R = e^{−9} = 1.23e-4: the support edge at 2r and 3r.
double gaussian_window_nodes(double j, double R);

}  // namespace mfv
