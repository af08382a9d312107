/// Closed forms of the thick-walled cylinder and the 1D axisymmetric ring (thick_cylinder.hpp).
#include "dynamics/thick_cylinder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

void check_finite(double x, const char* name) {
  if (!std::isfinite(x))
    throw InputError(fmt::format("thick cylinder: {} = {} is not a finite number; give a real value",
                                 name, x));
}

void check_radii(double a, double b) {
  check_finite(a, "inner radius a");
  check_finite(b, "outer radius b");
  if (a <= 0)
    throw InputError(fmt::format("thick cylinder: inner radius a = {} must be positive; give e.g. "
                                 "a = 0.1 (m)",
                                 a));
  if (b <= a)
    throw InputError(fmt::format("thick cylinder: outer radius b = {} must exceed the inner radius "
                                 "a = {}; give b > a",
                                 b, a));
}

void check_in_wall(double r, double a, double b, const char* name) {
  check_finite(r, name);
  if (r < a || r > b)
    throw InputError(fmt::format("thick cylinder: {} = {} lies outside the wall [{}, {}]; give a "
                                 "radius between the inner and outer radius",
                                 name, r, a, b));
}

void check_positive(double x, const char* name) {
  check_finite(x, name);
  if (x <= 0)
    throw InputError(fmt::format("thick cylinder: {} = {} must be positive", name, x));
}

void check_poisson(double nu) {
  check_finite(nu, "Poisson's ratio nu");
  if (nu <= -1 || nu >= 0.5)
    throw InputError(fmt::format("thick cylinder: Poisson's ratio nu = {} is outside (-1, 0.5); "
                                 "give e.g. 0.3",
                                 nu));
}

}  // namespace

double lame_sigma_rr(double p, double a, double b, double r) {
  check_finite(p, "pressure p");
  check_radii(a, b);
  check_in_wall(r, a, b, "radius r");
  return p * a * a * (1 - b * b / (r * r)) / (b * b - a * a);
}

double lame_sigma_tt(double p, double a, double b, double r) {
  check_finite(p, "pressure p");
  check_radii(a, b);
  check_in_wall(r, a, b, "radius r");
  return p * a * a * (1 + b * b / (r * r)) / (b * b - a * a);
}

double lame_sigma_zz(double p, double a, double b, double r, double nu) {
  check_poisson(nu);
  return nu * (lame_sigma_rr(p, a, b, r) + lame_sigma_tt(p, a, b, r));
}

