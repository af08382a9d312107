#include "dynamics/explicit.hpp"
#include "dynamics/small_matrix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <fmt/format.h>
#include <omp.h>

#include "methods/core/errors.hpp"
#include "methods/core/parallel.hpp"
#include "methods/neighbours.hpp"
#include "methods/ordering.hpp"

namespace mfv {

namespace {

constexpr int kChunk = 256;  // integration points per material call

/// Kinematics and stresses of one chunk of points [q0, q1): the deformation gradient (from u
/// in the Lagrangian frame, from the increment du and the stored F in the Eulerian one), the
/// material's P, prestress, viscosity, and the stress the force sums.
template <int D>
struct PointKernel {
  const int* offsets;
  const int* index;
  const double* grad;
  bool eulerian;
  const double* S0;  // D×D column-major or null
  double visc_alpha, visc_beta, length, wave_speed, density, dt;

  void deformation(int q, const double* u, const double* du, const double* Fc, double* F,
                   double* L) const {
    double H[D * D] = {};
    const double* src = eulerian ? du : u;
    for (int k = offsets[q]; k < offsets[q + 1]; ++k) {
      const double* uj = src + D * index[k];
      const double* g = grad + D * k;
      for (int j = 0; j < D; ++j)
        for (int i = 0; i < D; ++i) H[i + D * j] += uj[i] * g[j];
    }
    if (!eulerian) {
      for (int e = 0; e < D * D; ++e) F[e] = H[e];
      for (int i = 0; i < D; ++i) F[i + D * i] += 1;
      if (L) {  // Ḟ = Σ v ⊗ ∇₀N with v ≈ du/dt; L = Ḟ F⁻¹
        double Fd[D * D] = {};
        for (int k = offsets[q]; k < offsets[q + 1]; ++k) {
          const double* uj = du + D * index[k];
          const double* g = grad + D * k;
          for (int j = 0; j < D; ++j)
            for (int i = 0; i < D; ++i) Fd[i + D * j] += uj[i] * g[j] / dt;
        }
        double Fi[D * D];
        invert(F, Fi);
        multiply(Fd, Fi, L);
      }
      return;
    }
    // F ← (I + ΔH) F_committed, ΔH = Σ Δu_J ⊗ ∇N_J(x_q) (Table 2's L times dt).
    double A[D * D];
    for (int e = 0; e < D * D; ++e) A[e] = H[e];
    for (int i = 0; i < D; ++i) A[i + D * i] += 1;
    multiply(A, Fc + D * D * q, F);
    if (L)
      for (int e = 0; e < D * D; ++e) L[e] = H[e] / dt;
  }

  // The small dense algebra shared with the PETSc engine (dynamics/small_matrix.hpp).
  static constexpr auto multiply = &SmallMatrix<D>::multiply;
  static constexpr auto det = &SmallMatrix<D>::det;
  static constexpr auto invert = &SmallMatrix<D>::invert;

