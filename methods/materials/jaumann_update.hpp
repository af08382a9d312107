/// The objective step shared by the Jaumann-rate materials (j2-jaumann, j2-viscoplastic):
/// Hughes–Winget update of the Kirchhoff stress τ = F·P (001 eq 76 = 000 eq 5.2) from F_old to
/// F_new, ΔL = (F_new − F_old) F_mid⁻¹, F_mid = ½(F_old + F_new), DΔt = sym ΔL, WΔt = skew ΔL,
/// Q = (I − ½WΔt)⁻¹(I + ½WΔt), τ_trial = Q τ Qᵀ + λ tr(DΔt) I + 2μ DΔt, and P = τ F⁻ᵀ.
/// Q is exactly orthogonal and, for a rigid rotation, exactly the increment's rotation, so the
/// update is objective to round-off. 2D is plane strain (F33 = 1, τ33 kept), 1D uniaxial
/// strain (F = diag(F11, 1, 1)). The history of a point starts with F − I and τ (so that the
/// engine's zero fill means F = I, τ = 0); each material appends its own slots after them.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mfv::jaumann {

/// The shared history slots of one point: F − I (dim², column-major), then the symmetric τ
/// (xx, yy, zz, then xy, yz, xz as dim asks); a material's own slots start at end().
struct Slots {
  int dim;
  int f() const { return 0; }
  int tau() const { return dim * dim; }
  int tau_count() const { return 3 + dim * (dim - 1) / 2; }
  int end() const { return tau() + tau_count(); }
};

/// Names of the shared slots, in order (F11_minus_1, F21, ..., tau_xx, ...).
std::vector<std::string> slot_names(int dim);

/// Refuses dim outside 1..3 (InputError naming `material`) and a missing history (logic
/// error: the engine always passes state_size values per point).
void check_call(const char* material, int dim, const double* state);

/// Reads F_old and τ from the history `s` of one point and F_new from its dim×dim block `F`.
void load(int dim, const double* s, const double* F, Eigen::Matrix3d& F_old,
          Eigen::Matrix3d& F_new, Eigen::Matrix3d& tau);

/// τ ← Q τ Qᵀ + λ tr(DΔt) I + 2μ DΔt: the rotated elastic trial of the step F_old → F_new.
void elastic_trial(const Eigen::Matrix3d& F_old, const Eigen::Matrix3d& F_new, double lambda,
                   double mu, Eigen::Matrix3d& tau);

/// P = τ F_new⁻ᵀ into the dim×dim block `P`; F_new − I and τ into the history `s`.
void store(int dim, const Eigen::Matrix3d& F_new, const Eigen::Matrix3d& tau, double* P,
           double* s);

}  // namespace mfv::jaumann
