/// The fluid remedies of dynamics/fluid_remedies.hpp: the point-cloud operators (pure
/// functions, tested on their own) and the engine's step that applies them
/// (ExplicitDynamics::apply_fluid_remedies, a member defined here so that explicit.cpp only
/// calls it).
#include "dynamics/fluid_remedies.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "dynamics/explicit.hpp"
#include "methods/core/errors.hpp"
#include "methods/neighbours.hpp"

namespace mfv {

DensityFilter density_filter_from(const std::string& name) {
  if (name == "off") return DensityFilter::off;
  if (name == "shepard") return DensityFilter::shepard;
  if (name == "mls") return DensityFilter::mls;
  throw InputError(fmt::format("unknown density_filter '{}'; valid: off, shepard (Colagrossi & "
                               "Landrini's zeroth-order filter), mls (their first-order one)",
                               name));
}

DiffusionForm diffusion_form_from(const std::string& name) {
  if (name == "molteni") return DiffusionForm::molteni;
  if (name == "antuono") return DiffusionForm::antuono;
  throw InputError(fmt::format("unknown density_diffusion_form '{}'; valid: antuono (δ-SPH, "
                               "with the renormalized gradient), molteni (Molteni & Colagrossi "
                               "2009)",
                               name));
}

ShiftingForm shifting_form_from(const std::string& name) {
  if (name == "fickian") return ShiftingForm::fickian;
  if (name == "xu") return ShiftingForm::xu;
  throw InputError(fmt::format("unknown shifting_form '{}'; valid: fickian (Lind et al. 2012, "
                               "-D h^2 grad C), xu (Xu et al. 2009, the neighbours' 1/r^2 "
                               "repulsion)",
                               name));
}

void FluidRemedies::validate() const {
  if (filter_every < 1)
    throw InputError(fmt::format("density_filter_every = {} must be at least 1 (steps between "
                                 "re-initializations; Colagrossi & Landrini use 20-30)",
                                 filter_every));
  if (!(diffusion >= 0 && diffusion <= 1))
    throw InputError(fmt::format("density_diffusion = {} (δ of δ-SPH) must be in [0, 1]; 0.1 is "
                                 "the usual value, 0 turns it off",
                                 diffusion));
  // A particle displaced by ε from a square lattice moves back by about 0.88 D ε per move
  // (h = 1.2 Δx): above D ≈ 2.3 the shift overshoots and grows; 1 leaves a margin.
  if (!(shifting >= 0 && shifting <= 1))
    throw InputError(fmt::format("shifting = {} (D of δr = −D h² ∇C) must be in [0, 1] (a "
                                 "move overshoots the lattice above about 2.3). Give 0.1-0.5, or "
                                 "0 to turn it off",
                                 shifting));
  if (!(shifting_surface >= 0 && shifting_surface <= 2))
    throw InputError(fmt::format("shifting_surface = {} (the concentration C below which a "
                                 "particle shifts tangentially only) must be in [0, 2]; the "
                                 "square lattice's interior reads 1.02, a flat free surface 0.82: "
                                 "give e.g. 0.95",
                                 shifting_surface));
}

std::string FluidRemedies::description() const {
  std::string s;
  if (filter != DensityFilter::off)
    s += fmt::format(", {} density filter every {} steps",
                     filter == DensityFilter::mls ? "MLS" : "Shepard", filter_every);
  if (diffusion > 0)
    s += fmt::format(", density diffusion delta={:g} ({})", diffusion,
                     diffusion_form == DiffusionForm::antuono ? "Antuono et al. 2010"
                                                              : "Molteni & Colagrossi 2009");
  if (shifting > 0)
    s += fmt::format(", particle shifting D={:g} ({}, tangential below C={:g})", shifting,
                     shifting_form == ShiftingForm::xu ? "Xu et al. 2009" : "Lind et al. 2012",
                     shifting_surface);
  return s;
}

namespace remedies {

double kernel(double r, double h, double* dw) {
  const double q = r / h;
  if (!(q < 2)) {
    if (dw) *dw = 0;
    return 0;
  }
  const double sigma = 7 / (4 * M_PI * h * h), t = 1 - 0.5 * q;
  const double t3 = t * t * t;
  if (dw) *dw = sigma / h * (-5 * q * t3);
  return sigma * t3 * t * (2 * q + 1);
}

Pairs::Pairs(const Eigen::MatrixXd& x, double h, int threads_) : threads(std::max(1, threads_)) {
  ParticleSet ps;
  ps.dim = static_cast<int>(x.rows());
  ps.x = x;
  const NeighbourSearch search(ps);
  const Eigen::Index m = x.cols();
  std::vector<std::vector<int>> near(m);
#pragma omp parallel for schedule(static) num_threads(threads) if (m > 2048)
  for (Eigen::Index i = 0; i < m; ++i) search.within(x.col(i).data(), 2 * h, near[i]);
  offsets.assign(1, 0);
  for (Eigen::Index i = 0; i < m; ++i) {
    index.insert(index.end(), near[i].begin(), near[i].end());
    offsets.push_back(static_cast<int>(index.size()));
  }
}

int diffusion_substeps(double delta, double h, double c0, double dt, double dx) {
  constexpr double kFastest = 4.64;  // the checkerboard's decay rate over δ h c0 / Δx²
  const double rate_dt = kFastest * delta * h * c0 * dt / (dx * dx);
  return std::max(1, static_cast<int>(std::ceil(rate_dt)));
}

namespace {
/// ∇_i W_ij = dW/dr (x_i − x_j)/r (zero for i = j).
Eigen::Vector2d kernel_gradient(const Eigen::Vector2d& xij, double h) {
  const double r = xij.norm();
  if (!(r > 0)) return Eigen::Vector2d::Zero();
  double dw = 0;
  kernel(r, h, &dw);
  return dw / r * xij;
}
}  // namespace

Eigen::VectorXd filtered_density(const Eigen::MatrixXd& x, const Eigen::VectorXd& volume,
                                 const Eigen::VectorXd& rho, double h, DensityFilter kind) {
  if (kind == DensityFilter::off) return rho;
  return filtered_density(Pairs(x, h), x, volume, rho, h, kind);
}

Eigen::VectorXd filtered_density(const Pairs& pairs, const Eigen::MatrixXd& x,
                                 const Eigen::VectorXd& volume, const Eigen::VectorXd& rho,
                                 double h, DensityFilter kind) {
  Eigen::VectorXd out = rho;
  if (kind == DensityFilter::off) return out;
  const Eigen::Index m = x.cols();
#pragma omp parallel for schedule(static) num_threads(pairs.threads) if (m > 2048)
  for (Eigen::Index i = 0; i < m; ++i) {
    double num = 0, den = 0;
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e) {
      const int j = pairs.index[e];
      const Eigen::Vector2d r = x.col(i) - x.col(j);
      const double wv = kernel(r.norm(), h) * volume[j];
      num += rho[j] * wv;
      den += wv;
      if (kind == DensityFilter::mls) {
        const Eigen::Vector3d p(1, r.x() / h, r.y() / h);
        A += wv * p * p.transpose();
      }
    }
    const double shepard = den > 0 ? num / den : rho[i];
    out[i] = shepard;
    if (kind != DensityFilter::mls) continue;
    // First order: (β0, β) from A β = e1, in coordinates over h; a singular A (a point at
    // the edge of a splash) keeps Shepard's value.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A, Eigen::EigenvaluesOnly);
    const Eigen::Vector3d lambda = eig.eigenvalues();
    if (!(lambda.minCoeff() > 1e-8 * lambda.maxCoeff())) continue;
    const Eigen::Vector3d beta = A.ldlt().solve(Eigen::Vector3d::UnitX());
    double s = 0;
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e) {
      const int j = pairs.index[e];
      const Eigen::Vector2d r = x.col(i) - x.col(j);
      const Eigen::Vector3d p(1, r.x() / h, r.y() / h);
      s += rho[j] * beta.dot(p) * kernel(r.norm(), h) * volume[j];
    }
    if (std::isfinite(s)) out[i] = s;
  }
  return out;
}