  /// P → the summed stress: P (+ F S₀ + viscosity) in the Lagrangian frame, τ = P Fᵀ in the
  /// Eulerian one (the reference weight times τ is the current weight times σ).
  void finish(const double* F, double* P, const double* L) const {
    if (S0) {
      double FS[D * D];
      multiply(F, S0, FS);
      for (int e = 0; e < D * D; ++e) P[e] += FS[e];
    }
    const double J = det(F);
    double q = 0;
    if (L && (visc_alpha > 0 || visc_beta > 0)) {
      double div = 0;
      for (int i = 0; i < D; ++i) div += L[i + D * i];
      if (div < 0)
        q = density / J * (visc_beta * length * length * div * div -
                           visc_alpha * wave_speed * length * div);
    }
    if (!eulerian) {
      if (q != 0) {  // P_v = −q J F⁻ᵀ
        double Fi[D * D];
        invert(F, Fi);
        for (int j = 0; j < D; ++j)
          for (int i = 0; i < D; ++i) P[i + D * j] -= q * J * Fi[j + D * i];
      }
      return;
    }
    double tau[D * D];
    for (int j = 0; j < D; ++j)
      for (int i = 0; i < D; ++i) {
        double s = 0;
        for (int k = 0; k < D; ++k) s += P[i + D * k] * F[j + D * k];
        tau[i + D * j] = s;
      }
    for (int i = 0; i < D; ++i) tau[i + D * i] -= q * J;
    for (int e = 0; e < D * D; ++e) P[e] = tau[e];
  }
};

template <int D>
void compute_points(const PointKernel<D>& k, const Material& material, int nq, const double* u,
                    const double* du, const double* Fc, double* F, double* stress, double* state,
                    int state_size, bool viscosity, int threads) {
  const int chunks = (nq + kChunk - 1) / kChunk;
#pragma omp parallel for schedule(static) num_threads(threads) if (nq > kParallelMinimum)
  for (int c = 0; c < chunks; ++c) {
    const int q0 = c * kChunk, q1 = std::min(nq, q0 + kChunk);
    double Lbuf[kChunk * D * D];
    for (int q = q0; q < q1; ++q)
      k.deformation(q, u, du, Fc, F + D * D * q, viscosity ? Lbuf + D * D * (q - q0) : nullptr);
    // k.dt is 0 in trial evaluations: a rate-dependent material then responds elastically.
    material.first_piola(D, q1 - q0, F + D * D * q0, stress + D * D * q0,
                         state ? state + static_cast<long>(state_size) * q0 : nullptr, k.dt);
    for (int q = q0; q < q1; ++q)
      k.finish(F + D * D * q, stress + D * D * q, viscosity ? Lbuf + D * D * (q - q0) : nullptr);
  }
}

/// gather_forces' sums from the point-major table (row q: the particles J with w0_q ∇N_J(x_q)),
/// serially: particle I receives its terms by ascending q, each w0_q g computed and summed as
/// the gather does from its particle-major copy, so the forces agree bit for bit.
template <int D>
void scatter_forces(int nq, int n, const int* offsets, const int* index, const double* grad,
                    const double* w0, const double* stress, double* f) {
  std::fill(f, f + static_cast<std::ptrdiff_t>(D) * n, 0.0);
  for (int q = 0; q < nq; ++q) {
    const double* S = stress + D * D * q;
    const double w = w0[q];
    for (int e = offsets[q]; e < offsets[q + 1]; ++e) {
      double g[D];
      for (int c = 0; c < D; ++c) g[c] = w * grad[D * e + c];
      double* fi = f + D * index[e];
      for (int j = 0; j < D; ++j)
        for (int i = 0; i < D; ++i) fi[i] += S[i + D * j] * g[j];
    }
  }
}

template <int D>
void gather_forces(int n, const int* offsets, const int* point, const double* grad,
                   const double* stress, double* f, int threads) {
#pragma omp parallel for schedule(static) num_threads(threads) if (n > kParallelMinimum)
  for (int I = 0; I < n; ++I) {
    double fi[D] = {};
    for (int e = offsets[I]; e < offsets[I + 1]; ++e) {
      const double* S = stress + D * D * point[e];
      const double* g = grad + D * e;
      for (int j = 0; j < D; ++j)
        for (int i = 0; i < D; ++i) fi[i] += S[i + D * j] * g[j];
    }
    for (int i = 0; i < D; ++i) f[D * I + i] = fi[i];
  }
}

/// Solves N c = v for the nodal values c of each component, N_IJ = N_J(X_I) the table of
/// trial values at the particles (row I = particle I), so that Σ_J N_J(X_I) c_J = v_I.
/// The table is the matrix already (row-compressed), so it is mapped, not copied. BiCGSTAB
/// with a diagonal (Jacobi) preconditioner first: N is close to its diagonal (a particle's
/// own shape function dominates at its position), so it converges in a few tens of
/// iterations, each one sparse product, O(N) in all, where an incomplete LU's factorization
/// grows faster than N (66-123 s at 10^6 particles, bench/README.md). When Jacobi does not
/// reach the tolerance (an irregular set whose N is far from diagonal), IncompleteLUT, the
/// robust fallback; when neither does, SingularError with both causes.
void fit_nodal_values(const ShapeTable& t, int n, int dim, const Eigen::MatrixXd& v,
                      Eigen::VectorXd& out) {
  using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  const Eigen::Map<const RowMatrix> A(n, n, t.entries(), t.offsets.data(), t.index.data(),
                                      t.value.data());
  constexpr double kTolerance = 1e-12;  // relative residual |N c − v| / |v|
  Eigen::BiCGSTAB<RowMatrix, Eigen::DiagonalPreconditioner<double>> jacobi;
  jacobi.setTolerance(kTolerance);
  // A bound on the work before the fallback: a well-conditioned N converges in far fewer.
  jacobi.setMaxIterations(500);
  jacobi.compute(A);
  std::unique_ptr<Eigen::BiCGSTAB<RowMatrix, Eigen::IncompleteLUT<double>>> ilut;
  Eigen::VectorXd rhs(n), x(n);
  for (int c = 0; c < dim; ++c) {
    rhs = v.row(c).transpose();
    if (rhs.norm() == 0) {
      for (int I = 0; I < n; ++I) out[dim * I + c] = 0;
      continue;
    }
    x = jacobi.solve(rhs);
    std::string cause;
    if (jacobi.info() != Eigen::Success || !x.allFinite()) {
      cause = fmt::format("Jacobi-preconditioned BiCGSTAB stopped after {} iterations at a "
                          "relative residual of {:.3g}",
                          jacobi.iterations(), jacobi.error());
      if (!ilut) {
        ilut = std::make_unique<Eigen::BiCGSTAB<RowMatrix, Eigen::IncompleteLUT<double>>>();
        ilut->setTolerance(kTolerance);
        ilut->compute(A);
      }
      x = ilut->solve(rhs);
      if (ilut->info() != Eigen::Success || !x.allFinite())
        throw SingularError(fmt::format(
            "could not fit nodal velocities to the particle velocities (component {}): the "
            "shape-function values at the particles are singular or ill-conditioned ({}; "
            "with an incomplete-LU preconditioner, {} iterations at {:.3g})",
            c, cause, ilut->iterations(), ilut->error()));
    }
    for (int I = 0; I < n; ++I) out[dim * I + c] = x[I];
  }
}
}  // namespace

Eigen::VectorXd lumped_masses(const ParticleSet& particles, double density, MassLumping lumping) {
  if (lumping == MassLumping::volume) return density * particles.volume;
  return Eigen::VectorXd::Constant(particles.size(),
                                   density * particles.volume.sum() / particles.size());
}

KernelFrame kernel_frame_from(const std::string& name) {
  if (name == "lagrangian") return KernelFrame::lagrangian;
  if (name == "eulerian") return KernelFrame::eulerian;
  throw InputError(fmt::format("unknown kernel frame '{}'; valid: lagrangian, eulerian", name));
}

SupportRule support_rule_from(const std::string& name) {
  if (name == "fixed") return SupportRule::fixed;
  if (name == "adaptive") return SupportRule::adaptive;
  if (name == "stretch") return SupportRule::stretch;
  throw InputError(fmt::format("unknown support rule '{}'; valid: fixed (the t = 0 radii), "
                               "adaptive (radii scaled by J^(1/d)), stretch (by the largest "
                               "principal stretch); the last two for Eulerian kernels",
                               name));
}

ForceForm force_form_from(const std::string& name) {
  if (name == "test") return ForceForm::test_functions;
  if (name == "variational") return ForceForm::variational;
  throw InputError(fmt::format("unknown internal force form '{}'; valid: test (the method's test "
                               "functions), variational (the transpose of the trial gradient)",
                               name));
}

ParticleOrder particle_order_from(const std::string& name) {
  if (name == "none") return ParticleOrder::as_given;
  if (name == "hilbert") return ParticleOrder::hilbert;
  throw InputError(fmt::format("unknown particle order '{}'; valid: none (the discretization's), "
                               "hilbert (renumbered along the Hilbert curve inside the engine)",
                               name));
}

WallTraction wall_traction_from(const std::string& name) {
  if (name == "off") return WallTraction::off;
  if (name == "weak") return WallTraction::weak;
  throw InputError(fmt::format("unknown wall traction '{}'; valid: off (the problem's particle "
                               "forces only), weak (the walls' boundary term of the weak form)",
                               name));
}

VolumeAverage volume_average_from(const std::string& name) {
  if (name == "off") return VolumeAverage::off;
  if (name == "patch") return VolumeAverage::patch;
  throw InputError(fmt::format("unknown volume average '{}'; valid: off (each point's own "
                               "det F), patch (F-bar over the particles' patches)",
                               name));
}

KernelCentres kernel_centres_from(const std::string& name) {
  if (name == "coefficients") return KernelCentres::coefficients;
  if (name == "interpolated") return KernelCentres::interpolated;
  throw InputError(fmt::format("unknown kernel centres '{}'; valid: coefficients (the particles' "
                               "unknowns), interpolated (the trial field at the particles)",
                               name));
}

TimeIntegrator time_integrator_from(const std::string& name) {
  if (name == "verlet") return TimeIntegrator::verlet;
  if (name == "newmark") return TimeIntegrator::newmark;
  throw InputError(fmt::format("unknown time integrator '{}'; valid: verlet, newmark", name));
}

ExplicitDynamics::ExplicitDynamics(const Method& method, Discretization d, DynamicsModel model,
                                   DynamicsOptions options)
    : method_(method), d_(std::move(d)), model_(std::move(model)), opt_(options) {
  dim_ = d_.particles.dim;
  n_ = d_.particles.size();
  nq_ = d_.quadrature.size();
  if (dim_ != 1 && dim_ != 2)
    throw InputError(fmt::format("explicit dynamics supports 1D and 2D, not {}D", dim_));
  if (!model_.material) throw InputError("explicit dynamics needs a material");
  if (model_.mass.size() != n_ || (model_.mass.array() <= 0).any())
    throw InputError(fmt::format("explicit dynamics needs a positive lumped mass for each of the "
                                 "{} particles (got {} values); use lumped_masses",
                                 n_, model_.mass.size()));
  if (model_.initial_stress.size() != 0 &&
      (model_.initial_stress.rows() != dim_ || model_.initial_stress.cols() != dim_))
    throw InputError(fmt::format("initial stress must be {0}×{0}", dim_));
  if (opt_.update_every < 1)
    throw InputError(fmt::format("update_every = {} must be at least 1", opt_.update_every));
  if (opt_.newmark_gamma < 0.5)
    throw InputError(fmt::format("Newmark gamma = {} below 1/2 is unstable; use 0.5 or more",
                                 opt_.newmark_gamma));
  if (opt_.threads <= 0) opt_.threads = omp_get_max_threads();
  // A skin of many spacings lists nearly every particle for every point (quadratic memory).
  if (!(opt_.neighbour_skin >= 0 && opt_.neighbour_skin <= 10))
    throw InputError(fmt::format("neighbour skin = {} (over the spacing) must be a number in "
                                 "[0, 10]; 0.3 is the default, 0 searches afresh at every "
                                 "recomputation",
                                 opt_.neighbour_skin));
  spacing_ = d_.particles.spacing;
  retabulation_ = Retabulation(opt_.neighbour_skin * spacing_, opt_.threads);
  retabulation_.degenerate_fallback = model_.degenerate_fallback;
  wave_speed_ = model_.material->wave_speed(dim_, model_.density);
  const int m = dim_ * n_;
  u_ = v_ = a_ = f_int_ = f_ext_ = Eigen::VectorXd::Zero(m);
  inv_mass_.resize(m);
  for (int I = 0; I < n_; ++I)
    for (int c = 0; c < dim_; ++c) inv_mass_[dim_ * I + c] = 1 / model_.mass[I];
  for (const PrescribedVelocity& p : model_.prescribed) {
    if (p.particle < 0 || p.particle >= n_ || p.component < 0 || p.component >= dim_)
      throw InputError(fmt::format("prescribed velocity of particle {} component {} is outside "
                                   "the {} particles × {} components",
                                   p.particle, p.component, n_, dim_));
  }
  for (const FollowerPressure& fp : model_.follower_pressures) {
    if (dim_ != 2)
      throw InputError(fmt::format("a follower pressure needs a 2D model, this one is {}D", dim_));
    if (fp.loop.size() < 3 || !fp.pressure)
      throw InputError(fmt::format("a follower pressure needs a closed loop of at least 3 "
                                   "particles and a pressure law (got {} particles{})",
                                   fp.loop.size(), fp.pressure ? "" : ", no law"));
    for (int I : fp.loop)
      if (I < 0 || I >= n_)
        throw InputError(fmt::format("follower pressure particle {} is outside the {} particles",
                                     I, n_));
  }
  X_ = d_.particles.x;
  Xq_ = d_.quadrature.points;
  V0_ = d_.particles.volume;
  w0_ = d_.quadrature.weights;
  if (!d_.particle_values) {
    // d_.trial_at(X_, 0) bit for bit (Approximation::evaluate_into), on the engine's threads.
    NeighbourLists lists(0);
    d_.trial->evaluate_into(d_.particles, X_, 0, lists, opt_.threads, values_at_particles_);
  }
  if (opt_.frame == KernelFrame::eulerian) values_at_points0_ = d_.trial_q;
  dilation0_ = d_.particles.dilation;
  if (opt_.support != SupportRule::fixed) {
    if (opt_.frame != KernelFrame::eulerian)
      throw InputError("support=adaptive|stretch scales the supports of an Eulerian kernel; the "
                       "Lagrangian kernel's supports move with the material already (use "
                       "frame=eulerian, or support=fixed)");
    if (d_.quadrature.nodal_points < n_ &&
        static_cast<int>(values_at_points0_.value.size()) != values_at_points0_.entries())
      throw InputError("support=adaptive|stretch needs F at the particles: this method has neither "
                       "nodal points nor trial values at its integration points; use "
                       "support=fixed");
  }
  if (opt_.volume_average != VolumeAverage::off) {
    if (opt_.order != ParticleOrder::as_given)
      throw InputError("volume_average=patch needs the given particle order (reorder=none)");
    if (volume_table().value.size() != static_cast<std::size_t>(volume_table().entries()))
      throw InputError("volume_average=patch needs the values of the method's test or trial "
                       "functions at the points, which this method does not tabulate");
  }
  if (opt_.order == ParticleOrder::hilbert) {
    if (opt_.frame != KernelFrame::lagrangian)
      throw InputError("the Hilbert particle order (reorder=hilbert) is for the Lagrangian "
                       "kernel, whose tables are built once; use reorder=none with "
                       "frame=eulerian");
    renumber_along_hilbert_curve();
  }
  for (int q : model_.tensionless_points)
    if (q < 0 || q >= nq_)
      throw InputError(fmt::format("tensionless point {} is outside the {} integration points",
                                   q, nq_));
  if (!model_.tensionless_points.empty() && opt_.order != ParticleOrder::as_given)
    throw InputError("tensionless points (wall particles) need the given particle order "
                     "(reorder=none)");
  if (opt_.wall_traction == WallTraction::weak) {
    const char* why = model_.rigid_walls.empty() || !model_.wall_forces
                          ? "this problem has no rigid walls"
                      : dim_ != 2                ? "it is written for 2D models"
                      : d_.enriched_unknowns > 0 ? "enrichment unknowns have no wall term"
                      : opt_.order != ParticleOrder::as_given
                          ? "it needs the given particle order (reorder=none)"
                          : nullptr;
    if (why)
      throw InputError(fmt::format("wall_traction=weak is not available here: {}; use "
                                   "wall_traction=off",
                                   why));
  }
  if (opt_.remedies.any()) check_fluid_remedies();
  const int dd = dim_ * dim_;
  F_.assign(static_cast<std::size_t>(dd) * nq_, 0.0);
  for (int q = 0; q < nq_; ++q)
    for (int i = 0; i < dim_; ++i) F_[dd * q + i * (dim_ + 1)] = 1;
  committed_F_ = F_;
  stress_.assign(F_.size(), 0.0);
  scratch_F_.assign(F_.size(), 0.0);
  const int ns = model_.material->state_size(dim_);
  state_.assign(static_cast<std::size_t>(ns) * nq_, 0.0);
  model_.material->initial_state(dim_, nq_, state_.data());
  if (model_.initial_state && ns > 0) {
    if (renumbered_) {  // the callback gets the points in the engine's order
      Eigen::MatrixXd xq(dim_, nq_);
      for (int q = 0; q < nq_; ++q) xq.col(q) = Xq_.col(point_given_[q]);
      model_.initial_state(xq, ns, state_.data());
    } else {
      model_.initial_state(Xq_, ns, state_.data());
    }
  }
  // The gather runs serially (one thread, or too few particles to split): in the Eulerian
  // frame, whose tables change at every recomputation, the forces are scattered from the
  // point table instead of transposing it each time (a fifth of SPH's every-step cost).
  scatter_forces_ = opt_.frame == KernelFrame::eulerian && !renumbered_ &&
                    (opt_.threads <= 1 || n_ <= kParallelMinimum);
  build_force_tables();
  apply_prescribed(0, v_, a_);
  internal_force(u_, Eigen::VectorXd::Zero(m), 0, true, f_int_);
  external_force(0, f_ext_);
  a_ = ((f_ext_ - f_int_).array() * inv_mass_.array()).matrix();
  apply_prescribed(0, v_, a_);
  energy_.initial = energy_.kinetic = kinetic_energy();
}

void ExplicitDynamics::build_force_tables() {
  const ShapeTable& t = force_table();
  const Eigen::VectorXd& w0 = renumbered_ ? w0_r_ : w0_;
  if (t.points() != nq_ || static_cast<int>(t.grad.size()) != t.entries() * dim_)
    throw std::logic_error("explicit dynamics needs first derivatives of the functions the "
                           "internal force sums");
  if (scatter_forces_) return;
  // A counting sort of the entries by particle, the points split into one contiguous chunk
  // per thread: thread k's entries of particle I go after those of threads < k, so every
  // particle lists its points in ascending order, as the serial sort does.
  const int threads = nq_ > kParallelMinimum ? opt_.threads : 1;
  const std::size_t stride = static_cast<std::size_t>(n_) + 1;
  tt_next_.assign(threads * stride, 0);
  auto chunk = [&](int k, int& q0, int& q1) {
    q0 = static_cast<int>(static_cast<long>(nq_) * k / threads);
    q1 = static_cast<int>(static_cast<long>(nq_) * (k + 1) / threads);
  };
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    int q0, q1;
    chunk(omp_get_thread_num(), q0, q1);
    int* count = tt_next_.data() + omp_get_thread_num() * stride;
    for (int e = t.offsets[q0]; e < t.offsets[q1]; ++e) ++count[t.index[e]];
  }
  tt_offsets_.resize(n_ + 1);
  int base = 0;
  for (int I = 0; I < n_; ++I) {
    tt_offsets_[I] = base;
    for (int k = 0; k < threads; ++k) {
      int& slot = tt_next_[k * stride + I];
      const int c = slot;
      slot = base;  // the count becomes thread k's first slot for particle I
      base += c;
    }
  }
  tt_offsets_[n_] = base;
  tt_point_.resize(t.entries());
  tt_grad_.resize(static_cast<std::size_t>(t.entries()) * dim_);
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    int q0, q1;
    chunk(omp_get_thread_num(), q0, q1);
    int* next = tt_next_.data() + omp_get_thread_num() * stride;
    for (int q = q0; q < q1; ++q)
      for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e) {
        const int slot = next[t.index[e]]++;
        tt_point_[slot] = q;
        for (int c = 0; c < dim_; ++c) tt_grad_[dim_ * slot + c] = w0[q] * t.grad[dim_ * e + c];
      }
  }
}

