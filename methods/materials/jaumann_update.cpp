/// The Hughes–Winget objective step of the Jaumann-rate materials (see jaumann_update.hpp).
#include "methods/materials/jaumann_update.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv::jaumann {

namespace {
// Off-diagonal τ slots after xx, yy, zz: (0,1), (1,2), (0,2).
constexpr int kOffRow[3] = {0, 1, 0}, kOffCol[3] = {1, 2, 2};
}  // namespace

std::vector<std::string> slot_names(int dim) {
  std::vector<std::string> names;
  for (int j = 0; j < dim; ++j)
    for (int i = 0; i < dim; ++i)
      names.push_back(i == j ? fmt::format("F{}{}_minus_1", i + 1, j + 1)
                             : fmt::format("F{}{}", i + 1, j + 1));
  const char* tau[] = {"tau_xx", "tau_yy", "tau_zz", "tau_xy", "tau_yz", "tau_xz"};
  for (int k = 0; k < Slots{dim}.tau_count(); ++k) names.push_back(tau[k]);
  return names;
}

void check_call(const char* material, int dim, const double* state) {
  if (dim < 1 || dim > 3)
    throw InputError(fmt::format("material '{}' works in 1D, 2D or 3D, not {}D", material, dim));
  if (!state)
    throw std::logic_error(
        fmt::format("material '{}' needs its history (state_size per point)", material));
}

void load(int dim, const double* s, const double* F, Eigen::Matrix3d& F_old,
          Eigen::Matrix3d& F_new, Eigen::Matrix3d& tau) {
  const Slots l{dim};
  const int nt = l.tau_count();
  F_old = Eigen::Matrix3d::Identity();
  F_new = F_old;
  for (int j = 0; j < dim; ++j)
    for (int i = 0; i < dim; ++i) {
      F_old(i, j) += s[l.f() + i + dim * j];
      F_new(i, j) = F[i + dim * j];
    }
  tau = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) tau(k, k) = s[l.tau() + k];
  for (int k = 3; k < nt; ++k)
    tau(kOffRow[k - 3], kOffCol[k - 3]) = tau(kOffCol[k - 3], kOffRow[k - 3]) = s[l.tau() + k];
}

void elastic_trial(const Eigen::Matrix3d& F_old, const Eigen::Matrix3d& F_new, double lambda,
                   double mu, Eigen::Matrix3d& tau) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d dL = (F_new - F_old) * (0.5 * (F_old + F_new)).inverse();
  const Eigen::Matrix3d dD = 0.5 * (dL + dL.transpose()), dW = 0.5 * (dL - dL.transpose());
  const Eigen::Matrix3d Q = (I - 0.5 * dW).inverse() * (I + 0.5 * dW);
  tau = Q * tau * Q.transpose() + lambda * dD.trace() * I + 2 * mu * dD;
}

void store(int dim, const Eigen::Matrix3d& F_new, const Eigen::Matrix3d& tau, double* P,
           double* s) {
  const Slots l{dim};
  const int nt = l.tau_count();
  const Eigen::Matrix3d P3 = tau * F_new.inverse().transpose();
  for (int j = 0; j < dim; ++j)
    for (int i = 0; i < dim; ++i) {
      P[i + dim * j] = P3(i, j);
      s[l.f() + i + dim * j] = F_new(i, j) - (i == j ? 1 : 0);
    }
  for (int k = 0; k < 3; ++k) s[l.tau() + k] = tau(k, k);
  for (int k = 3; k < nt; ++k)
    s[l.tau() + k] =
        0.5 * (tau(kOffRow[k - 3], kOffCol[k - 3]) + tau(kOffCol[k - 3], kOffRow[k - 3]));
}

}  // namespace mfv::jaumann
