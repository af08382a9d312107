/// `rlm`: Randles–Libersky normalized SPH with nodal integration (001 Table 1 row RLM,
/// eqs 33–34): the symmetrized SPH sums with the kernel gradient corrected by B.
#include "methods/approximations/particle_gradients.hpp"
#include "methods/methods/register.hpp"

namespace mfv {

void register_rlm(MethodRegistry& r, const MethodParts& parts) {
  r.add("rlm",
        "Randles-Libersky normalized SPH, collocation at the particles: the SPH sums with "
        "grad W corrected by B (001 eqs 33-34, Table 1)",
        particle_method_schema(parts.kernels, false), [parts](const Params& p) {
          ParticleRecipe g;
          g.integration = parts.integrations.create("nodal");
          set_particle_dilation(p, parts.kernels, g.dilation_over_spacing, g.dilation);
          Params a;
          a.set("kernel", p.text("kernel").c_str());
          std::shared_ptr<const Approximation> sph = parts.approximations.create("sph", a);
          std::shared_ptr<const Approximation> mls = parts.approximations.create("mls", a);
          g.build = [sph, mls](Discretization& d, int) {
            auto tables =
                randles_libersky(sph->evaluate(d.particles, d.particles.x, 1), d.particles);
            d.trial_q = std::move(tables.trial);
            d.test_q = std::move(tables.test);
            d.trial = mls;
            d.test = sph;
            d.form = Form::collocation;
            d.particle_values = true;
          };
          g.description = fmt::format(
              "Randles-Libersky collocation, {} kernel, support {}; particle values fixed "
              "directly; fields between particles: linear MLS fit",
              p.text("kernel"),
              p.number("radius") > 0 ? fmt::format("radius {}", p.number("radius"))
                                     : fmt::format("{} dx", p.number("dmax")));
          return make_particle_method(std::move(g));
        });
}

}  // namespace mfv