const ShapeTable& ExplicitDynamics::trial_table() const {
  return renumbered_ ? trial_r_ : d_.trial_q;
}

const ShapeTable& ExplicitDynamics::force_table() const {
  if (renumbered_) return force_is_trial_ ? trial_r_ : force_r_;
  return opt_.force == ForceForm::variational ? d_.trial_q : d_.test_q;
}

void ExplicitDynamics::renumber_along_hilbert_curve() {
  const Renumbering r = hilbert_renumbering(d_);
  const std::vector<int> particle_new = r.particle_new();
  // Copies of what the force loops read (index and gradients); the discretization keeps its
  // own order for everything outside the engine.
  auto copy = [&](const ShapeTable& t) {
    ShapeTable c;
    c.dim = t.dim;
    c.order = 1;
    c.offsets.resize(nq_ + 1);
    c.offsets[0] = 0;
    for (int q = 0; q < nq_; ++q) {
      const int g = r.point_old[q];
      c.offsets[q + 1] = c.offsets[q] + t.offsets[g + 1] - t.offsets[g];
    }
    c.index.resize(t.entries());
    c.grad.resize(t.grad.size());
    for (int q = 0; q < nq_; ++q) {
      const int g = r.point_old[q];
      int k = c.offsets[q];
      for (int e = t.offsets[g]; e < t.offsets[g + 1]; ++e, ++k) {
        c.index[k] = particle_new[t.index[e]];
        for (int i = 0; i < dim_; ++i) c.grad[dim_ * k + i] = t.grad[dim_ * e + i];
      }
    }
    return c;
  };
  const ShapeTable& force = opt_.force == ForceForm::variational ? d_.trial_q : d_.test_q;
  if (force.points() != nq_ || static_cast<int>(force.grad.size()) != force.entries() * dim_ ||
      static_cast<int>(d_.trial_q.grad.size()) != d_.trial_q.entries() * dim_)
    throw std::logic_error("explicit dynamics needs first derivatives of the functions the "
                           "internal force sums");
  force_is_trial_ = &force == &d_.trial_q || (force.offsets == d_.trial_q.offsets &&
                                              force.index == d_.trial_q.index &&
                                              force.grad == d_.trial_q.grad);
  trial_r_ = copy(d_.trial_q);
  if (!force_is_trial_) force_r_ = copy(force);
  w0_r_.resize(nq_);
  for (int q = 0; q < nq_; ++q) w0_r_[q] = w0_[r.point_old[q]];
  particle_given_ = r.particle_old;
  point_given_ = r.point_old;
  u_r_.resize(dim_ * n_);
  du_r_.resize(dim_ * n_);
  f_r_.resize(dim_ * n_);
  renumbered_ = true;
}

