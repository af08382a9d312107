#include "stability/dispersion.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "stability/critical_step.hpp"

namespace mfv {

namespace {

constexpr double kZero = 1e-7;  ///< |ω²| below this many (c π/Δx)² counts as zero

/// π/Δx: the unit wave numbers are reported in.
double kappa_unit(const BlochRow& row) { return std::numbers::pi / row.spacing; }
/// (c π/Δx)² with c² = modulus/ρ: the unit ω² is reported in.
double omega2_unit(const BlochRow& row, double modulus, double density) {
  return modulus / density * kappa_unit(row) * kappa_unit(row);
}
/// The unit wave direction θ (1D: +x).
Eigen::VectorXd direction(int dim, double theta) {
  Eigen::VectorXd dir(dim);
  if (dim == 1) dir << 1;
  else dir << std::cos(theta), std::sin(theta);
  return dir;
}
/// The lowest ω² branch at wave number k along dir, in units of `scale`.
double lowest(const BlochRow& row, double k, const Eigen::VectorXd& dir, double scale) {
  return row.omega2(k * dir)[0] / scale;
}

int round_half_width(LatticeKind kind, double w) {
  int hw = static_cast<int>(std::ceil(w - 1e-9));
  if (kind == LatticeKind::hexagonal && hw % 2 != 0) ++hw;
  return std::max(hw, 2);
}

Discretization discretize_patch(const Method& method, const LatticePatch& p) {
  Discretization d = method.discretize(p.domain, p.particles, 1);
  // The explicit engine's force tables span the particles only; enrichment unknowns (xefg's
  // crack) have no place in them, nor does a crack in an infinite periodic lattice.
  refuse_enrichment(d, "a lattice (dispersion, stretch-map) analysis");
  return d;
}

}  // namespace

BlochRow bloch_row(const Method& method, const DispersionSetup& s) {
  if (!s.material) throw InputError("a dispersion analysis needs a material");
  if (!(s.density > 0)) throw InputError(fmt::format("density {} must be positive", s.density));
  if (!(s.step > 0 && s.step < 1e-2))
    throw InputError(fmt::format("finite-difference step {} must lie in (0, 1e-2)", s.step));
  const double dx = s.spacing;
  const int dim = s.lattice == LatticeKind::line ? 1 : 2;
  for (const Eigen::MatrixXd* m : {&s.prestress, &s.deformation})
    if (m->size() != 0 && (m->rows() != dim || m->cols() != dim))
      throw InputError(fmt::format("the prestress and the deformation of a {} lattice must be "
                                   "{}×{} matrices",
                                   to_string(s.lattice), dim, dim));
  // 1. The reach of the operator: test support of the centre plus trial support of its
  //    points; the Eulerian kernel's tables at those points also move with their own
  //    neighbours (normalization, correction, volumes), one trial radius further.
  // The measured radius saturates at the probe's diameter when a support spans the whole
  // probe (it is then measured short, and the patch built from it would be too small): the
  // probe grows until the supports fit, up to 96 spacings on a line and 16 in 2D; a support
  // wider still is refused (radius=1e300 used to run for minutes on an all-to-all patch).
  const int max_probe = s.lattice == LatticeKind::line ? 96 : 16;
  double r_test = 0, r_trial = 0;
  for (int probe_half_width = s.lattice == LatticeKind::line ? 12 : 8;; probe_half_width *= 2) {
    // Supports are the same everywhere on a lattice, so the tables' largest point–particle
    // distances are the centre's. A point's own neighbours (trial or test) set how far its
    // tables move when the particles do.
    const LatticePatch probe = lattice_patch(s.lattice, dx, probe_half_width);
    const Discretization d = discretize_patch(method, probe);
    r_test = table_radius(d.test_q, d.quadrature.points, d.particles.x);
    r_trial = std::max(table_radius(d.trial_q, d.quadrature.points, d.particles.x), r_test);
    const double diameter =
        (probe.particles.x.rowwise().maxCoeff() - probe.particles.x.rowwise().minCoeff()).norm();
    if (r_trial < 0.95 * diameter) break;
    if (2 * probe_half_width > max_probe)
      throw InputError(fmt::format("the method's supports reach at least {:.3g} spacings, across "
                                   "the whole {}-spacing probe patch they are measured on; use a "
                                   "smaller support (dmax, radius, j, bands)",
                                   r_trial / dx, 2 * probe_half_width));
  }
  if (!(r_test > 0))
    throw InputError("the method's test function of the centre particle samples no point, so "
                     "there is nothing to analyse: its support is too small for the lattice; "
                     "raise it (dmax, radius, j)");
  double reach = r_test + r_trial;
  if (s.frame == KernelFrame::eulerian) reach += r_trial;
  // 2. A patch whose centre sees only interior particles: every point within reach of the
  //    centre has its whole (trial) support and Voronoi cells inside.
  // Checked before the conversion to int: a huge support (radius=1e300) would overflow it,
  // and a patch past 500 spacings (10^6 particles in 2D) is beyond what the analysis can hold.
  constexpr double kMaxHalfWidth = 500;
  const double wanted = (reach + r_trial) / dx + 2;
  if (!(wanted <= kMaxHalfWidth))
    throw InputError(fmt::format("the method's supports reach {:.3g} spacings, so the lattice patch "
                                 "would need a half width of {:.3g} spacings, more than the {} the "
                                 "analysis builds; use a smaller support (dmax, radius, j)",
                                 reach / dx, wanted, kMaxHalfWidth));
  const int needed = round_half_width(s.lattice, wanted);
  if (s.half_width > 0 && s.half_width < needed)
    throw InputError(fmt::format("half_width {} is smaller than the {} spacings the method's "
                                 "supports reach; leave it 0 (automatic) or use {} or more",
                                 s.half_width, needed, needed));
  // The row by translation differentiates the forces at every P within reach of the centre,
  // so each of those needs the interior the centre needs: one reach more.
  const double wanted_translated = (2 * reach + r_trial) / dx + 2;
  const int needed_translated = wanted_translated <= kMaxHalfWidth
                                    ? round_half_width(s.lattice, wanted_translated)
                                    : std::numeric_limits<int>::max();
  const int hw = s.half_width > 0 ? round_half_width(s.lattice, s.half_width)
                 : s.by_translation && needed_translated <= kMaxHalfWidth ? needed_translated
                                                                          : needed;
  const bool translate = s.by_translation && hw >= needed_translated;
  const LatticePatch patch = lattice_patch(s.lattice, dx, hw);
  Discretization d = discretize_patch(method, patch);
  BlochRow row;
  row.dim = dim;
  row.spacing = dx;
  row.lattice = s.lattice;
  row.half_width = hw;
  row.patch_particles = patch.particles.size();
  row.influence_radius = reach / dx;
  row.description = d.description;
  const int n = patch.particles.size(), c = patch.centre;
  const Eigen::MatrixXd X = patch.particles.x;
  row.lumped_mass = s.density * patch.particles.volume[c];
  // 3. The engine on the patch, moved to the deformed state if there is one.
  DynamicsModel model;
  model.material = s.material;
  model.density = s.density;
  model.mass = lumped_masses(patch.particles, s.density, MassLumping::volume);
  if (s.prestress.size()) model.initial_stress = s.prestress;
  DynamicsOptions opt;
  opt.frame = s.frame;
  opt.threads = 1;
  std::vector<int> neighbours;
  for (int J = 0; J < n; ++J)
    if ((X.col(J) - X.col(c)).norm() <= reach + 1e-9 * dx) neighbours.push_back(J);
  // The centre's row of the consistent mass from the t = 0 tables (the reference
  // configuration), the same matrix the critical-step analysis uses; its component blocks
  // are diagonal and equal, so component 0 stands for all.
  std::vector<double> mass_row;
  if (s.consistent_mass) {
    const Eigen::SparseMatrix<double> M =
        consistent_mass(d, s.density, free_unknowns(dim * n, {}));
    for (int J : neighbours) mass_row.push_back(M.coeff(dim * c, dim * J));
  }
  ExplicitDynamics engine(method, std::move(d), std::move(model), opt);
  if (s.deformation.size()) {
    const Eigen::MatrixXd H = s.deformation - Eigen::MatrixXd::Identity(dim, dim);
    Eigen::VectorXd u0(dim * n);
    for (int J = 0; J < n; ++J) u0.segment(dim * J, dim) = H * X.col(J);
    engine.displace(u0);
  }
  // 4. K_0J by central differences of the engine's force.
  const double eps = s.step * dx;
  Eigen::VectorXd du = Eigen::VectorXd::Zero(dim * n);
  // ∂f/∂u_{J,k}, the whole force vector: perturb one unknown both ways.
  const auto force_derivative = [&](int J, int k) -> Eigen::VectorXd {
    du[dim * J + k] = eps;
    const Eigen::VectorXd fp = engine.trial_force(du);
    du[dim * J + k] = -eps;
    const Eigen::VectorXd fm = engine.trial_force(du);
    du[dim * J + k] = 0;
    row.force_evaluations += 2;
    return (fp - fm) / (2 * eps);
  };
  // ∂f_at/∂u_J, dim × dim.
  const auto direct_block = [&](int J, int at) {
    Eigen::MatrixXd K(dim, dim);
    for (int k = 0; k < dim; ++k) K.col(k) = force_derivative(J, k).segment(dim * at, dim);
    return K;
  };
  for (int J : neighbours) row.offset.push_back(X.col(J) - X.col(c));
  if (translate) {
    // K_0J = K_{P,0}, X_P = X_0 − (X_J − X_0): the lattice and the uniform state are the same
    // seen from every particle, so the column of the centre's perturbation holds the row.
    Eigen::MatrixXd dforce(dim * n, dim);
    for (int k = 0; k < dim; ++k) dforce.col(k) = force_derivative(c, k);
    for (int J : neighbours) {
      const Eigen::VectorXd want = 2 * X.col(c) - X.col(J);
      int P = -1;
      for (int I = 0; I < n && P < 0; ++I)
        if ((X.col(I) - want).norm() <= 1e-9 * dx) P = I;
      if (P < 0) throw std::logic_error("bloch_row: a lattice patch that is not centrally symmetric");
      row.stiffness.push_back(dforce.middleRows(dim * P, dim));
    }
    // The check: direct differences at the farthest neighbour and at the nearest other one
    // (a discretization whose integration cells or supports are not the same from every
    // particle breaks the invariance there first).
    double largest = 0;
    for (const Eigen::MatrixXd& K : row.stiffness) largest = std::max(largest, K.cwiseAbs().maxCoeff());
    std::size_t far = 0, near = 0;
    for (std::size_t i = 0; i < neighbours.size(); ++i) {
      const double r = row.offset[i].norm();
      if (r > row.offset[far].norm()) far = i;
      if (neighbours[i] != c && (neighbours[near] == c || r < row.offset[near].norm())) near = i;
    }
    bool invariant = true;
    for (std::size_t i : {far, near}) {
      if (neighbours[i] == c) continue;
      const Eigen::MatrixXd K = direct_block(neighbours[i], c);
      if (!((K - row.stiffness[i]).cwiseAbs().maxCoeff() <= 1e-6 * largest)) invariant = false;
    }
    if (invariant) {
      row.translated = true;
    } else {
      row.stiffness.clear();
    }
  }
  if (!row.translated)
    for (int J : neighbours) row.stiffness.push_back(direct_block(J, c));
  row.mass = std::move(mass_row);
  return row;
}

std::vector<double> BlochRow::omega2(const Eigen::VectorXd& kappa, double* imaginary) const {
  using cd = std::complex<double>;
  Eigen::MatrixXcd D = Eigen::MatrixXcd::Zero(dim, dim);
  cd M = mass.empty() ? cd(lumped_mass) : cd(0);
  for (std::size_t J = 0; J < offset.size(); ++J) {
    const cd phase = std::exp(cd(0, kappa.dot(offset[J])));
    D += stiffness[J].cast<cd>() * phase;
    if (!mass.empty()) M += mass[J] * phase;
  }
  std::vector<double> out;
  double im = 0;
  if (dim == 1) {
    const cd w = D(0, 0) / M;
    out.push_back(w.real());
    im = std::abs(w.imag());
  } else {
    Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(D / M, false);
    for (int k = 0; k < dim; ++k) {
      out.push_back(es.eigenvalues()[k].real());
      im = std::max(im, std::abs(es.eigenvalues()[k].imag()));
    }
  }
  std::sort(out.begin(), out.end());
  if (imaginary) *imaginary = im;
  return out;
}

BlochRow BlochRow::combine(const BlochRow& a, const BlochRow& b, double s) {
  if (a.offset.size() != b.offset.size())
    throw std::logic_error("combining Bloch rows of different patches");
  BlochRow r = a;
  for (std::size_t J = 0; J < a.stiffness.size(); ++J)
    r.stiffness[J] = a.stiffness[J] + s * (b.stiffness[J] - a.stiffness[J]);
  return r;
}

DispersionBranch dispersion_branch(const BlochRow& row, double theta, int points,
                                   double modulus, double density) {
  if (points < 2) throw InputError(fmt::format("a branch needs at least 2 wave numbers, got {}", points));
  const double unit = kappa_unit(row), scale = omega2_unit(row, modulus, density);
  const double kmax = brillouin_boundary(row.lattice, row.spacing, theta);
  DispersionBranch b;
  b.theta = theta;
  const Eigen::VectorXd dir = direction(row.dim, theta);
  for (int i = 0; i < points; ++i) {
    const double k = kmax * i / (points - 1);
    double im = 0;
    std::vector<double> w = row.omega2(k * dir, &im);
    for (double& v : w) v /= scale;
    b.kappa.push_back(k / unit);
    b.omega2.push_back(std::move(w));
    b.imaginary.push_back(im / scale);
  }
  return b;
}

StabilityVerdict scan_stability(const std::vector<double>& thetas, int points, bool tension,
                                const std::function<double(double theta)>& zone_boundary,
                                const std::function<double(double kn, double theta)>& lowest) {
  if (thetas.empty()) throw InputError("a stability verdict needs at least one direction");
  const double pi = std::numbers::pi;
  StabilityVerdict v;
  double min_ratio = 1e300;
  for (std::size_t t = 0; t < thetas.size(); ++t) {
    const double theta = thetas[t];
    const double kmax = zone_boundary(theta);
    double prev = 0;
    bool found_onset = false;
    for (int i = 1; i < points; ++i) {
      const double kn = kmax * i / (points - 1);
      const double w = lowest(kn, theta);
      if (kn > 0.02) min_ratio = std::min(min_ratio, w / (kn * kn));
      if (w < -kZero && !found_onset) {
        found_onset = true;
        // Bisection on the sign of ω² between the last stable sample and this one.
        double lo = prev, hi = kn;
        for (int it = 0; it < 50; ++it) {
          const double mid = 0.5 * (lo + hi);
          (lowest(mid, theta) < -kZero ? hi : lo) = mid;
        }
        if (!v.unstable || hi < v.onset) {
          v.onset = hi;
          v.onset_theta = theta * 180 / pi;
        }
        v.unstable = true;
      } else if (std::abs(w) <= kZero && kn > 0.05 && !v.spurious) {
        v.spurious = true;
        v.spurious_kappa = kn;
        v.spurious_theta = theta * 180 / pi;
      }
      if (w >= -kZero) prev = kn;
      if (t == 0 && i == points - 1) v.cutoff_omega = std::sqrt(std::max(w, 0.0));
    }
  }
  v.min_ratio = min_ratio;
  if (v.unstable)
    v.text = fmt::format("{}unstable above κ = {:.3f} π/Δx (θ = {:g}°)", tension ? "tensile-" : "",
                         v.onset, v.onset_theta);
  if (v.spurious)
    v.text += fmt::format("{}spurious mode at κ = {:.3f} π/Δx (θ = {:g}°)",
                          v.text.empty() ? "" : "; ", v.spurious_kappa, v.spurious_theta);
  if (v.text.empty()) v.text = "stable";
  return v;
}

StabilityVerdict stability_verdict(const BlochRow& row, const std::vector<double>& thetas,
                                   int points, double modulus, double density, bool tension) {
  const double unit = kappa_unit(row), scale = omega2_unit(row, modulus, density);
  return scan_stability(
      thetas, points, tension,
      [&](double theta) { return brillouin_boundary(row.lattice, row.spacing, theta) / unit; },
      [&](double kn, double theta) {
        return lowest(row, kn * unit, direction(row.dim, theta), scale);
      });
}

ThresholdCurve stress_threshold(const BlochRow& unstressed, const BlochRow& stressed, double theta,
                                int points, double limit, double modulus, double density) {
  const double unit = kappa_unit(unstressed), scale = omega2_unit(unstressed, modulus, density);
  const double kmax = brillouin_boundary(unstressed.lattice, unstressed.spacing, theta);
  const Eigen::VectorXd dir = direction(unstressed.dim, theta);
  ThresholdCurve c;
  const int grid = 200;
  for (int i = 1; i < points; ++i) {
    const double k = kmax * i / (points - 1);
    // ω²/κ² (normalized): the same zero set as ω², with a tolerance that does not shrink
    // at long waves.
    const double kn2 = (k / unit) * (k / unit);
    auto h = [&](double sigma) {
      return lowest(BlochRow::combine(unstressed, stressed, sigma), k, dir, scale) / kn2;
    };
    auto edge = [&](double sign) {
      if (h(0) < -kZero) return std::numeric_limits<double>::quiet_NaN();
      double last = 0;
      for (int g = 1; g <= grid; ++g) {
        const double s = sign * limit * g / grid;
        if (h(s) < -kZero) {
          double lo = last, hi = s;
          for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (h(mid) < -kZero ? hi : lo) = mid;
          }
          return 0.5 * (lo + hi);
        }
        last = s;
      }
      return std::numeric_limits<double>::quiet_NaN();
    };
    c.kappa.push_back(k / unit);
    c.lower.push_back(edge(-1));
    c.upper.push_back(edge(+1));
  }
  return c;
}

}  // namespace mfv