Eigen::MatrixXd density_gradient(const Pairs& pairs, const Eigen::MatrixXd& x,
                                 const Eigen::VectorXd& volume, const Eigen::VectorXd& rho,
                                 double h) {
  const Eigen::Index m = x.cols();
  Eigen::MatrixXd g(2, m);
#pragma omp parallel for schedule(static) num_threads(pairs.threads) if (m > 2048)
  for (Eigen::Index i = 0; i < m; ++i) {
    Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
    Eigen::Vector2d s = Eigen::Vector2d::Zero();
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e) {
      const int j = pairs.index[e];
      if (j == i) continue;
      const Eigen::Vector2d grad = kernel_gradient(x.col(i) - x.col(j), h) * volume[j];
      M += grad * (x.col(j) - x.col(i)).transpose();
      s += (rho[j] - rho[i]) * grad;
    }
    g.col(i) = M.determinant() > 0.1 ? Eigen::Vector2d(M.inverse() * s) : s;
  }
  return g;
}

Eigen::MatrixXd density_gradient(const Eigen::MatrixXd& x, const Eigen::VectorXd& volume,
                                 const Eigen::VectorXd& rho, double h) {
  return density_gradient(Pairs(x, h), x, volume, rho, h);
}

Eigen::VectorXd density_diffusion(const Pairs& pairs, const Eigen::MatrixXd& x,
                                  const Eigen::VectorXd& volume, const Eigen::VectorXd& rho,
                                  double h, double c0, double delta, DiffusionForm form) {
  const Eigen::Index m = x.cols();
  const Eigen::MatrixXd g = form == DiffusionForm::antuono
                                ? density_gradient(pairs, x, volume, rho, h)
                                : Eigen::MatrixXd::Zero(2, m);
  Eigen::VectorXd D = Eigen::VectorXd::Zero(m);
#pragma omp parallel for schedule(static) num_threads(pairs.threads) if (m > 2048)
  for (Eigen::Index i = 0; i < m; ++i) {
    double s = 0;
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e) {
      const int j = pairs.index[e];
      if (j == i) continue;
      const Eigen::Vector2d rji = x.col(j) - x.col(i);
      const double r2 = rji.squaredNorm();
      if (!(r2 > 0)) continue;
      const Eigen::Vector2d psi = 2 * (rho[j] - rho[i]) / r2 * rji - (g.col(i) + g.col(j));
      s += psi.dot(kernel_gradient(-rji, h)) * volume[j];
    }
    D[i] = delta * h * c0 * s;
  }
  return D;
}