Eigen::MatrixXd ExplicitDynamics::points_to_given(Eigen::MatrixXd by_engine) const {
  if (!renumbered_) return by_engine;
  Eigen::MatrixXd out(by_engine.rows(), by_engine.cols());
  for (int q = 0; q < nq_; ++q) out.col(point_given_[q]) = by_engine.col(q);
  return out;
}

void ExplicitDynamics::internal_force(const Eigen::VectorXd& u, const Eigen::VectorXd& du,
                                      double dt, bool commit, Eigen::VectorXd& f) const {
  const bool eulerian = opt_.frame == KernelFrame::eulerian;
  const bool viscosity = opt_.viscosity.enabled() && dt > 0;
  double* F = commit ? F_.data() : scratch_F_.data();
  // A trial evaluation must not move the material's history: it works on a copy.
  std::vector<double> trial_state;
  double* state = nullptr;
  if (!state_.empty()) {
    if (commit) {
      state = state_.data();
    } else {
      trial_state = state_;
      state = trial_state.data();
    }
  }
  f.resize(dim_ * n_);
  if (renumbered_) {
    // Into the engine's order and back: two passes over the unknowns against the tables'
    // twenty-odd entries per point.
    // The Lagrangian kernel reads du only for the viscosity's rate (the Eulerian frame, which
    // needs it always, is refused with this order).
    for (int k = 0; k < n_; ++k)
      for (int c = 0; c < dim_; ++c) u_r_[dim_ * k + c] = u[dim_ * particle_given_[k] + c];
    if (viscosity || eulerian)
      for (int k = 0; k < n_; ++k)
        for (int c = 0; c < dim_; ++c) du_r_[dim_ * k + c] = du[dim_ * particle_given_[k] + c];
    if (dim_ == 1)
      forces<1>(u_r_, du_r_, dt, eulerian, viscosity, F, state, f_r_);
    else
      forces<2>(u_r_, du_r_, dt, eulerian, viscosity, F, state, f_r_);
    for (int k = 0; k < n_; ++k)
      for (int c = 0; c < dim_; ++c) f[dim_ * particle_given_[k] + c] = f_r_[dim_ * k + c];
    return;
  }
  if (dim_ == 1)
    forces<1>(u, du, dt, eulerian, viscosity, F, state, f);
  else
    forces<2>(u, du, dt, eulerian, viscosity, F, state, f);
}

template <int D>
void ExplicitDynamics::forces(const Eigen::VectorXd& u, const Eigen::VectorXd& du, double dt,
                              bool eulerian, bool viscosity, double* F, double* state,
                              Eigen::VectorXd& f) const {
  const ShapeTable& t = trial_table();
  const double* S0 = model_.initial_stress.size() ? model_.initial_stress.data() : nullptr;
  PointKernel<D> k{t.offsets.data(), t.index.data(), t.grad.data(), eulerian, S0,
                   opt_.viscosity.alpha, opt_.viscosity.beta, spacing_, wave_speed_,
                   model_.density, dt};
  if (opt_.volume_average == VolumeAverage::patch) {
    // Two passes: every point's F first (the patches need all of them), then F̄ and the
    // material.
    constexpr int DD = D * D;
    std::vector<double> L(viscosity ? static_cast<std::size_t>(DD) * nq_ : 0);
    const double* Fc = committed_F_.data();
#pragma omp parallel for schedule(static) num_threads(opt_.threads) if (nq_ > kParallelMinimum)
    for (int q = 0; q < nq_; ++q)
      k.deformation(q, u.data(), du.data(), Fc, F + DD * q, viscosity ? L.data() + DD * q : nullptr);
    double* Fs = F;  // F̄: committed in the Eulerian frame (see VolumeAverage::patch)
    average_volumes(Fs);
    const int ns = model_.material->state_size(dim_);
    const int chunks = (nq_ + kChunk - 1) / kChunk;
#pragma omp parallel for schedule(static) num_threads(opt_.threads) if (nq_ > kParallelMinimum)
    for (int c = 0; c < chunks; ++c) {
      const int q0 = c * kChunk, q1 = std::min(nq_, q0 + kChunk);
      model_.material->first_piola(D, q1 - q0, Fs + DD * q0, stress_.data() + DD * q0,
                                   state ? state + static_cast<long>(ns) * q0 : nullptr, k.dt);
      for (int q = q0; q < q1; ++q)
        k.finish(Fs + DD * q, stress_.data() + DD * q, viscosity ? L.data() + DD * q : nullptr);
    }
    release_tension();
    sum_forces<D>(f);
    return;
  }
  compute_points<D>(k, *model_.material, nq_, u.data(), du.data(), committed_F_.data(), F,
                    stress_.data(), state, model_.material->state_size(dim_), viscosity,
                    opt_.threads);
  release_tension();
  sum_forces<D>(f);
}

