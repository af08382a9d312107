/// `kbm-ni`, `kbm-si`: Krongauz–Belytschko corrected derivatives (001 eqs 26–32) of MLS trial
/// functions with Shepard test functions, Petrov–Galerkin (001 §4.1.1), integrated at the
/// particles (ni) or at particles and stress points (si, eqs 63–65).
/// Eulerian recomputations with Retabulation::degenerate_fallback: where a point's support is
/// too small or collinear, the MLS trial values become Shepard values and the correction
/// a = I (plain Shepard gradient); an empty support gives a zero row (particle_gradients.hpp).
#include "methods/approximations/particle_gradients.hpp"
#include "methods/methods/register.hpp"
#include "methods/kernels/kernel_choice.hpp"

namespace mfv {

namespace {

void register_kbm_variant(MethodRegistry& r, const MethodParts& parts, const std::string& name,
                          const std::string& integration) {
  ParamSchema s = particle_method_schema(parts.kernels, true);
  if (integration == "stress-points")
    s.push_back(ParamSpec::choice("layout", "quad-centres", {"quad-centres", "triangle-centres"},
                                  "stress points at lattice quadrilateral or triangle centres "
                                  "(000 Fig. 8)"));
  r.add(name,
        fmt::format("Krongauz-Belytschko corrected gradients of MLS trial functions, Shepard test "
                    "functions (Petrov-Galerkin), {} integration (001 eqs 26-32, Table 1)",
                    integration == "nodal" ? "nodal" : integration == "gauss-cells" ? "Gauss-cell" : "stress-point"),
        s, [parts, integration](const Params& p) {
          ParticleRecipe g;
          g.integration = parts.integrations.create(
              integration,
              integration == "stress-points" ? forward(p, {{"layout", "layout"}}) : Params{});
          set_particle_dilation(p, parts.kernels, g.dilation_over_spacing, g.dilation);
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          const Params a = with_kernel({}, p);
          std::shared_ptr<const Approximation> shepard = parts.approximations.create("shepard", a);
          std::shared_ptr<const Approximation> mls = parts.approximations.create("mls", a);
          g.build = [shepard, mls](Discretization& d, int, Retabulation* cache) {
            const Eigen::MatrixXd& pts = d.quadrature.points;
            if (cache) {
              // Shepard and MLS share kernel and dilations, so one list serves both; the
              // three tables are at the same points, so one set of marks counts each once.
              DegenerateMarks marks;
              DegenerateMarks* degenerate = cache->degenerate_fallback ? &marks : nullptr;
              shepard->evaluate_into(d.particles, pts, 1, cache->at_points, cache->threads,
                                     d.test_q, degenerate);
              mls->evaluate_into(d.particles, pts, 0, cache->at_points, cache->threads,
                                 cache->kernel_table, degenerate);
              corrected_gradient(d.test_q, cache->kernel_table, d.particles, pts, d.trial_q,
                                 cache->threads, degenerate);
              cache->degenerate_points = marks.count();
            } else {
              ShapeTable test = shepard->evaluate(d.particles, pts, 1);
              d.trial_q =
                  corrected_gradient(test, mls->evaluate(d.particles, pts, 0), d.particles, pts);
              d.test_q = std::move(test);
            }
            d.trial = mls;
            d.test = shepard;
            d.form = Form::petrov_galerkin;
          };
          g.description = fmt::format(
              "KBM: MLS trial, corrected gradient, Shepard test, {} kernel, support {}, {}{}, "
              "bc={}",
              p.text("kernel"),
              support_text(p),
              integration, integration == "stress-points" ? " " + p.text("layout") : "",
              p.text("bc"));
          // Shepard tests are not linearly complete: only a quadrature exact for them meets the
          // second divergence identity. Gauss cells leave a small fixed defect (the 1D
          // reference stalls near 1e-4 with 6 points per cell), nodal and stress-point sums a
          // large one (issue 43).
          g.formal = formal_order_of(
              p, true, false, false,
              integration == "gauss-cells"
                  ? "the Shepard tests (not linearly complete) meet the second divergence "
                    "identity only under exact quadrature; Gauss cells leave a small fixed "
                    "defect (issue 43); vci=quadratic declares 2 / 1"
                  : "the Shepard tests (not linearly complete) miss both divergence identities "
                    "under nodal and stress-point sums (issue 43; 001 claims close to 2 for "
                    "si); vci=quadratic declares 2 / 1");
          return vci_if_asked(p, make_particle_method(std::move(g)));
        });
}

}  // namespace

void register_kbm(MethodRegistry& r, const MethodParts& parts) {
  register_kbm_variant(r, parts, "kbm-ni", "nodal");
  register_kbm_variant(r, parts, "kbm-si", "stress-points");
  // Not in 001: the same method on Gauss cells, which isolates the effect of the quadrature.
  register_kbm_variant(r, parts, "kbm-ci", "gauss-cells");
}

}  // namespace mfv