Eigen::VectorXd density_diffusion(const Eigen::MatrixXd& x, const Eigen::VectorXd& volume,
                                  const Eigen::VectorXd& rho, double h, double c0, double delta,
                                  DiffusionForm form) {
  return density_diffusion(Pairs(x, h), x, volume, rho, h, c0, delta, form);
}

Eigen::VectorXd concentration(const Eigen::MatrixXd& x, double h, double dx) {
  const Pairs pairs(x, h);
  Eigen::VectorXd C = Eigen::VectorXd::Zero(x.cols());
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e)
      C[i] += kernel((x.col(i) - x.col(pairs.index[e])).norm(), h) * dx * dx;
  return C;
}

Eigen::MatrixXd shifts(const Eigen::MatrixXd& x, double h, double dx, double D, double surface,
                       const std::vector<char>& held, const Eigen::MatrixXd& wall_normal,
                       ShiftingForm form, double alpha) {
  const Pairs pairs(x, h);
  const Eigen::Index n = x.cols();
  // C_I and ∇C_I first: a particle near one below `surface` (its vicinity) shifts
  // tangentially as it does.
  Eigen::VectorXd C = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd gC = Eigen::MatrixXd::Zero(2, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e) {
      const Eigen::Vector2d xij = x.col(i) - x.col(pairs.index[e]);
      C[i] += kernel(xij.norm(), h) * dx * dx;
      gC.col(i) += kernel_gradient(xij, h) * dx * dx;
    }
  Eigen::MatrixXd dr = Eigen::MatrixXd::Zero(2, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (static_cast<std::size_t>(i) < held.size() && held[i]) continue;
    bool near_surface = false;
    for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1] && !near_surface; ++e)
      near_surface = C[pairs.index[e]] < surface;
    Eigen::Vector2d d = -D * h * h * gC.col(i);
    if (form == ShiftingForm::xu) {
      // r̄_I the mean neighbour distance; a pair closer than 1e-3 Δx counts at that distance.
      double mean = 0;
      int count = 0;
      for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e)
        if (pairs.index[e] != i) {
          mean += (x.col(i) - x.col(pairs.index[e])).norm();
          ++count;
        }
      d.setZero();
      if (count > 0) {
        mean /= count;
        for (int e = pairs.offsets[i]; e < pairs.offsets[i + 1]; ++e) {
          const int j = pairs.index[e];
          if (j == i) continue;
          const Eigen::Vector2d xij = x.col(i) - x.col(j);
          const double r = std::max(xij.norm(), 1e-3 * dx);
          const Eigen::Vector2d nij =
              xij.norm() > 0 ? Eigen::Vector2d(xij / xij.norm()) : Eigen::Vector2d::UnitX();
          d += D * alpha * mean * mean / (r * r) * nij;
        }
      }
    }
    if (near_surface && gC.col(i).norm() > 0) {
      const Eigen::Vector2d nrm = gC.col(i).normalized();
      d -= d.dot(nrm) * nrm;
    }
    if (wall_normal.cols() == n && !wall_normal.col(i).isZero()) {
      const Eigen::Vector2d nw = wall_normal.col(i).normalized();
      d -= d.dot(nw) * nw;
    }
    const double len = d.norm();
    if (len > kMaxShift * dx) d *= kMaxShift * dx / len;
    dr.col(i) = d;
  }
  return dr;
}

}  // namespace remedies