template <int D>
void ExplicitDynamics::sum_forces(Eigen::VectorXd& f) const {
  if (scatter_forces_) {
    const ShapeTable& t = force_table();
    scatter_forces<D>(nq_, n_, t.offsets.data(), t.index.data(), t.grad.data(), w0_.data(),
                      stress_.data(), f.data());
    return;
  }
  gather_forces<D>(n_, tt_offsets_.data(), tt_point_.data(), tt_grad_.data(), stress_.data(),
                   f.data(), opt_.threads);
}

void ExplicitDynamics::release_tension() const {
  // The stress the force sums (P, or τ = J σ in the Eulerian frame): its trace has σ's sign
  // (J > 0; P Fᵀ = J σ), so dropping the isotropic part of a pulling one leaves no tension.
  const int dd = dim_ * dim_;
  for (int q : model_.tensionless_points) {
    double* S = stress_.data() + dd * q;
    if (opt_.frame == KernelFrame::eulerian) {
      double trace = 0;
      for (int i = 0; i < dim_; ++i) trace += S[i * (dim_ + 1)];
      if (!(trace > 0)) continue;
      for (int i = 0; i < dim_; ++i) S[i * (dim_ + 1)] -= trace / dim_;
    } else {
      // P = J σ F⁻ᵀ: remove J (tr σ / D) F⁻ᵀ, J tr σ = tr(P Fᵀ).
      Eigen::Map<Eigen::MatrixXd> P(S, dim_, dim_);
      const Eigen::Map<const Eigen::MatrixXd> F(F_.data() + dd * q, dim_, dim_);
      const double j_trace = (P * F.transpose()).trace();
      if (!(j_trace > 0)) continue;
      P -= (j_trace / dim_) * F.inverse().transpose();
    }
  }
}

const ShapeTable& ExplicitDynamics::volume_table() const {
  const ShapeTable& test = d_.test_q;
  if (test.points() == nq_ && test.value.size() == static_cast<std::size_t>(test.entries()) &&
      test.entries() > 0)
    return test;
  return d_.trial_q;
}

void ExplicitDynamics::average_volumes(double* F) const {
  // VolumeAverage::patch (dynamics/explicit.hpp): Ĵ_I the patch's current over reference
  // volume, J̄_q its interpolation back to the point, F̄ = (J̄/J)^{1/D} F.
  const ShapeTable& t = volume_table();
  const int dd = dim_ * dim_;
  auto det = [&](const double* A) { return dim_ == 1 ? A[0] : A[0] * A[3] - A[1] * A[2]; };
  std::vector<double> num(n_, 0.0), den(n_, 0.0);
  for (int q = 0; q < nq_; ++q) {
    const double J = det(F + dd * q), w = w0_[q];
    for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e) {
      num[t.index[e]] += w * J * t.value[e];
      den[t.index[e]] += w * t.value[e];
    }
  }
#pragma omp parallel for schedule(static) num_threads(opt_.threads) if (nq_ > kParallelMinimum)
  for (int q = 0; q < nq_; ++q) {
    double s = 0, sw = 0;
    for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e) {
      const int I = t.index[e];
      if (!(den[I] > 0)) continue;
      s += t.value[e] * num[I] / den[I];
      sw += t.value[e];
    }
    double* Fq = F + dd * q;
    const double J = det(Fq);
    // A point with no patch, or an inverted one, keeps its own F (the watch sees it).
    if (!(sw > 0) || !(J > 0) || !(s / sw > 0)) continue;
    const double scale = std::pow(s / sw / J, 1.0 / dim_);
    for (int e = 0; e < dd; ++e) Fq[e] *= scale;
  }
}

namespace {
/// out[c] += Σ_J N_J(X_I) u_J[c]: the field of the unknowns u at particle I from the table of
/// values at the particles (methods whose unknowns are not the particle values).
void add_field_at(const ShapeTable& t, int dim, const Eigen::VectorXd& u, int I, double* out) {
  for (int e = t.offsets[I]; e < t.offsets[I + 1]; ++e)
    for (int c = 0; c < dim; ++c) out[c] += t.value[e] * u[dim * t.index[e] + c];
}
}  // namespace

void ExplicitDynamics::external_force(double t, Eigen::VectorXd& f) const {
  f.setZero(dim_ * n_);
  if (model_.external_force) model_.external_force(t, f);
  if (model_.particle_forces || model_.wall_forces) {
    Eigen::MatrixXd& fp = particle_force_;
    fp.setZero(dim_, n_);
    const Eigen::MatrixXd x = particle_positions();
    if (model_.particle_forces) model_.particle_forces(t, x, fp);
    if (model_.wall_forces) {
      // Particle-value methods: the test functions are δ at the particles, so the boundary
      // term's nodal rule is the force at the particle itself (WallTraction::off's sums).
      if (opt_.wall_traction == WallTraction::weak && !d_.particle_values) {
        Eigen::MatrixXd& fw = wall_force_;
        fw.setZero(dim_, n_);
        model_.wall_forces(t, x, fw);
        add_wall_tractions(x, fw, f);
      } else {
        model_.wall_forces(t, x, fp);
      }
    }
    if (d_.particle_values) {
      f += Eigen::Map<const Eigen::VectorXd>(fp.data(), fp.size());
    } else {
      const ShapeTable& tv = values_at_particles_;
      for (int I = 0; I < n_; ++I)
        for (int e = tv.offsets[I]; e < tv.offsets[I + 1]; ++e)
          for (int c = 0; c < dim_; ++c) f[dim_ * tv.index[e] + c] += tv.value[e] * fp(c, I);
    }
  }
  for (const FollowerPressure& fp : model_.follower_pressures) {
    const double p = fp.pressure(t);
    if (p == 0) continue;
    const Eigen::MatrixXd x = positions_of(fp.loop);
    const int m = static_cast<int>(fp.loop.size());
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector2d d = x.col((k + 1) % m) - x.col((k + m - 1) % m);
      add_force_at_particle(fp.loop[k], 0.5 * p * Eigen::Vector2d(d.y(), -d.x()), f);
    }
  }
}

void ExplicitDynamics::add_force_at_particle(int K, const Eigen::Vector2d& force,
                                             Eigen::VectorXd& f) const {
  if (d_.particle_values) {
    f.segment<2>(2 * K) += force;
    return;
  }
  const ShapeTable& tv = values_at_particles_;
  for (int e = tv.offsets[K]; e < tv.offsets[K + 1]; ++e)
    f.segment<2>(2 * tv.index[e]) += tv.value[e] * force;
}

