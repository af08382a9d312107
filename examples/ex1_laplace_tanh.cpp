/// Example 1: solve laplace-tanh with RKPM step by step and check the peak gradient.
/// Reads as the numbered steps every case of the suite goes through (verify/runner.cpp does
/// the same with timings); runs in well under a second and doubles as a test.
#include <cmath>
#include <cstdio>

#include "apps/catalogue.hpp"
#include "analyses/norms.hpp"
#include "analyses/static_solve.hpp"
#include "verify/runner.hpp"

int main() {
  using namespace mfv;
  // 1. The catalogue: every kernel, approximation, integration scheme, method and problem.
  const Catalogue catalogue;

  // 2. The problem: -u'' = f on [0, 6] with u = tanh(10 (x - 3)) (004 II §7).
  const auto problem = catalogue.problems.create_as<BoundaryValueProblem>("laplace-tanh", Params::parse("s=10"));

  // 3. The method by name and parameters: RKPM, Gaussian window, dilation index j = 1.
  const auto method = catalogue.methods.create("rkpm", Params::parse("kernel=gaussian,j=1"));

  // 4. Particles: 81 uniformly spaced on the domain.
  const Domain domain = problem->domain();
  ParticleSet particles = uniform_line(domain, 81, 0.0);

  // 5. Discretize: dilations, quadrature and shape functions at the quadrature points.
  const Discretization d = method->discretize(domain, std::move(particles),
                                              problem->derivative_order());

  // 6. Assemble the weak form and 7. solve with the essential conditions imposed.
  const AssembledSystem system = problem->assemble(d);
  SolveInfo info;
  const Eigen::VectorXd u = solve_constrained(system, d, info);

  // 8. Errors on a rule independent of the method, and the headline quantity.
  const ErrorNorms e = error_norms(*problem, d, u, common_error_rule(domain, 81));
  const double peak = problem->headline(d, u).at("peak du/dx at x=3");
  std::printf("%s\nrelative L2 error %.3e, H1 seminorm %.3e, peak u'(3) = %.5f (exact 10)\n",
              d.description.c_str(), e.l2_rel, e.h1_semi_rel, peak);

  // 9. Check: a Gaussian window with j = 1 resolves the layer at 81 nodes to well under 1%.
  const bool ok = e.l2_rel < 1e-3 && std::abs(peak - 10) < 0.2 && info.residual < 1e-10;
  std::printf("%s\n", ok ? "ok" : "FAILED: error or peak outside the expected range");
  return ok ? 0 : 1;
}