// ---- the engine's side (members of ExplicitDynamics) ----

void ExplicitDynamics::check_fluid_remedies() const {
  opt_.remedies.validate();
  const char* why = opt_.frame != KernelFrame::eulerian
                        ? "they act on the Eulerian kernel's F, which the Lagrangian kernel "
                          "recomputes from u at every step (give frame=eulerian)"
                    : dim_ != 2 ? "they are written for 2D models"
                    : opt_.order != ParticleOrder::as_given
                        ? "they need the given particle order (reorder=none)"
                        : nullptr;
  if (why)
    throw InputError(fmt::format("the fluid remedies (density_filter, density_diffusion, "
                                 "shifting) are not available here: {}",
                                 why));
  if (opt_.remedies.shifting > 0 && d_.quadrature.nodal_points < n_)
    throw InputError("shifting needs an integration point at every particle (a nodal or "
                     "stress-point rule: the velocity's Taylor correction reads the trial "
                     "gradient there); this method integrates on cells: give shifting=0");
}

Eigen::MatrixXd ExplicitDynamics::remedy_centres() const {
  if (opt_.kernel_centres == KernelCentres::interpolated && !d_.particle_values)
    return particle_positions();
  return X_ + Eigen::Map<const Eigen::MatrixXd>(u_.data(), dim_, n_);
}

Eigen::MatrixXd ExplicitDynamics::remedy_points(const Eigen::MatrixXd& centres) const {
  // As retabulate() places them: the particles' own points at the centres, the others carried
  // by the t = 0 trial values, X_q + Σ_J N_J(X_q) u_J.
  Eigen::MatrixXd xq = Xq_;
  const int nodal = d_.quadrature.nodal_points;
  const ShapeTable& t = values_at_points0_;
  const bool values = static_cast<int>(t.value.size()) == t.entries();
  for (int q = 0; q < nq_; ++q) {
    if (q < nodal) {
      xq.col(q) = centres.col(q);
      continue;
    }
    if (!values) continue;
    for (int e = t.offsets[q]; e < t.offsets[q + 1]; ++e)
      for (int c = 0; c < dim_; ++c) xq(c, q) += t.value[e] * u_[dim_ * t.index[e] + c];
  }
  return xq;
}