void ExplicitDynamics::add_wall_tractions(const Eigen::MatrixXd& x, const Eigen::MatrixXd& fw,
                                          Eigen::VectorXd& f) const {
  // The feet: each pushed particle's nearest point on the walls, in the configuration the
  // functions live in (the particles' current positions for the Eulerian kernel, whose
  // centres are there; the reference ones for the Lagrangian kernel).
  const Eigen::MatrixXd& at = opt_.frame == KernelFrame::eulerian ? x : X_;
  std::vector<int> pushed;
  for (int K = 0; K < n_; ++K)
    if (fw(0, K) != 0 || fw(1, K) != 0) pushed.push_back(K);
  if (pushed.empty()) return;
  Eigen::MatrixXd feet(2, static_cast<Eigen::Index>(pushed.size()));
  for (std::size_t k = 0; k < pushed.size(); ++k) {
    const Eigen::Vector2d p = at.col(pushed[k]);
    double best = std::numeric_limits<double>::infinity();
    for (const RigidWall& w : model_.rigid_walls) {
      const Eigen::Vector2d foot = w.nearest(p);
      if (const double d2 = (p - foot).squaredNorm(); d2 < best) {
        best = d2;
        feet.col(k) = foot;
      }
    }
  }
  const Approximation& force =
      opt_.force == ForceForm::variational || !d_.test ? *d_.trial : *d_.test;
  // The force at the particle, as WallTraction::off.
  auto at_particle = [&](int K) { add_force_at_particle(K, fw.col(K), f); };
  auto add = [&](const ShapeTable& t, int row, int K) {
    if (t.offsets[row] == t.offsets[row + 1]) return at_particle(K);  // no support reaches it
    for (int e = t.offsets[row]; e < t.offsets[row + 1]; ++e)
      f.segment<2>(2 * t.index[e]) += t.value[e] * fw.col(K);
  };
  try {
    const ShapeTable t = force.evaluate(d_.particles, feet, 0);
    for (std::size_t k = 0; k < pushed.size(); ++k) add(t, static_cast<int>(k), pushed[k]);
  } catch (const SingularError&) {
    // A foot at the material's edge (a splash, a corner) whose support is too small for the
    // correction: that particle's force stays at the particle.
    for (std::size_t k = 0; k < pushed.size(); ++k) {
      try {
        const ShapeTable t = force.evaluate(d_.particles, feet.col(k), 0);
        add(t, 0, pushed[k]);
      } catch (const SingularError&) {
        at_particle(pushed[k]);
      }
    }
  }
}

Eigen::MatrixXd ExplicitDynamics::positions_of(const std::vector<int>& particles) const {
  Eigen::MatrixXd x(dim_, static_cast<Eigen::Index>(particles.size()));
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const int I = particles[k];
    x.col(k) = X_.col(I);
    if (d_.particle_values)
      x.col(k) += u_.segment(dim_ * I, dim_);
    else
      add_field_at(values_at_particles_, dim_, u_, I, x.col(k).data());
  }
  return x;
}

double ExplicitDynamics::min_jacobian() const {
  const int dd = dim_ * dim_;
  double j = std::numeric_limits<double>::infinity();
  for (int q = 0; q < nq_; ++q) {
    const double* F = F_.data() + dd * q;
    j = std::min(j, dim_ == 1 ? F[0] : F[0] * F[3] - F[1] * F[2]);
  }
  return j;
}

Eigen::VectorXi ExplicitDynamics::point_neighbours() const {
  const ShapeTable& t = d_.trial_q;
  Eigen::VectorXi n(nq_);
  for (int q = 0; q < nq_; ++q) n[q] = t.offsets[q + 1] - t.offsets[q];
  return n;
}

int ExplicitDynamics::min_neighbours() const {
  // Called after every step by detectors: no allocation.
  const ShapeTable& t = d_.trial_q;
  int m = nq_ > 0 ? std::numeric_limits<int>::max() : 0;
  for (int q = 0; q < nq_; ++q) m = std::min(m, t.offsets[q + 1] - t.offsets[q]);
  return m;
}

Eigen::VectorXd ExplicitDynamics::point_state(const std::string& name) const {
  const std::vector<std::string> names = model_.material->state_names(dim_);
  const int ns = model_.material->state_size(dim_);
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end() || ns == 0) return {};
  const int slot = static_cast<int>(it - names.begin());
  Eigen::VectorXd v(nq_);
  for (int q = 0; q < nq_; ++q)
    v[renumbered_ ? point_given_[q] : q] = state_[static_cast<std::size_t>(ns) * q + slot];
  return v;
}

void ExplicitDynamics::apply_prescribed(double t, Eigen::VectorXd& v, Eigen::VectorXd& a) const {
  for (const PrescribedVelocity& p : model_.prescribed)
    if (t < p.until) {
      v[dim_ * p.particle + p.component] = p.value;
      a[dim_ * p.particle + p.component] = 0;
    }
}

void ExplicitDynamics::set_particle_velocity(const Eigen::MatrixXd& v) {
  if (v.rows() != dim_ || v.cols() != n_)
    throw InputError(fmt::format("initial velocity must be {} × {} (components × particles), got "
                                 "{} × {}",
                                 dim_, n_, v.rows(), v.cols()));
  if (d_.particle_values) {
    v_ = Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
  } else {
    fit_nodal_values(values_at_particles_, n_, dim_, v, v_);
  }
  apply_prescribed(t_, v_, a_);
  energy_.kinetic = kinetic_energy();
  energy_.initial = energy_.kinetic - energy_.internal_work + energy_.external_work;
}

void ExplicitDynamics::set_replayed_state(double t, const Eigen::MatrixXd& u,
                                          const Eigen::MatrixXd& v) {
  if (!d_.particle_values)
    throw std::logic_error("set_replayed_state: the method's unknowns are not particle values");
  if (u.rows() != dim_ || u.cols() != n_ || v.rows() != dim_ || v.cols() != n_)
    throw std::logic_error(fmt::format("set_replayed_state: fields must be {} × {}", dim_, n_));
  t_ = t;
  u_ = Eigen::Map<const Eigen::VectorXd>(u.data(), u.size());
  v_ = Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
  energy_.kinetic = kinetic_energy();
}

double ExplicitDynamics::max_eigenvalue(int iterations) const {
  const int m = dim_ * n_;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(-1, 1);
  Eigen::VectorXd x(m);
  for (int i = 0; i < m; ++i) x[i] = uni(rng);
  for (const PrescribedVelocity& p : model_.prescribed) x[dim_ * p.particle + p.component] = 0;
  Eigen::VectorXd fp(m), fm(m), Kx(m);
  const bool eulerian = opt_.frame == KernelFrame::eulerian;
  double lambda = 0;
  for (int it = 0; it < iterations; ++it) {
    x /= x.norm();
    const double eps = 1e-7 * std::max(spacing_, 1e-300);
    const Eigen::VectorXd du = eps * x;
    if (eulerian) {
      internal_force(u_, du, 0, false, fp);
      internal_force(u_, -du, 0, false, fm);
    } else {
      internal_force(u_ + du, du, 0, false, fp);
      internal_force(u_ - du, -du, 0, false, fm);
    }
    Kx = (fp - fm) / (2 * eps);
    for (const PrescribedVelocity& p : model_.prescribed) Kx[dim_ * p.particle + p.component] = 0;
    const Eigen::VectorXd Mx = x.cwiseQuotient(inv_mass_);
    lambda = x.dot(Kx) / x.dot(Mx);
    x = Kx.cwiseProduct(inv_mass_);
    if (x.norm() == 0) return 0;
  }
  // The finite differences moved the scratch buffers only; the committed stress is restored.
  Eigen::VectorXd f(m);
  internal_force(u_, Eigen::VectorXd::Zero(m), 0, false, f);
  return lambda;
}

