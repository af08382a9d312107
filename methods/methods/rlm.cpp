/// `rlm`: Randles–Libersky normalized SPH with nodal integration (001 Table 1 row RLM,
/// eqs 33–34): the symmetrized SPH sums with the kernel gradient corrected by B.
/// Eulerian recomputations with Retabulation::degenerate_fallback: a particle whose B⁻¹ is
/// singular (too few or collinear neighbours) takes B = I, plain SPH (particle_gradients.hpp).
#include "methods/approximations/particle_gradients.hpp"
#include "methods/methods/register.hpp"

namespace mfv {

void register_rlm(MethodRegistry& r, const MethodParts& parts) {
  r.add("rlm",
        "Randles-Libersky normalized SPH, collocation at the particles: the SPH sums with "
        "grad W corrected by B (001 eqs 33-34, Table 1)",
        particle_method_schema(parts.kernels, false), [parts](const Params& p) {
          return make_collocation_method(
              parts, p, "Randles-Libersky collocation",
              [](ShapeTable& sph, const ParticleSet& particles, Discretization& d,
                 int threads, DegenerateMarks* degenerate) {
                // Into the discretization's own tables: their storage is reused.
                RandlesLiberskyTables tables{std::move(d.trial_q), std::move(d.test_q)};
                randles_libersky(sph, particles, tables, threads, degenerate);
                d.trial_q = std::move(tables.trial);
                d.test_q = std::move(tables.test);
              });
        });
}

}  // namespace mfv
