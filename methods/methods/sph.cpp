/// `sph`: symmetrized SPH with collocation at the particles (001 Table 1 row SPH, eq 25), and
/// `sph-galerkin`: Galerkin with the uncorrected SPH kernel estimate (004 II Fig. 3).
/// Degenerate supports (Retabulation::degenerate_fallback): `sph` divides by no kernel sum and
/// every particle lies in its own support, so it never needs the fallback; `sph-galerkin`'s
/// points with an empty support get a zero row (CorrectedKernelApproximation).
#include "methods/approximations/particle_gradients.hpp"
#include "methods/methods/register.hpp"
#include "methods/kernels/kernel_choice.hpp"

namespace mfv {

std::unique_ptr<Method> make_collocation_method(const MethodParts& parts, const Params& p,
                                                const std::string& name,
                                                const CollocationTables& tables) {
  ParticleRecipe g;
  g.integration = parts.integrations.create("nodal");
  set_particle_dilation(p, parts.kernels, g.dilation_over_spacing, g.dilation);
  const Params a = with_kernel({}, p);
  std::shared_ptr<const Approximation> sph = parts.approximations.create("sph", a);
  std::shared_ptr<const Approximation> mls = parts.approximations.create("mls", a);
  g.build = [sph, mls, tables](Discretization& d, int, Retabulation* cache) {
    if (cache) {
      // The kernel sums and the gradients are at the particles: one set of marks.
      DegenerateMarks marks;
      DegenerateMarks* degenerate = cache->degenerate_fallback ? &marks : nullptr;
      sph->evaluate_into(d.particles, d.particles.x, 1, cache->at_particles, cache->threads,
                         cache->kernel_table, degenerate);
      tables(cache->kernel_table, d.particles, d, cache->threads, degenerate);
      cache->degenerate_points = marks.count();
    } else {
      ShapeTable kernel = sph->evaluate(d.particles, d.particles.x, 1);
      tables(kernel, d.particles, d, 1, nullptr);
    }
    d.trial = mls;  // reconstruction of the particle values between particles
    d.test = sph;
    d.form = Form::collocation;
    d.particle_values = true;
  };
  g.description = fmt::format(
      "{}, {} kernel, support {}; particle values fixed directly at essential boundaries; "
      "fields between particles: linear MLS fit",
      name, p.text("kernel"), support_text(p));
  // Randles-Libersky's B makes the gradient linearly consistent; plain SPH's is not.
  const bool linear = name.find("Randles") != std::string::npos;
  g.formal = formal_order_of(p, linear, false, false,
                             "collocation at the particles: no Galerkin identity to meet (vci=quadratic "
                             "declares 2 / 1)");
  return vci_if_asked(p, make_particle_method(std::move(g)));
}

void register_sph(MethodRegistry& r, const MethodParts& parts) {
  r.add("sph",
        "symmetrized SPH, collocation at the particles: F_I = Σ V_J (u_J - u_I) ⊗ ∇W_IJ, "
        "f_I = -V_I Σ V_J (σ_J + σ_I)·∇W_IJ (001 Table 1, eq 25); no boundary treatment",
        particle_method_schema(parts.kernels, false), [parts](const Params& p) {
          return make_collocation_method(
              parts, p, "symmetrized SPH collocation",
              // No correction, nothing to invert: every particle lies in its own support, so
              // the kernel sums never fall back and a degenerate support needs no fallback.
              [](ShapeTable& sph, const ParticleSet&, Discretization& d, int threads,
                 DegenerateMarks*) {
                // The kernel table becomes the gradient table in place (its rows are the
                // same): no copy of the rows per Eulerian recomputation, and the previous
                // gradient table's storage goes back to the cache for the next kernel table.
                std::swap(sph, d.trial_q);
                sph_symmetric_gradient_in_place(d.trial_q, threads);
                d.test_q = d.trial_q;  // the force is the transpose of the gradient: symmetric
                d.gradient_consistency = 0;  // no correction: only constants (001 eq 25)
              });
        });

  ParamSchema s = common_galerkin_schema(10);
  for (auto& spec : kernel_choice(parts.kernels, "gaussian", "kernel W")) s.push_back(spec);
  s.push_back(ParamSpec::positive("h", 1 / (0.5 * std::sqrt(M_PI)),
                                  "dilation over spacing, a = h dx (004 II Fig. 3 uses "
                                  "sigma = dx/(0.1 sqrt(pi)) and dx/(0.5 sqrt(pi)))"));
  r.add("sph-galerkin", "Galerkin with the plain SPH kernel estimate (no correction, 004 II Fig. 3)",
        s, [parts](const Params& p) {
          GalerkinRecipe g;
          g.trial = parts.approximations.create("sph", with_kernel({}, p));
          g.integration = parts.integrations.create("gauss-cells", forward(p, {{"quad", "n"}}));
          g.dilation_over_spacing = p.number("h");
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          g.description = fmt::format("SPH {} kernel, a={:.4g} dx, bc={}", p.text("kernel"),
                                      p.number("h"), p.text("bc"));
          g.formal = {NAN, NAN, "the plain kernel estimate reproduces no polynomial: no order "
                                "to declare"};
          return make_galerkin_method(std::move(g));
        });
}

}  // namespace mfv