void ExplicitDynamics::displace(const Eigen::VectorXd& du) {
  if (du.size() != dim_ * n_)
    throw InputError(fmt::format("a displacement increment needs {} entries, got {}", dim_ * n_,
                                 du.size()));
  u_ += du;
  Eigen::VectorXd f(dim_ * n_);
  internal_force(u_, du, 0, true, f);
  f_int_ = f;
  if (opt_.frame == KernelFrame::eulerian) {
    committed_F_ = F_;
    retabulate();
    internal_force(u_, Eigen::VectorXd::Zero(dim_ * n_), 0, true, f_int_);
  }
}

Eigen::VectorXd ExplicitDynamics::trial_force(const Eigen::VectorXd& du) const {
  Eigen::VectorXd f(dim_ * n_);
  if (opt_.frame == KernelFrame::lagrangian) {
    internal_force(u_ + du, du, 0, false, f);
    return f;
  }
  ExplicitDynamics moved(*this);
  moved.displace(du);
  return moved.f_int_;
}

double ExplicitDynamics::critical_time_step(int iterations) const {
  const double l = max_eigenvalue(iterations);
  if (!(l > 0)) throw SingularError("the stiffness has no positive eigenvalue: no critical step");
  return 2 / std::sqrt(l);
}

void ExplicitDynamics::step(double dt) {
  if (!(dt > 0)) throw InputError(fmt::format("time step {} must be positive", dt));
  const int m = dim_ * n_;
  Eigen::VectorXd& du = du_;
  Eigen::VectorXd& f_new = f_new_;
  Eigen::VectorXd& fe_new = fe_new_;
  Eigen::VectorXd& v_pred = v_pred_;
  du.resize(m);
  f_new.resize(m);
  fe_new.resize(m);
  // Predictor: u_{n+1} = u_n + dt v_n + dt²/2 a_n (both schemes), velocities at the half step
  // (Verlet) or the Newmark predictor v_n + (1 − γ) dt a_n.
  const double gamma = opt_.integrator == TimeIntegrator::verlet ? 0.5 : opt_.newmark_gamma;
  // One pass over the unknowns instead of three (at 10^6 particles each pass streams 16 MB);
  // every entry is the expression v_ + (1 − γ) dt a_, dt v_ + ½ dt² a_ evaluated as before.
  v_pred.resize(m);
  {
    const double c_pred = (1 - gamma) * dt, c_half = 0.5 * dt * dt;
    const double *v = v_.data(), *a = a_.data();
    double *vp = v_pred.data(), *d = du.data(), *u = u_.data();
    for (int i = 0; i < m; ++i) {
      vp[i] = v[i] + c_pred * a[i];
      d[i] = dt * v[i] + c_half * a[i];
      u[i] += d[i];
    }
  }
  internal_force(u_, du, dt, true, f_new);
  // Only the Eulerian frame advances F from the committed one; the Lagrangian F is u's.
  if (opt_.frame == KernelFrame::eulerian) committed_F_ = F_;
  external_force(t_ + dt, fe_new);
  Eigen::VectorXd& a_new = a_;
  // Energy: trapezoidal work of the internal and external forces over du; at prescribed
  // unknowns the support does the work (its reaction is f_int − f_ext there).
  energy_.internal_work += 0.5 * (f_int_ + f_new).dot(du);
  double ext = 0.5 * (f_ext_ + fe_new).dot(du);
  for (const PrescribedVelocity& p : model_.prescribed)
    if (t_ < p.until) {
      const int i = dim_ * p.particle + p.component;
      ext += 0.5 * ((f_int_[i] - f_ext_[i]) + (f_new[i] - fe_new[i])) * du[i];
    }
  energy_.external_work += ext;
  {  // a = (f_ext − f_int)/m and v = v_pred + γ dt a in one pass
    const double c_corr = gamma * dt;
    const double *fe = fe_new.data(), *fi = f_new.data(), *im = inv_mass_.data(),
                 *vp = v_pred.data();
    double *a = a_new.data(), *v = v_.data();
    for (int i = 0; i < m; ++i) {
      a[i] = (fe[i] - fi[i]) * im[i];
      v[i] = vp[i] + c_corr * a[i];
    }
  }
  f_int_.swap(f_new);  // the scratch vectors are overwritten next step
  f_ext_.swap(fe_new);
  t_ += dt;
  apply_prescribed(t_, v_, a_);
  ++counters_.steps;
  if (opt_.frame == KernelFrame::eulerian && opt_.remedies.any()) apply_fluid_remedies(dt);
  if (opt_.frame == KernelFrame::eulerian && counters_.steps % opt_.update_every == 0) retabulate();
  energy_.kinetic = kinetic_energy();
}

void ExplicitDynamics::retabulate() {
  const int dd = dim_ * dim_;
  auto jac = [&](int q) {
    const double* F = F_.data() + dd * q;
    return dim_ == 1 ? F[0] : F[0] * F[3] - F[1] * F[2];
  };
  // Into the discretization's own storage: no allocation per recomputation.
  Eigen::MatrixXd& x = d_.particles.x;
  // The kernels' centres: the unknowns (coefficients), or the trial field at the particles
  // (KernelCentres::interpolated; the same for methods whose unknowns are particle values).
  if (opt_.kernel_centres == KernelCentres::interpolated && !d_.particle_values)
    x = particle_positions();
  else
    x = X_ + Eigen::Map<const Eigen::MatrixXd>(u_.data(), dim_, n_);
  Eigen::VectorXd& V = d_.particles.volume;
  V = V0_;
  const int nodal = d_.quadrature.nodal_points;
  for (int I = 0; I < std::min(n_, nodal); ++I) V[I] *= jac(I);
  Eigen::MatrixXd& xq = d_.quadrature.points;
  xq = Xq_;
  // The points move with the material: the t = 0 values place them at X_q + u^h(X_q). (The
  // current table would evaluate u at the point's current position with the current
  // supports, a lagged estimate that loses stress points under large strain.)
  const ShapeTable& t = values_at_points0_;
  const bool values = static_cast<int>(t.value.size()) == t.entries();
  for (int q = 0; q < nq_; ++q) {
    if (q < nodal) {
      xq.col(q) = x.col(q);
      continue;
    }
    if (!values) continue;
    for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e)
      for (int c = 0; c < dim_; ++c) xq(c, q) += t.value[e] * u_[dim_ * t.index[e] + c];
  }
  for (int q = 0; q < nq_; ++q) d_.quadrature.weights[q] = w0_[q] * jac(q);
  if (opt_.support != SupportRule::fixed) adapt_supports();
  method_.retabulate(d_, 1, retabulation_);
  counters_.degenerate_points = retabulation_.degenerate_points;
  counters_.degenerate_peak = std::max(counters_.degenerate_peak, counters_.degenerate_points);
  if (d_.trial_q.points() != nq_ || d_.test_q.points() != nq_)
    throw std::logic_error("a method's retabulation changed its integration points");
  build_force_tables();
  ++counters_.retabulations;
  counters_.neighbour_rebuilds = retabulation_.rebuilds();
}