void ExplicitDynamics::apply_fluid_remedies(double dt) {
  const FluidRemedies& r = opt_.remedies;
  const long k = counters_.steps;
  const bool filter = r.filter != DensityFilter::off && k % r.filter_every == 0;
  const bool diffuse = r.diffusion > 0;
  const bool shift = r.shifting > 0 && k % opt_.update_every == 0;
  if (!filter && !diffuse && !shift) return;
  const double h = kRemedySmoothing * spacing_;
  const int dd = dim_ * dim_;
  // ρ_q = ρ_ref,q / J_q: the material's reference density slot, or the model's density.
  const std::vector<std::string> names = model_.material->state_names(dim_);
  const int ns = model_.material->state_size(dim_);
  const auto slot = std::find(names.begin(), names.end(), "reference_density");
  Eigen::VectorXd ref = Eigen::VectorXd::Constant(nq_, model_.density), rho(nq_), V(nq_);
  for (int q = 0; q < nq_; ++q) {
    if (slot != names.end()) ref[q] = state_[static_cast<std::size_t>(ns) * q + (slot - names.begin())];
    const double* F = F_.data() + dd * q;
    const double J = F[0] * F[3] - F[1] * F[2];
    rho[q] = ref[q] / J;
    V[q] = w0_[q] * J;
  }
  const Eigen::MatrixXd centres = remedy_centres();
  const Eigen::MatrixXd xq = remedy_points(centres);
  const remedies::Pairs pairs(xq, h, opt_.threads);
  Eigen::VectorXd target = rho;
  if (diffuse) {
    // Forward Euler in sub-steps (diffusion_substeps), the volumes following the density.
    const int m = remedies::diffusion_substeps(r.diffusion, h, wave_speed_, dt, spacing_);
    Eigen::VectorXd Vs = V;
    for (int k = 0; k < m; ++k) {
      target += dt / m *
                remedies::density_diffusion(pairs, xq, Vs, target, h, wave_speed_, r.diffusion,
                                            r.diffusion_form);
      if (k + 1 < m) Vs = V.cwiseProduct(rho).cwiseQuotient(target);
    }
  }
  if (filter) target = remedies::filtered_density(pairs, xq, V, target, h, r.filter);
  if (shift) {
    std::vector<char> held(n_, 0);
    for (const PrescribedVelocity& p : model_.prescribed)
      if (t_ < p.until) held[p.particle] = 1;
    // The rigid walls' normals at the particles within 2h of one (the nearest wall's).
    Eigen::MatrixXd normal;
    if (!model_.rigid_walls.empty()) {
      normal = Eigen::MatrixXd::Zero(2, n_);
      for (int I = 0; I < n_; ++I) {
        double best = 2 * h;
        for (const RigidWall& w : model_.rigid_walls) {
          const Eigen::Vector2d p = centres.col(I), off = p - w.nearest(p);
          if (off.norm() < best && off.norm() > 0) {
            best = off.norm();
            normal.col(I) = off / best;
          }
        }
      }
    }
    // Xu et al.'s α = U_max Δt over the time since the last move (update_every steps).
    double u_max = 0;
    for (int I = 0; I < n_; ++I) u_max = std::max(u_max, v_.segment<2>(2 * I).norm());
    const Eigen::MatrixXd dr =
        remedies::shifts(centres, h, spacing_, r.shifting, r.shifting_surface, held, normal,
                         r.shifting_form, u_max * dt * opt_.update_every);
    if (dr.cwiseAbs().maxCoeff() > 0) {
      // Lind et al.'s Taylor corrections: the velocity from the trial gradient at the
      // particle's own point (the tables of the last recomputation), the density from ⟨∇ρ⟩^L.
      const ShapeTable& t = d_.trial_q;
      Eigen::VectorXd dv = Eigen::VectorXd::Zero(dim_ * n_);
      for (int I = 0; I < n_; ++I) {
        if (dr.col(I).isZero()) continue;
        Eigen::Matrix2d G = Eigen::Matrix2d::Zero();
        for (int e = t.offsets[I]; e < t.offsets[I + 1]; ++e)
          G += v_.segment<2>(2 * t.index[e]) *
               Eigen::Map<const Eigen::Vector2d>(t.grad.data() + 2 * e).transpose();
        dv.segment<2>(2 * I) = G * dr.col(I);
      }
      const Eigen::MatrixXd grad_rho = remedies::density_gradient(pairs, xq, V, target, h);
      u_ += Eigen::Map<const Eigen::VectorXd>(dr.data(), dr.size());
      v_ += dv;
      apply_prescribed(t_, v_, a_);
      const Eigen::MatrixXd moved = remedy_points(remedy_centres());
      for (int q = 0; q < nq_; ++q) target[q] += grad_rho.col(q).dot(moved.col(q) - xq.col(q));
    }
  }
  // The new densities through the volumes: F ← (ρ/ρ̃)^{1/2} F, committed and current alike.
  for (int q = 0; q < nq_; ++q) {
    if (!(target[q] > 0) || !std::isfinite(target[q]) || target[q] == rho[q] || !(rho[q] > 0))
      continue;
    const double s = std::sqrt(rho[q] / target[q]);
    for (int e = 0; e < dd; ++e) {
      F_[dd * q + e] *= s;
      committed_F_[dd * q + e] *= s;
    }
  }
}

}  // namespace mfv
