#include "dynamics/petsc_dynamics.hpp"
#include "dynamics/small_matrix.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <petscmat.h>

#include "methods/core/errors.hpp"
#include "methods/core/petsc_session.hpp"

namespace mfv {

namespace {

constexpr int kChunk = 256;  // integration points per material call, as the native engine

void ok(PetscErrorCode code, const char* what) { petsc::check(code, what); }

/// This rank's contiguous share [begin, end) of n items (PETSc's default split).
struct Range {
  PetscInt begin = 0, end = 0;
  PetscInt size() const { return end - begin; }
  bool owns(PetscInt i) const { return i >= begin && i < end; }
};

Range split(MPI_Comm comm, PetscInt n) {
  PetscInt local = PETSC_DECIDE, global = n;
  ok(PetscSplitOwnership(comm, &local, &global), "PetscSplitOwnership");
  PetscInt end = 0;
  MPI_Scan(&local, &end, 1, MPIU_INT, MPI_SUM, comm);
  return {end - local, end};
}

/// Which rank each integration point lives on, as the global row order of the operators:
/// `order` lists the points of rank 0, then rank 1 ..., each in ascending number, and
/// `begin[r]` is where rank r's start. A nodal point (a particle's own, q < nodal_points)
/// goes with its particle; any other point (stress points, Gauss points) with the particle of
/// median number in its support, so that a point's support is mostly on its own rank and the
/// halo stays the band along the cut whatever the rule's numbering.
struct PointPartition {
  std::vector<int> order;
  std::vector<PetscInt> begin;
};

PointPartition partition_points(const ShapeTable& t, int nodal_points, int n,
                                const std::vector<PetscInt>& particle_begin) {
  const int ranks = static_cast<int>(particle_begin.size()) - 1;
  auto owner = [&](int J) {
    return static_cast<int>(std::upper_bound(particle_begin.begin(), particle_begin.end(), J) -
                            particle_begin.begin()) - 1;
  };
  const int nq = t.points();
  std::vector<int> rank_of(nq);
  std::vector<int> support;
  for (int q = 0; q < nq; ++q) {
    if (q < nodal_points && q < n) {
      rank_of[q] = owner(q);
      continue;
    }
    support.assign(t.index.begin() + t.offsets[q], t.index.begin() + t.offsets[q + 1]);
    if (support.empty()) {
      rank_of[q] = 0;
      continue;
    }
    auto mid = support.begin() + support.size() / 2;
    std::nth_element(support.begin(), mid, support.end());
    rank_of[q] = owner(*mid);
  }
  PointPartition p;
  p.begin.assign(ranks + 1, 0);
  for (int q = 0; q < nq; ++q) ++p.begin[rank_of[q] + 1];
  for (int r = 0; r < ranks; ++r) p.begin[r + 1] += p.begin[r];
  p.order.resize(nq);
  std::vector<PetscInt> next(p.begin.begin(), p.begin.end() - 1);
  for (int q = 0; q < nq; ++q) p.order[next[rank_of[q]]++] = q;
  return p;
}

/// The gradient operator of table t: an AIJ matrix with a row per (point, direction j) of
/// this rank's points (rows k = points.begin ... in the partition's order, point
/// order[k]) and a column per particle J, entry w_q ∂N_J/∂X_j(X_q) (w_q = 1 without
/// weights), preallocated exactly from the table's rows (diagonal block: this rank's
/// particles; off-diagonal block: the others).
Mat gradient_operator(MPI_Comm comm, const ShapeTable& t, int dim, Range points,
                      const std::vector<int>& order, Range particles, PetscInt n,
                      const Eigen::VectorXd* weights) {
  const PetscInt rows = dim * points.size();
  std::vector<PetscInt> d_nnz(rows), o_nnz(rows);
  for (PetscInt k = points.begin; k < points.end; ++k) {
    const int q = order[k];
    PetscInt d = 0, o = 0;
    for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e) ++(particles.owns(t.index[e]) ? d : o);
    for (int j = 0; j < dim; ++j) {
      d_nnz[dim * (k - points.begin) + j] = d;
      o_nnz[dim * (k - points.begin) + j] = o;
    }
  }
  Mat G = nullptr;
  ok(MatCreate(comm, &G), "MatCreate");
  ok(MatSetSizes(G, rows, particles.size(), PETSC_DETERMINE, n), "MatSetSizes");
  ok(MatSetType(G, MATAIJ), "MatSetType");
  // One of the two applies (SeqAIJ on one rank, where every column is on the diagonal block).
  ok(MatSeqAIJSetPreallocation(G, 0, d_nnz.data()), "MatSeqAIJSetPreallocation");
  ok(MatMPIAIJSetPreallocation(G, 0, d_nnz.data(), 0, o_nnz.data()),
     "MatMPIAIJSetPreallocation");
  ok(MatSetOption(G, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE), "MatSetOption");
  ok(MatSetOption(G, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  std::vector<PetscInt> cols;
  std::vector<PetscScalar> vals;
  for (PetscInt k = points.begin; k < points.end; ++k) {
    const int q = order[k];
    const int e0 = t.offsets[q], e1 = t.offsets[q + 1];
    cols.assign(t.index.begin() + e0, t.index.begin() + e1);
    vals.resize(e1 - e0);
    for (int j = 0; j < dim; ++j) {
      const PetscInt row = dim * k + j;
      for (int e = e0; e < e1; ++e)
        vals[e - e0] = weights ? (*weights)[q] * t.grad[dim * e + j] : t.grad[dim * e + j];
      ok(MatSetValues(G, 1, &row, e1 - e0, cols.data(), vals.data(), INSERT_VALUES),
         "MatSetValues");
    }
  }
  ok(MatAssemblyBegin(G, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  ok(MatAssemblyEnd(G, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  return G;
}

/// Columns of G's off-diagonal block: the particles of other ranks this rank's rows touch.
long ghost_columns(Mat G) {
  PetscBool mpi = PETSC_FALSE;
  ok(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(G), MATMPIAIJ, &mpi),
     "PetscObjectTypeCompare");
  if (!mpi) return 0;
  Mat Ad = nullptr, Ao = nullptr;
  const PetscInt* colmap = nullptr;
  ok(MatMPIAIJGetSeqAIJ(G, &Ad, &Ao, &colmap), "MatMPIAIJGetSeqAIJ");
  PetscInt r = 0, c = 0;
  ok(MatGetSize(Ao, &r, &c), "MatGetSize");
  return c;
}

long local_nonzeros(Mat G) {
  MatInfo info;
  ok(MatGetInfo(G, MAT_LOCAL, &info), "MatGetInfo");
  return static_cast<long>(info.nz_used);
}


/// A vector's owned entries for reading or writing (VecGetArray/VecRestoreArray in scope).
class Local {
 public:
  explicit Local(Vec v) : v_(v) { ok(VecGetArray(v_, &a_), "VecGetArray"); }
  ~Local() { VecRestoreArray(v_, &a_); }
  Local(const Local&) = delete;
  Local& operator=(const Local&) = delete;
  double& operator[](PetscInt i) { return a_[i]; }
  double* data() { return a_; }

 private:
  Vec v_;
  PetscScalar* a_ = nullptr;
};

}  // namespace

struct PetscDynamics::Impl {
  DynamicsModel model;  // the engine's copy (the native engine keeps its own)
  DynamicsOptions opt;
  ExplicitDynamics native;
  MPI_Comm comm = PETSC_COMM_WORLD;
  int dim = 1, n = 0, nq = 0, dd = 1, ns = 0;
  Range particles, points;  ///< points: rows in the partition's order
  std::vector<int> point_order;  ///< the point of each global row (PointPartition::order)
  double t = 0, spacing = 0, wave_speed = 0;
  EnergyBalance energy;
  DynamicsCounters counters;
  bool finite = true;
  bool gathered = true;  ///< native holds the current state
  PetscHalo halo;
  Mat G = nullptr, Gt = nullptr;    // trial and (weighted) test gradient operators
  Mat GM = nullptr, GtM = nullptr;  // the same applied per component (MATMAIJ)
  // Unknowns (dim per particle, interleaved); the per-entry mass and its inverse.
  Vec u = nullptr, v = nullptr, a = nullptr, f_int = nullptr, f_ext = nullptr, f_new = nullptr,
      fe_new = nullptr, du = nullptr, v_pred = nullptr, mass = nullptr, inv_mass = nullptr;
  // Per point (dim·dim, column-major): F, the summed stress P, and Ḟ dt for the viscosity.
  Vec H = nullptr, P = nullptr, Hd = nullptr;
  std::vector<double> history;  ///< material state of the owned points (ns per point)
  struct Prescribed {
    PetscInt local;
    double value, until;
  };
  std::vector<Prescribed> prescribed;  ///< those of the owned unknowns, in the model's order
  Eigen::VectorXd f_ext_full;          ///< the model's external force, every unknown
  // Gathers to every rank, made on the first request.
  VecScatter to_all_unknowns = nullptr, to_all_points = nullptr;
  Vec all_unknowns = nullptr, all_points = nullptr;

  Impl(const Method& method, Discretization d, DynamicsModel m, DynamicsOptions o)
      : model(m), opt(o), native(method, std::move(d), std::move(m), o) {}

  ~Impl() {
    for (Vec* x : {&u, &v, &a, &f_int, &f_ext, &f_new, &fe_new, &du, &v_pred, &mass,
                   &inv_mass, &H, &P, &Hd, &all_unknowns, &all_points})
      if (*x) VecDestroy(x);
    for (VecScatter* s : {&to_all_unknowns, &to_all_points})
      if (*s) VecScatterDestroy(s);
    for (Mat* M : {&GM, &GtM, &G, &Gt})
      if (*M) MatDestroy(M);
  }

  template <int D>
  void points_stress(double dt, bool viscosity);
  void internal_force(double dt);
  void gather(Vec x, bool unknowns, Eigen::VectorXd& out);
};

template <int D>
void PetscDynamics::Impl::points_stress(double dt, bool viscosity) {
  constexpr int DD = D * D;
  const PetscInt nloc = points.size();
  const double* S0 = model.initial_stress.size() ? model.initial_stress.data() : nullptr;
  const double alpha = opt.viscosity.alpha, beta = opt.viscosity.beta;
  Local F(H), S(P);
  double* Fd = nullptr;
  Vec hd = Hd;
  PetscScalar* fd_array = nullptr;
  if (viscosity) {
    ok(VecGetArray(hd, &fd_array), "VecGetArray");
    Fd = fd_array;
  }
  for (PetscInt q = 0; q < nloc; ++q)
    for (int i = 0; i < D; ++i) F[DD * q + i * (D + 1)] += 1;
  for (PetscInt q0 = 0; q0 < nloc; q0 += kChunk) {
    const PetscInt q1 = std::min<PetscInt>(nloc, q0 + kChunk);
    model.material->first_piola(D, static_cast<int>(q1 - q0), F.data() + DD * q0,
                                S.data() + DD * q0,
                                ns > 0 ? history.data() + static_cast<long>(ns) * q0 : nullptr,
                                dt);
  }
  // The native engine's PointKernel::finish in the Lagrangian frame: prestress F S₀, and the
  // viscous pressure −q J F⁻ᵀ in compression (L = Ḟ F⁻¹, Ḟ = Σ du_J ⊗ ∇₀N_J / dt).
  for (PetscInt q = 0; q < nloc; ++q) {
    const double* Fq = F.data() + DD * q;
    double* Pq = S.data() + DD * q;
    if (S0) {
      double FS[DD];
      SmallMatrix<D>::multiply(Fq, S0, FS);
      for (int e = 0; e < DD; ++e) Pq[e] += FS[e];
    }
    if (!viscosity) continue;
    double Fdot[DD], Fi[DD], L[DD];
    for (int e = 0; e < DD; ++e) Fdot[e] = Fd[DD * q + e] / dt;
    SmallMatrix<D>::invert(Fq, Fi);
    SmallMatrix<D>::multiply(Fdot, Fi, L);
    double div = 0;
    for (int i = 0; i < D; ++i) div += L[i + D * i];
    const double J = SmallMatrix<D>::det(Fq);
    if (!(div < 0)) continue;
    const double qv = model.density / J *
                      (beta * spacing * spacing * div * div - alpha * wave_speed * spacing * div);
    if (qv == 0) continue;
    for (int j = 0; j < D; ++j)
      for (int i = 0; i < D; ++i) Pq[i + D * j] -= qv * J * Fi[j + D * i];
  }
  if (viscosity) ok(VecRestoreArray(hd, &fd_array), "VecRestoreArray");
}

void PetscDynamics::Impl::internal_force(double dt) {
  const bool viscosity = opt.viscosity.enabled() && dt > 0;
  ok(MatMult(GM, u, H), "MatMult (deformation gradient)");
  if (viscosity) ok(MatMult(GM, du, Hd), "MatMult (deformation rate)");
  if (dim == 1)
    points_stress<1>(dt, viscosity);
  else
    points_stress<2>(dt, viscosity);
  ok(MatMultTranspose(GtM, P, f_new), "MatMultTranspose (internal force)");
}

void PetscDynamics::Impl::gather(Vec x, bool unknowns, Eigen::VectorXd& out) {
  VecScatter& s = unknowns ? to_all_unknowns : to_all_points;
  Vec& all = unknowns ? all_unknowns : all_points;
  if (!s) ok(VecScatterCreateToAll(x, &s, &all), "VecScatterCreateToAll");
  ok(VecScatterBegin(s, x, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
  ok(VecScatterEnd(s, x, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
  PetscInt size = 0;
  ok(VecGetSize(all, &size), "VecGetSize");
  const PetscScalar* p = nullptr;
  ok(VecGetArrayRead(all, &p), "VecGetArrayRead");
  out = Eigen::Map<const Eigen::VectorXd>(p, size);
  ok(VecRestoreArrayRead(all, &p), "VecRestoreArrayRead");
}

PetscDynamics::PetscDynamics(const Method& method, Discretization d, DynamicsModel model,
                             DynamicsOptions options) {
  auto refuse = [](const std::string& what, const std::string& why) {
    throw InputError(fmt::format("engine=petsc does not support {} ({}); use engine=native",
                                 what, why));
  };
  if (options.frame == KernelFrame::eulerian)
    refuse("frame=eulerian", "its tables are recomputed at the moving particles; the PETSc "
                             "engine runs the total-Lagrangian step");
  if (options.volume_average != VolumeAverage::off)
    refuse("volume_average=patch", "it needs every point's F before any stress");
  if (!model.tensionless_points.empty())
    refuse("tensionless points (wall particles)", "the ranks own their points' stresses");
  if (options.wall_traction != WallTraction::off)
    refuse("wall_traction=weak", "it reads the stresses at the particles' points on every rank");
  if (options.order != ParticleOrder::as_given)
    refuse("reorder=hilbert", "the ranks own contiguous blocks of the given numbering");
  if (!model.follower_pressures.empty())
    refuse("follower pressures", "they need the current positions of the loaded surface every "
                                 "step");
  if (model.particle_forces || model.wall_forces)
    refuse("particle forces", "they need the current positions of every particle every step");
  petsc::ensure_initialized();
  impl_ = std::make_unique<Impl>(method, std::move(d), std::move(model), options);
  Impl& s = *impl_;
  const Discretization& disc = s.native.discretization();
  s.dim = s.native.dim();
  s.n = s.native.particles();
  s.nq = disc.quadrature.size();
  s.dd = s.dim * s.dim;
  s.ns = s.model.material->state_size(s.dim);
  s.spacing = disc.particles.spacing;
  s.wave_speed = s.model.material->wave_speed(s.dim, s.model.density);
  s.particles = split(s.comm, s.n);
  const ShapeTable& trial = disc.trial_q;
  const ShapeTable& test = s.opt.force == ForceForm::variational ? disc.trial_q : disc.test_q;
  for (const ShapeTable* t : {&trial, &test})
    if (t->points() != s.nq || static_cast<int>(t->grad.size()) != t->entries() * s.dim)
      throw std::logic_error("the PETSc engine needs first derivatives of the trial and test "
                             "functions at every integration point");
  {
    const int ranks = petsc::size();
    std::vector<PetscInt> particle_begin(ranks + 1, 0);
    MPI_Allgather(&s.particles.end, 1, MPIU_INT, particle_begin.data() + 1, 1, MPIU_INT, s.comm);
    PointPartition pp =
        partition_points(trial, disc.quadrature.nodal_points, s.n, particle_begin);
    const int r = petsc::rank();
    s.points = {pp.begin[r], pp.begin[r + 1]};
    s.point_order = std::move(pp.order);
  }
  s.G = gradient_operator(s.comm, trial, s.dim, s.points, s.point_order, s.particles, s.n,
                          nullptr);
  s.Gt = gradient_operator(s.comm, test, s.dim, s.points, s.point_order, s.particles, s.n,
                           &disc.quadrature.weights);
  ok(MatCreateMAIJ(s.G, s.dim, &s.GM), "MatCreateMAIJ");
  ok(MatCreateMAIJ(s.Gt, s.dim, &s.GtM), "MatCreateMAIJ");
  ok(MatCreateVecs(s.GM, &s.u, &s.H), "MatCreateVecs");
  for (Vec* x : {&s.v, &s.a, &s.f_int, &s.f_ext, &s.f_new, &s.fe_new, &s.du, &s.v_pred, &s.mass,
                 &s.inv_mass})
    ok(VecDuplicate(s.u, x), "VecDuplicate");
  for (Vec* x : {&s.P, &s.Hd}) ok(VecDuplicate(s.H, x), "VecDuplicate");
  {
    Local m(s.mass), im(s.inv_mass);
    for (PetscInt I = s.particles.begin; I < s.particles.end; ++I)
      for (int c = 0; c < s.dim; ++c) {
        const PetscInt i = s.dim * (I - s.particles.begin) + c;
        m[i] = s.model.mass[I];
        im[i] = 1 / s.model.mass[I];
      }
  }
  for (const PrescribedVelocity& p : s.model.prescribed)
    if (s.particles.owns(p.particle))
      s.prescribed.push_back({s.dim * (p.particle - s.particles.begin) + p.component, p.value,
                              p.until});
  if (s.model.external_force) s.f_ext_full.resize(s.dim * s.n);
  load_from_native();

  PetscHalo& h = s.halo;
  h.ranks = petsc::size();
  h.rank = petsc::rank();
  h.owned_points = s.points.size();
  h.owned_unknowns = s.dim * s.particles.size();
  h.ghost_trial = s.dim * ghost_columns(s.G);
  h.ghost_test = s.dim * ghost_columns(s.Gt);
  const long per_double = sizeof(PetscScalar);
  h.halo_bytes = per_double * (h.ghost_trial * (s.opt.viscosity.enabled() ? 2 : 1) +
                               h.ghost_test + (h.ranks > 1 ? 5 : 0));
  h.matrix_bytes = (local_nonzeros(s.G) + local_nonzeros(s.Gt)) *
                   static_cast<long>(sizeof(PetscScalar) + sizeof(PetscInt));
}

PetscDynamics::~PetscDynamics() = default;

void PetscDynamics::load_from_native() {
  Impl& s = *impl_;
  const ExplicitDynamics& e = s.native;
  const PetscInt u0 = s.dim * s.particles.begin, mloc = s.dim * s.particles.size();
  const std::pair<Vec, const Eigen::VectorXd*> unknowns[] = {
      {s.u, &e.u_}, {s.v, &e.v_}, {s.a, &e.a_}, {s.f_int, &e.f_int_}, {s.f_ext, &e.f_ext_}};
  for (const auto& [x, src] : unknowns) {
    Local l(x);
    for (PetscInt i = 0; i < mloc; ++i) l[i] = (*src)[u0 + i];
  }
  const std::pair<Vec, const std::vector<double>*> per_point[] = {{s.H, &e.F_},
                                                                  {s.P, &e.stress_}};
  for (const auto& [x, src] : per_point) {
    Local l(x);
    for (PetscInt k = 0; k < s.points.size(); ++k) {
      const long q = s.point_order[s.points.begin + k];
      for (int c = 0; c < s.dd; ++c) l[s.dd * k + c] = (*src)[s.dd * q + c];
    }
  }
  s.history.resize(static_cast<std::size_t>(s.ns) * s.points.size());
  for (PetscInt k = 0; k < s.points.size(); ++k) {
    const long q = s.point_order[s.points.begin + k];
    for (int c = 0; c < s.ns; ++c) s.history[s.ns * k + c] = e.state_[s.ns * q + c];
  }
  s.t = e.t_;
  s.energy = e.energy_;
  s.counters = e.counters_;
  s.finite = e.u_.allFinite() && e.v_.allFinite();
  s.gathered = true;
}

void PetscDynamics::set_particle_velocity(const Eigen::MatrixXd& v) {
  state();  // the native engine fits the nodal velocities about the current state
  impl_->native.set_particle_velocity(v);
  load_from_native();
}

void PetscDynamics::step(double dt) {
  if (!(dt > 0)) throw InputError(fmt::format("time step {} must be positive", dt));
  Impl& s = *impl_;
  const PetscInt m = s.dim * s.particles.size();
  const double gamma = s.opt.integrator == TimeIntegrator::verlet ? 0.5 : s.opt.newmark_gamma;
  // ExplicitDynamics::step, entry by entry on the owned unknowns.
  {
    Local u(s.u), v(s.v), a(s.a), du(s.du), vp(s.v_pred);
    const double c_pred = (1 - gamma) * dt, c_acc = 0.5 * dt * dt;
    for (PetscInt i = 0; i < m; ++i) {
      vp[i] = v[i] + c_pred * a[i];
      du[i] = dt * v[i] + c_acc * a[i];
      u[i] += du[i];
    }
  }
  s.internal_force(dt);
  ok(VecSet(s.fe_new, 0.0), "VecSet");
  if (s.model.external_force) {
    s.f_ext_full.setZero();
    s.model.external_force(s.t + dt, s.f_ext_full);
    Local fe(s.fe_new);
    for (PetscInt i = 0; i < m; ++i) fe[i] = s.f_ext_full[s.dim * s.particles.begin + i];
  }
  // Sums of this rank: trapezoidal internal and external work over du, the supports' work at
  // prescribed unknowns, the kinetic energy, and non-finite unknowns; one reduction.
  double sums[5] = {0, 0, 0, 0, 0};
  {
    Local fi(s.f_int), fe(s.f_ext), fn(s.f_new), fen(s.fe_new), du(s.du), a(s.a), v(s.v),
        vp(s.v_pred), im(s.inv_mass), mass(s.mass), u(s.u);
    for (PetscInt i = 0; i < m; ++i) {
      sums[0] += (fi[i] + fn[i]) * du[i];
      sums[1] += (fe[i] + fen[i]) * du[i];
    }
    for (const Impl::Prescribed& p : s.prescribed)
      if (s.t < p.until) {
        const PetscInt i = p.local;
        sums[2] += ((fi[i] - fe[i]) + (fn[i] - fen[i])) * du[i];
      }
    const double c_cor = gamma * dt;
    for (PetscInt i = 0; i < m; ++i) {
      a[i] = (fen[i] - fn[i]) * im[i];
      v[i] = vp[i] + c_cor * a[i];
    }
    const double t_new = s.t + dt;
    for (const Impl::Prescribed& p : s.prescribed)
      if (t_new < p.until) {
        v[p.local] = p.value;
        a[p.local] = 0;
      }
    for (PetscInt i = 0; i < m; ++i) {
      sums[3] += 0.5 * mass[i] * v[i] * v[i];
      if (!std::isfinite(u[i]) || !std::isfinite(v[i])) sums[4] += 1;
    }
  }
  double total[5];
  MPI_Allreduce(sums, total, 5, MPI_DOUBLE, MPI_SUM, s.comm);
  s.energy.internal_work += 0.5 * total[0];
  s.energy.external_work += 0.5 * total[1] + 0.5 * total[2];
  s.energy.kinetic = total[3];
  s.finite = total[4] == 0;
  std::swap(s.f_int, s.f_new);  // the scratch vectors are overwritten next step
  std::swap(s.f_ext, s.fe_new);
  s.t += dt;
  ++s.counters.steps;
  s.gathered = false;
}

double PetscDynamics::time() const { return impl_->t; }
const EnergyBalance& PetscDynamics::energy() const { return impl_->energy; }
const DynamicsCounters& PetscDynamics::counters() const { return impl_->counters; }
bool PetscDynamics::fields_finite() const { return impl_->finite; }
PetscHalo PetscDynamics::halo() const { return impl_->halo; }

const ExplicitDynamics& PetscDynamics::state() {
  Impl& s = *impl_;
  if (s.gathered) return s.native;
  ExplicitDynamics& e = s.native;
  s.gather(s.u, true, e.u_);
  s.gather(s.v, true, e.v_);
  s.gather(s.a, true, e.a_);
  s.gather(s.f_int, true, e.f_int_);
  s.gather(s.f_ext, true, e.f_ext_);
  // Per-point fields arrive in the partition's row order: back to the points' numbers.
  auto unpermute = [&](const double* rows, int width, std::vector<double>& out) {
    for (int k = 0; k < s.nq; ++k) {
      const long q = s.point_order[k];
      for (int c = 0; c < width; ++c) out[width * q + c] = rows[static_cast<long>(width) * k + c];
    }
  };
  Eigen::VectorXd rows;
  s.gather(s.H, false, rows);
  unpermute(rows.data(), s.dd, e.F_);
  s.gather(s.P, false, rows);
  unpermute(rows.data(), s.dd, e.stress_);
  if (s.ns > 0) {
    const int ranks = petsc::size();
    std::vector<int> counts(ranks), displs(ranks);
    const int mine = static_cast<int>(s.history.size());
    MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, s.comm);
    for (int r = 1; r < ranks; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    std::vector<double> all(e.state_.size());
    MPI_Allgatherv(s.history.data(), mine, MPI_DOUBLE, all.data(), counts.data(),
                   displs.data(), MPI_DOUBLE, s.comm);
    unpermute(all.data(), s.ns, e.state_);
  }
  e.t_ = s.t;
  e.energy_ = s.energy;
  e.counters_ = s.counters;
  s.gathered = true;
  return e;
}

Eigen::VectorXd PetscDynamics::displacement() const {
  Eigen::VectorXd out;
  impl_->gather(impl_->u, true, out);
  return out;
}

Eigen::VectorXd PetscDynamics::velocity() const {
  Eigen::VectorXd out;
  impl_->gather(impl_->v, true, out);
  return out;
}

std::string PetscDynamics::description() const {
  const Impl& s = *impl_;
  // The native description ends with its OpenMP thread count, which does not run these steps
  // (one thread per rank).
  std::string base = s.native.description();
  if (const auto k = base.rfind(", "); k != std::string::npos &&
                                       base.find(" thread", k) != std::string::npos)
    base.erase(k);
  return fmt::format("{}; PETSc total-Lagrangian engine on {} MPI rank{} (MPIAIJ gradient "
                     "operators applied per component by MAIJ, 1 thread per rank)",
                     base, s.halo.ranks, s.halo.ranks > 1 ? "s" : "");
}

std::unique_ptr<DynamicsEngine> make_dynamics_engine(const std::string& name,
                                                     const Method& method, Discretization d,
                                                     DynamicsModel model,
                                                     DynamicsOptions options) {
  if (name == "native")
    return std::make_unique<NativeDynamics>(method, std::move(d), std::move(model), options);
  if (name == "petsc")
    return std::make_unique<PetscDynamics>(method, std::move(d), std::move(model), options);
  throw InputError(fmt::format("unknown dynamics engine '{}'; valid: native (the OpenMP engine, "
                               "every option), petsc (total-Lagrangian steps on PETSc across MPI "
                               "ranks)",
                               name));
}

}  // namespace mfv
