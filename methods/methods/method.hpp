/// Methods: named combinations of trial/test approximation, integration scheme and essential
/// boundary treatment. Following 001 Table 1, every method is read as two operators on its
/// integration points: the gradient of the field (deformation gradient) and the internal force
/// assembled from fluxes (stresses). Static solvers, explicit dynamics and stability analyses
/// all go through these two, so a method plugs into every analysis at once.
#pragma once
#include <memory>
#include <string>

#include <Eigen/Dense>

#include "methods/approximations/approximation.hpp"
#include "methods/core/registry.hpp"
#include "methods/integration/integration.hpp"
#include "methods/particles.hpp"

namespace mfv {

/// How the discrete equations are formed (001 §4).
enum class Form {
  galerkin,         ///< test = trial functions (Bubnov–Galerkin)
  petrov_galerkin,  ///< test functions differ (e.g. Shepard tests with corrected trials, KBM)
  collocation       ///< equations at particles (SPH): test functions are Dirac deltas
};

/// Essential boundary enforcement for non-interpolating approximations.
enum class EssentialBC { lagrange, penalty };

/// Everything a solver or analysis needs from a method on one particle set.
struct Discretization {
  ParticleSet particles;
  IntegrationRule quadrature;
  std::shared_ptr<const Approximation> trial, test;
  ShapeTable trial_q;  ///< trial shape functions at the quadrature points
  ShapeTable test_q;   ///< test shape functions there (same table for Galerkin)
  Form form = Form::galerkin;
  EssentialBC essential = EssentialBC::lagrange;
  double penalty = 1e8;       ///< penalty factor relative to the stiffness diagonal
  std::string description;    ///< resolved components, printed in reports

  /// Σ_J ∂N_J/∂x (x_q) u_J at every quadrature point: dim rows × nq (for a scalar field:
  /// the field gradient; for a vector field applied per component, the deformation gradient).
  Eigen::MatrixXd gradient(const Eigen::VectorXd& u) const;
  /// f_I = Σ_q w_q ∂N^test_I/∂x (x_q) · flux_q: the internal force from fluxes/stresses.
  Eigen::VectorXd internal_force(const Eigen::MatrixXd& flux) const;
  /// Values of the trial field at arbitrary points (errors, plots, VTK).
  ShapeTable trial_at(const Eigen::MatrixXd& points, int order) const;
};

class Method {
 public:
  virtual ~Method() = default;
  /// Sets particle dilations from the method's parameters, builds the quadrature and the
  /// shape function tables up to derivative `order` (the weak form's need).
  virtual Discretization discretize(const Domain& domain, ParticleSet particles,
                                    int order) const = 0;
};

using MethodRegistry = Registry<Method>;

/// A Galerkin (or Petrov–Galerkin) method assembled from registered parts.
struct GalerkinRecipe {
  std::shared_ptr<const Approximation> trial;
  std::shared_ptr<const Approximation> test;  ///< null: Bubnov–Galerkin
  std::shared_ptr<const IntegrationScheme> integration;
  double dilation_over_spacing = 1.0;  ///< a_J = this × Δx
  EssentialBC essential = EssentialBC::lagrange;
  double penalty = 1e8;
  std::string description;
};

std::unique_ptr<Method> make_galerkin_method(GalerkinRecipe recipe);

/// Parameters every Galerkin method shares: boundary enforcement and quadrature.
ParamSchema common_galerkin_schema(int default_gauss_points);
EssentialBC essential_from(const Params& p);

}  // namespace mfv
