/// Problems of the catalogue: domain, weak form, exact solution and the published values
/// the reports print beside ours. One file per catalogue entry.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "methods/core/registry.hpp"
#include "methods/methods/method.hpp"

namespace mfv {

/// A linear system from a weak form, with essential conditions u(x_b) = g_b still to impose.
struct AssembledSystem {
  Eigen::SparseMatrix<double> K;
  Eigen::VectorXd f;
  Eigen::MatrixXd constraint_points;  ///< dim × nb
  Eigen::VectorXd constraint_values;  ///< g_b
};

/// A value printed in a paper, with what it must be matched against.
struct PublishedValue {
  std::string source;     ///< "004 II Table 1"
  std::string quantity;   ///< "peak du/dx at x=3", "error u"
  std::string method;     ///< method name it belongs to
  Params method_params;   ///< parameters that must match (subset)
  int nodes = 0;          ///< resolution
  double value = 0;
  std::string note;       ///< e.g. "norm not stated"
};

/// Resolutions per suite level.
enum class Level { quick, standard, full };

class Problem {
 public:
  virtual ~Problem() = default;
  virtual Domain domain() const = 0;
  /// Highest derivative of the shape functions the weak form needs.
  virtual int derivative_order() const { return 1; }
  /// Exact solution and its derivative at the columns of x (scalar field, 1D).
  virtual void exact(const Eigen::MatrixXd& x, Eigen::VectorXd& u, Eigen::VectorXd& du) const = 0;
  virtual AssembledSystem assemble(const Discretization& d) const = 0;
  /// Node counts of a refinement study.
  virtual std::vector<int> resolutions(Level level) const = 0;
  /// Problem-specific headline quantities of a solution (name → value), e.g. peak u'.
  virtual std::map<std::string, double> headline(const Discretization& d,
                                                 const Eigen::VectorXd& u) const {
    return {};
  }
  /// Exact values of the headline quantities (for the reports).
  virtual std::map<std::string, double> headline_exact() const { return {}; }
  virtual std::vector<PublishedValue> published() const { return {}; }
  /// What the reports say about the published values: known misprints, ambiguous readings
  /// and the best explanation of a gap (Markdown paragraphs). Numbers stay in the tables.
  virtual std::vector<std::string> published_notes() const { return {}; }
  /// Gauss points per cell between particles used by the paper for error norms.
  virtual int paper_error_points() const { return 12; }
};

using ProblemRegistry = Registry<Problem>;

void register_laplace_tanh(ProblemRegistry&);
void register_advection_diffusion(ProblemRegistry&);

/// Registers every problem: add one line here for a new one.
inline void register_all_problems(ProblemRegistry& r) {
  register_laplace_tanh(r);
  register_advection_diffusion(r);
}

/// Shared 1D assembly of ∫ (k w' u' + c w u' + τ R(w) R(u)) - ∫ w f (+ τ R(w) f) used by both
/// 1D problems; R(v) = -v'' + c v' is the residual operator of the stabilized form (004 I eq 6.3).
struct ScalarForm1D {
  double diffusion = 1.0;
  double advection = 0.0;
  double tau = 0.0;
};
AssembledSystem assemble_scalar_1d(const Discretization& d, const ScalarForm1D& form,
                                   const std::function<double(double)>& source);

}  // namespace mfv