void ExplicitDynamics::adapt_supports() {
  // The growth of each point's neighbourhood: J^{1/d} (its volume's, SPH's h ∝ (m/ρ)^{1/d})
  // or the largest principal stretch λ_max = √(largest eigenvalue of FᵀF) (the direction
  // that loses neighbours first: a nearly incompressible ring stretched 1.5 round its hoop
  // keeps J ≈ 1). A collapsed or inverted point (J ≤ 0) is read as J = 1e-3.
  const int dd = dim_ * dim_;
  auto growth = [&](int q) {
    const double* F = F_.data() + dd * q;
    if (dim_ == 1) return std::max(F[0], 1e-3);
    if (opt_.support == SupportRule::adaptive)
      return std::sqrt(std::max(F[0] * F[3] - F[1] * F[2], 1e-3));
    const double c11 = F[0] * F[0] + F[1] * F[1], c22 = F[2] * F[2] + F[3] * F[3],
                 c12 = F[0] * F[2] + F[1] * F[3];
    const double half_trace = 0.5 * (c11 + c22);
    const double disc = std::sqrt(std::max(0.25 * (c11 - c22) * (c11 - c22) + c12 * c12, 0.0));
    return std::sqrt(std::max(half_trace + disc, 1e-6));
  };
  // At each particle: its own point's where the rule integrates at the particles, else the
  // average over the integration points its t = 0 trial function covers, weighted by
  // w0_q |N_I(X_q)| (the volume each point gives the particle).
  const int nodal = d_.quadrature.nodal_points;
  Eigen::VectorXd g = Eigen::VectorXd::Ones(n_);
  if (nodal >= n_) {
    for (int I = 0; I < n_; ++I) g[I] = growth(I);
  } else {
    Eigen::VectorXd num = Eigen::VectorXd::Zero(n_), den = Eigen::VectorXd::Zero(n_);
    const ShapeTable& t = values_at_points0_;
    for (int q = 0; q < nq_; ++q) {
      const double gq = growth(q);
      for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e) {
        const double w = w0_[q] * std::abs(t.value[e]);
        num[t.index[e]] += w * gq;
        den[t.index[e]] += w;
      }
    }
    for (int I = 0; I < n_; ++I)
      if (den[I] > 0) g[I] = num[I] / den[I];
  }
  // At most kMaxSupportGrowth times the t = 0 radius: a band point strained to 1 would
  // otherwise widen its support over the whole plate (a dense table, minutes per step).
  d_.particles.dilation = dilation0_.cwiseProduct(g.cwiseMin(kMaxSupportGrowth));
}

double ExplicitDynamics::kinetic_energy() const {
  double k = 0;
  for (int I = 0; I < n_; ++I)
    for (int c = 0; c < dim_; ++c) k += 0.5 * model_.mass[I] * v_[dim_ * I + c] * v_[dim_ * I + c];
  return k;
}

namespace {
Eigen::MatrixXd field_at_particles(const ShapeTable& t, bool particle_values, int dim, int n,
                                   const Eigen::VectorXd& u) {
  Eigen::MatrixXd out = Eigen::Map<const Eigen::MatrixXd>(u.data(), dim, n);
  if (particle_values) return out;
  out.setZero();
  for (int I = 0; I < n; ++I) add_field_at(t, dim, u, I, out.col(I).data());
  return out;
}
}  // namespace

Eigen::MatrixXd ExplicitDynamics::particle_velocity() const {
  return field_at_particles(values_at_particles_, d_.particle_values, dim_, n_, v_);
}

Eigen::MatrixXd ExplicitDynamics::particle_displacement() const {
  return field_at_particles(values_at_particles_, d_.particle_values, dim_, n_, u_);
}

Eigen::MatrixXd ExplicitDynamics::particle_positions() const {
  return X_ + particle_displacement();
}

Eigen::MatrixXd ExplicitDynamics::point_cauchy_stress() const {
  const int dd = dim_ * dim_;
  Eigen::MatrixXd s(dd, nq_);
  for (int q = 0; q < nq_; ++q) {
    Eigen::Map<const Eigen::MatrixXd> F(F_.data() + dd * q, dim_, dim_);
    Eigen::Map<const Eigen::MatrixXd> S(stress_.data() + dd * q, dim_, dim_);
    const double J = F.determinant();
    Eigen::MatrixXd sigma =
        opt_.frame == KernelFrame::eulerian ? Eigen::MatrixXd(S / J)
                                            : Eigen::MatrixXd(S * F.transpose() / J);
    s.col(q) = Eigen::Map<const Eigen::VectorXd>(sigma.data(), dd);
  }
  return points_to_given(std::move(s));
}

const std::vector<int>& ExplicitDynamics::particle_points() const {
  if (!nearest_point_.empty()) return nearest_point_;
  nearest_point_.resize(n_);
  if (d_.quadrature.nodal_points >= n_) {
    for (int I = 0; I < n_; ++I) nearest_point_[I] = I;
    return nearest_point_;
  }
  // Cell rules: the nearest integration point. The reference points do not move, so the
  // search runs once, on the first call.
  ParticleSet pts;
  pts.dim = dim_;
  pts.x = Xq_;
  const NeighbourSearch search(pts);
  std::vector<int> near;
  for (int I = 0; I < n_; ++I) {
    double radius = spacing_ > 0 ? spacing_ : 1.0;
    for (near.clear(); near.empty(); radius *= 2) search.within(X_.col(I).data(), radius, near);
    int best = near.front();
    for (int q : near)
      if ((Xq_.col(q) - X_.col(I)).squaredNorm() < (Xq_.col(best) - X_.col(I)).squaredNorm())
        best = q;
    nearest_point_[I] = best;
  }
  return nearest_point_;
}

Eigen::MatrixXd ExplicitDynamics::particle_cauchy_stress() const {
  const Eigen::MatrixXd s = point_cauchy_stress();
  if (d_.quadrature.nodal_points >= n_) return s.leftCols(n_);
  const std::vector<int>& point = particle_points();
  Eigen::MatrixXd out(s.rows(), n_);
  for (int I = 0; I < n_; ++I) out.col(I) = s.col(point[I]);
  return out;
}

std::string ExplicitDynamics::description() const {
  std::string visc = opt_.viscosity.enabled()
                         ? fmt::format("artificial viscosity alpha={:g} beta={:g} (l = {:g})",
                                       opt_.viscosity.alpha, opt_.viscosity.beta, spacing_)
                         : "no artificial viscosity";
  return fmt::format(
      "{} kernel{}, {}, {}, {}{}{}, {} thread{}{}",
      opt_.frame == KernelFrame::lagrangian ? "Lagrangian" : "Eulerian",
      opt_.frame == KernelFrame::eulerian
          ? fmt::format(" (tables every {} steps, neighbour skin {:g} dx{})", opt_.update_every,
                        opt_.neighbour_skin,
                        opt_.kernel_centres == KernelCentres::interpolated && !d_.particle_values
                            ? ", supports at the interpolated positions"
                            : "")
          : "",
      opt_.integrator == TimeIntegrator::verlet
          ? "central differences (velocity Verlet)"
          : fmt::format("explicit Newmark predictor-corrector gamma={:g}", opt_.newmark_gamma),
      model_.material->description(dim_), visc,
      opt_.force == ForceForm::variational
          ? ", variational internal force (transpose of the trial gradient)"
          : "",
      opt_.volume_average == VolumeAverage::patch
          ? ", F-bar over the particles' patches" + opt_.remedies.description()
          : opt_.remedies.description(),
      opt_.threads, opt_.threads > 1 ? "s" : "",
      renumbered_ ? ", particles and points renumbered along the Hilbert curve" : "");
}

}  // namespace mfv