double lame_displacement(double p, double a, double b, double r, double E, double nu) {
  check_finite(p, "pressure p");
  check_radii(a, b);
  check_in_wall(r, a, b, "radius r");
  check_positive(E, "Young's modulus E");
  check_poisson(nu);
  return (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
}

double first_yield_pressure(double yield_stress, double a, double b, double nu) {
  check_positive(yield_stress, "yield stress");
  check_radii(a, b);
  check_poisson(nu);
  const double k = a * a / (b * b);
  return yield_stress * (1 - k) / std::sqrt(3 + (1 - 2 * nu) * (1 - 2 * nu) * k * k);
}

double hill_pressure(double yield_stress, double a, double b, double c) {
  check_positive(yield_stress, "yield stress");
  check_radii(a, b);
  check_in_wall(c, a, b, "plastic radius c");
  return yield_stress / std::sqrt(3.0) * (2 * std::log(c / a) + 1 - c * c / (b * b));
}

double hill_collapse_pressure(double yield_stress, double a, double b) {
  check_positive(yield_stress, "yield stress");
  check_radii(a, b);
  return 2 / std::sqrt(3.0) * yield_stress * std::log(b / a);
}

double slip_line_angle(double r, double a, double theta0, int branch) {
  check_positive(a, "inner radius a");
  check_positive(r, "radius r");
  check_finite(theta0, "theta0");
  if (branch != 1 && branch != -1)
    throw InputError(fmt::format("slip line: branch = {} must be +1 or -1 (the two families)",
                                 branch));
  return theta0 + branch * std::log(r / a);
}

// --- AxisymmetricRing ----------------------------------------------------------------------------

namespace {

/// Gauss points ξ = ∓1/√3 on [−1, 1]: N1 = (1 − ξ)/2, N2 = (1 + ξ)/2.
constexpr double gauss_xi[AxisymmetricRing::points_per_element] = {-0.57735026918962576,
                                                                   0.57735026918962576};

constexpr int max_elements = 1000000;

}  // namespace

AxisymmetricRing::AxisymmetricRing(ThickCylinder cylinder) : cyl_(std::move(cylinder)) {
  check_radii(cyl_.inner, cyl_.outer);
  if (cyl_.elements < 1 || cyl_.elements > max_elements)
    throw InputError(fmt::format("thick cylinder: elements = {} must be between 1 and {}; give "
                                 "e.g. 40 elements through the wall",
                                 cyl_.elements, max_elements));
  check_finite(cyl_.density, "density");
  if (cyl_.density <= 0)
    throw InputError(fmt::format("thick cylinder: density = {} must be positive; give the mass "
                                 "density in kg/m^3, e.g. 7800",
                                 cyl_.density));
  if (!cyl_.material)
    throw InputError("thick cylinder: no material; give one from the material registry");
  if (!std::isfinite(cyl_.viscosity.alpha) || !std::isfinite(cyl_.viscosity.beta) ||
      cyl_.viscosity.alpha < 0 || cyl_.viscosity.beta < 0)
    throw InputError(fmt::format("thick cylinder: artificial viscosity alpha = {}, beta = {} must "
                                 "be non-negative and finite; give e.g. alpha = 0.5, beta = 1 or "
                                 "zeros for none",
                                 cyl_.viscosity.alpha, cyl_.viscosity.beta));
  if (!cyl_.pressure)
    throw InputError("thick cylinder: no pressure history; give p(t), e.g. [](double) { return "
                     "1e6; }");

  const int ne = cyl_.elements, nn = ne + 1, nq = points_per_element * ne;
  const double a = cyl_.inner, h = (cyl_.outer - cyl_.inner) / ne;
  R_.resize(nn);
  for (int i = 0; i < nn; ++i) R_(i) = i == ne ? cyl_.outer : a + i * h;
  u_ = v_ = a_ = f_int_ = Eigen::VectorXd::Zero(nn);
  // Lumped (row-sum) masses per radian: ρ ∫ N_i R dR = ρ h (2R_i + R_j)/6 on each element.
  mass_ = Eigen::VectorXd::Zero(nn);
  point_R_.resize(nq);
  point_w_.resize(nq);
  for (int e = 0; e < ne; ++e) {
    const double R1 = R_(e), R2 = R_(e + 1), he = R2 - R1;
    mass_(e) += cyl_.density * he * (2 * R1 + R2) / 6;
    mass_(e + 1) += cyl_.density * he * (R1 + 2 * R2) / 6;
    for (int g = 0; g < points_per_element; ++g) {
      const double xi = gauss_xi[g];
      const int q = points_per_element * e + g;
      point_R_(q) = 0.5 * (1 - xi) * R1 + 0.5 * (1 + xi) * R2;
      point_w_(q) = 0.5 * he * point_R_(q);  // Gauss weight 1 × Jacobian he/2 × the R of R dR
    }
  }
  F_.assign(4 * nq, 0.0);
  P_.assign(4 * nq, 0.0);
  state_.assign(static_cast<std::size_t>(cyl_.material->state_size(2)) * nq, 0.0);
  cyl_.material->initial_state(2, nq, state_.data());
  compute_forces(0);
  a_ = ((-f_int_).array() / mass_.array()).matrix();
  a_(0) += f_ext_ / mass_(0);
}

double AxisymmetricRing::pressure_at(double t) const {
  const double p = cyl_.pressure(t);
  if (!std::isfinite(p))
    throw InputError(fmt::format("thick cylinder: the pressure history returned {} at t = {:g} s; "
                                 "give a finite p(t)",
                                 p, t));
  return p;
}

void AxisymmetricRing::compute_forces(double dt) {
  const int ne = cyl_.elements, nq = points_per_element * ne;
  for (int e = 0; e < ne; ++e) {
    const double he = R_(e + 1) - R_(e);
    const double r1 = R_(e) + u_(e), r2 = R_(e + 1) + u_(e + 1);
    const double lambda_r = (r2 - r1) / he;
    for (int g = 0; g < points_per_element; ++g) {
      const int q = points_per_element * e + g;
      const double xi = gauss_xi[g];
      const double lambda_t = (0.5 * (1 - xi) * r1 + 0.5 * (1 + xi) * r2) / point_R_(q);
      if (!(lambda_r > 0) || !(lambda_t > 0))
        throw SingularError(fmt::format(
            "thick cylinder: element {} of {} inverted at t = {:g} s (lambda_r = {:g}, lambda_theta "
            "= {:g}); lower the pressure or the time step",
            e, ne, t_, lambda_r, lambda_t));
      double* F = F_.data() + 4 * q;  // column-major 2×2: F11, F21, F12, F22
      F[0] = lambda_r;
      F[1] = F[2] = 0;
      F[3] = lambda_t;
    }
  }
  cyl_.material->first_piola(2, nq, F_.data(), P_.data(), state_.data(), dt);
  if (cyl_.viscosity.enabled()) add_viscosity();
  f_int_.setZero();
  for (int e = 0; e < ne; ++e) {
    const double he = R_(e + 1) - R_(e);
    for (int g = 0; g < points_per_element; ++g) {
      const int q = points_per_element * e + g;
      const double xi = gauss_xi[g];
      const double Prr = P_[4 * q], Ptt = P_[4 * q + 3], Rq = point_R_(q), w = point_w_(q);
      if (!std::isfinite(Prr) || !std::isfinite(Ptt))
        throw SingularError(fmt::format("thick cylinder: the stress went non-finite at t = {:g} s "
                                        "in element {} of {}; lower the time step or the load",
                                        t_, e, ne));
      f_int_(e) += w * (-Prr / he + Ptt * 0.5 * (1 - xi) / Rq);
      f_int_(e + 1) += w * (Prr / he + Ptt * 0.5 * (1 + xi) / Rq);
    }
  }
  f_ext_ = pressure_at(t_) * inner_radius();
}

void AxisymmetricRing::add_viscosity() {
  const double c = cyl_.material->wave_speed(2, cyl_.density);
  const double alpha = cyl_.viscosity.alpha, beta = cyl_.viscosity.beta;
  for (int e = 0; e < cyl_.elements; ++e) {
    const double he = R_(e + 1) - R_(e);
    for (int g = 0; g < points_per_element; ++g) {
      const int q = points_per_element * e + g;
      const double xi = gauss_xi[g];
      const double lambda_r = F_[4 * q], lambda_t = F_[4 * q + 3], J = lambda_r * lambda_t;
      const double rate_r = (v_(e + 1) - v_(e)) / he,
                   rate_t = (0.5 * (1 - xi) * v_(e) + 0.5 * (1 + xi) * v_(e + 1)) / point_R_(q);
      const double div = rate_r / lambda_r + rate_t / lambda_t;
      if (div >= 0) continue;
      const double visc = cyl_.density / J * (beta * he * he * div * div - alpha * c * he * div);
      // P_v = −q J F⁻ᵀ, diagonal here.
      P_[4 * q] -= visc * lambda_t;
      P_[4 * q + 3] -= visc * lambda_r;
    }
  }
}

void AxisymmetricRing::step(double dt) {
  if (!std::isfinite(dt) || dt <= 0)
    throw InputError(fmt::format("thick cylinder: time step dt = {} must be positive and finite; "
                                 "take a fraction of critical_time_step()",
                                 dt));
  const Eigen::VectorXd f_int_old = f_int_;
  const double f_ext_old = f_ext_;
  v_ += 0.5 * dt * a_;
  const Eigen::VectorXd du = dt * v_;
  u_ += du;
  t_ += dt;
  if (!du.allFinite())
    throw SingularError(fmt::format("thick cylinder: the displacement went non-finite at t = {:g} "
                                    "s; lower the time step",
                                    t_));
  compute_forces(dt);
  external_work_ += 0.5 * (f_ext_old + f_ext_) * du(0);
  internal_work_ += 0.5 * (f_int_old + f_int_).dot(du);
  a_ = ((-f_int_).array() / mass_.array()).matrix();
  a_(0) += f_ext_ / mass_(0);
  v_ += 0.5 * dt * a_;
}

double AxisymmetricRing::critical_time_step() const {
  const int ne = cyl_.elements, nq = points_per_element * ne;
  // Forward differences of (P_rr, P_θθ) in (λ_r, λ_θ) on copies of the state, so that the
  // probe does not advance a history-dependent material.
  constexpr double delta = 1e-7;
  std::vector<double> Fr = F_, Ft = F_, P0(4 * nq), Pr(4 * nq), Pt(4 * nq);
  for (int q = 0; q < nq; ++q) {
    Fr[4 * q] += delta * F_[4 * q];
    Ft[4 * q + 3] += delta * F_[4 * q + 3];
  }
  std::vector<double> s = state_;
  cyl_.material->first_piola(2, nq, F_.data(), P0.data(), s.data());
  s = state_;
  cyl_.material->first_piola(2, nq, Fr.data(), Pr.data(), s.data());
  s = state_;
  cyl_.material->first_piola(2, nq, Ft.data(), Pt.data(), s.data());

  double dt = std::numeric_limits<double>::infinity();
  for (int e = 0; e < ne; ++e) {
    const double R1 = R_(e), R2 = R_(e + 1), he = R2 - R1;
    Eigen::Matrix2d K = Eigen::Matrix2d::Zero();
    for (int g = 0; g < points_per_element; ++g) {
      const int q = points_per_element * e + g;
      const double xi = gauss_xi[g], Rq = point_R_(q);
      const double hr = delta * F_[4 * q], ht = delta * F_[4 * q + 3];
      Eigen::Matrix2d D;
      D << (Pr[4 * q] - P0[4 * q]) / hr, (Pt[4 * q] - P0[4 * q]) / ht,
          (Pr[4 * q + 3] - P0[4 * q + 3]) / hr, (Pt[4 * q + 3] - P0[4 * q + 3]) / ht;
      const Eigen::Matrix2d Ds = 0.5 * (D + D.transpose());
      Eigen::Matrix2d B;  // rows: ∂λ_r/∂u_i, ∂λ_θ/∂u_i
      B << -1 / he, 1 / he, 0.5 * (1 - xi) / Rq, 0.5 * (1 + xi) / Rq;
      K += point_w_(q) * B.transpose() * Ds * B;
    }
    const double m1 = cyl_.density * he * (2 * R1 + R2) / 6,
                 m2 = cyl_.density * he * (R1 + 2 * R2) / 6;
    Eigen::Matrix2d A;  // M^{-1/2} K M^{-1/2}
    A << K(0, 0) / m1, K(0, 1) / std::sqrt(m1 * m2), K(1, 0) / std::sqrt(m1 * m2), K(1, 1) / m2;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> modes(A);
    const double lmax = modes.eigenvalues()(1);
    if (!std::isfinite(lmax))
      throw SingularError(fmt::format("thick cylinder: the tangent of element {} is not finite at "
                                      "t = {:g} s",
                                      e, t_));
    if (!(lmax > 0)) continue;
    const double omega = std::sqrt(lmax);
    // Damped central differences: Δt ≤ (2/ω)(√(1 + ξ²) − ξ), ξ = φᵀ M^{-1/2} C M^{-1/2} φ/(2ω)
    // the damping ratio of the element's highest mode φ, C = ∫ η B_divᵀ B_div R dR the
    // viscosity linearized in the velocities, η = (ρ/J)(α c l + 2β l² |∇·v|) (a 1D element
    // gives ξ ≈ α + 2β l|∇·v|/c).
    double xi = 0;
    if (cyl_.viscosity.enabled()) {
      const double c = cyl_.material->wave_speed(2, cyl_.density);
      Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
      for (int g = 0; g < points_per_element; ++g) {
        const int q = points_per_element * e + g;
        const double gx = gauss_xi[g], lambda_r = F_[4 * q], lambda_t = F_[4 * q + 3];
        Eigen::RowVector2d b;  // ∂(∇·v)/∂v_i
        b << -1 / he / lambda_r + 0.5 * (1 - gx) / point_R_(q) / lambda_t,
            1 / he / lambda_r + 0.5 * (1 + gx) / point_R_(q) / lambda_t;
        const double div = b(0) * v_(e) + b(1) * v_(e + 1);
        const double eta = cyl_.density / (lambda_r * lambda_t) *
                           (cyl_.viscosity.alpha * c * he +
                            2 * cyl_.viscosity.beta * he * he * std::abs(div));
        C += point_w_(q) * eta * b.transpose() * b;
      }
      const Eigen::Vector2d phi = modes.eigenvectors().col(1);
      const Eigen::Vector2d phi_m(phi(0) / std::sqrt(m1), phi(1) / std::sqrt(m2));
      xi = phi_m.dot(C * phi_m) / (2 * omega);
    }
    dt = std::min(dt, 2 / omega / (std::sqrt(1 + xi * xi) + xi));
  }
  if (!std::isfinite(dt))
    throw SingularError(fmt::format("thick cylinder: the material has no stiffness at t = {:g} s, "
                                    "so no critical time step exists; check its parameters",
                                    t_));
  return dt;
}

double AxisymmetricRing::kinematic_time_step(double fraction) const {
  if (!std::isfinite(fraction) || fraction <= 0 || fraction >= 1)
    throw InputError(fmt::format("thick cylinder: stretch per step = {} must lie in (0, 1); "
                                 "give e.g. 0.1 of an element's length per step",
                                 fraction));
  double dt = std::numeric_limits<double>::infinity();
  for (int e = 0; e < cyl_.elements; ++e) {
    const double length = R_(e + 1) + u_(e + 1) - R_(e) - u_(e);
    const double dv = std::abs(v_(e + 1) - v_(e)), da = std::abs(a_(e + 1) - a_(e));
    // The positive root of ½ da dt² + dv dt − fraction·ℓ = 0, written without cancellation.
    const double reach = fraction * length;
    const double denominator = dv + std::sqrt(dv * dv + 2 * da * reach);
    if (denominator > 0) dt = std::min(dt, 2 * reach / denominator);
  }
  return dt;
}

Eigen::VectorXd AxisymmetricRing::point_radii() const {
  const int nq = points_per_element * cyl_.elements;
  Eigen::VectorXd r(nq);
  for (int q = 0; q < nq; ++q) r(q) = point_R_(q) * F_[4 * q + 3];
  return r;
}

Eigen::VectorXd AxisymmetricRing::sigma_rr() const {
  const int nq = points_per_element * cyl_.elements;
  Eigen::VectorXd s(nq);
  for (int q = 0; q < nq; ++q) s(q) = P_[4 * q] / F_[4 * q + 3];
  return s;
}

Eigen::VectorXd AxisymmetricRing::sigma_tt() const {
  const int nq = points_per_element * cyl_.elements;
  Eigen::VectorXd s(nq);
  for (int q = 0; q < nq; ++q) s(q) = P_[4 * q + 3] / F_[4 * q];
  return s;
}

double AxisymmetricRing::kinetic_energy() const {
  return 0.5 * (mass_.array() * v_.array().square()).sum();
}

RadiusHistory run_thick_cylinder(const ThickCylinder& cylinder, double end_time, double safety,
                                 const std::vector<double>& sample_times,
                                 double stretch_per_step) {
  if (!std::isfinite(end_time) || end_time <= 0)
    throw InputError(fmt::format("thick cylinder: end time = {} must be positive and finite",
                                 end_time));
  if (!std::isfinite(safety) || safety <= 0 || safety > 1)
    throw InputError(fmt::format("thick cylinder: safety = {} must lie in (0, 1]; give e.g. 0.8 "
                                 "of the critical time step",
                                 safety));
  for (std::size_t k = 0; k < sample_times.size(); ++k) {
    const double ts = sample_times[k];
    if (!std::isfinite(ts) || ts < 0 || ts > end_time || (k > 0 && ts < sample_times[k - 1]))
      throw InputError(fmt::format("thick cylinder: sample time {} = {} must be finite, in [0, "
                                   "end time {}] and not before the previous one",
                                   k, ts, end_time));
  }
  AxisymmetricRing ring(cylinder);
  RadiusHistory out;
  std::size_t next = 0;
  // Steps land on the sample times; one within 1e-12 of the end time of the current time counts
  // as reached (round-off of the sum of steps).
  const double eps = 1e-12 * end_time;
  const auto record = [&] {
    for (; next < sample_times.size() && sample_times[next] <= ring.time() + eps; ++next) {
      out.times.push_back(sample_times[next]);
      out.inner.push_back(ring.inner_radius());
      out.outer.push_back(ring.outer_radius());
    }
  };
  record();
  while (ring.time() < end_time - eps) {
    const double target = next < sample_times.size() ? sample_times[next] : end_time;
    const double dt = std::min(
        {safety * ring.critical_time_step(), ring.kinematic_time_step(stretch_per_step)});
    // A step collapsing toward zero (an element crushed ever faster, stiffening without bound)
    // would never reach the end: stop with the time instead of hanging.
    if (!(dt > 1e-9 * end_time))
      throw SingularError(fmt::format("thick cylinder: the time step collapsed to {:g} s at t = "
                                      "{:g} s ({} steps); the load crushes the wall, lower it",
                                      dt, ring.time(), out.steps));
    ring.step(std::min(dt, target - ring.time()));
    ++out.steps;
    record();
  }
  out.point_radii = ring.point_radii();
  out.sigma_rr = ring.sigma_rr();
  out.sigma_tt = ring.sigma_tt();
  out.kinetic_energy = ring.kinetic_energy();
  out.external_work = ring.external_work();
  out.internal_work = ring.internal_work();
  return out;
}

CylinderConvergence thick_cylinder_convergence(const ThickCylinder& cylinder, double end_time,
                                               double safety,
                                               const std::vector<double>& sample_times,
                                               int levels, double stretch_per_step) {
  if (levels < 2 || levels > 12)
    throw InputError(fmt::format("thick cylinder convergence: levels = {} must be between 2 and "
                                 "12 (each level doubles the elements)",
                                 levels));
  if (sample_times.empty())
    throw InputError("thick cylinder convergence: no sample times; give the times at which the "
                     "inner-radius histories are compared");
  CylinderConvergence out;
  for (int l = 0; l < levels; ++l) {
    ThickCylinder c = cylinder;
    const long n = static_cast<long>(cylinder.elements) << l;
    if (n > max_elements)
      throw InputError(fmt::format("thick cylinder convergence: level {} would need {} elements "
                                   "(more than {}); start coarser or use fewer levels",
                                   l, n, max_elements));
    c.elements = static_cast<int>(n);
    try {
      out.runs.push_back(run_thick_cylinder(c, end_time, safety, sample_times, stretch_per_step));
    } catch (const SingularError& e) {
      throw SingularError(fmt::format("thick cylinder convergence, {} elements: {}", n, e.what()));
    }
    out.elements.push_back(c.elements);
  }
  for (int l = 1; l < levels; ++l) {
    const RadiusHistory &coarse = out.runs[l - 1], &fine = out.runs[l];
    double d = 0;
    for (std::size_t k = 0; k < fine.inner.size(); ++k) {
      const double rel = std::abs(fine.inner[k] - coarse.inner[k]) / fine.inner[k];
      if (!std::isfinite(rel))
        throw SingularError(fmt::format("thick cylinder convergence: the inner radius at t = {:g} "
                                        "s is not finite ({} elements)",
                                        fine.times[k], out.elements[l]));
      d = std::max(d, rel);
    }
    out.differences.push_back(d);
  }
  return out;
}

}  // namespace mfv
