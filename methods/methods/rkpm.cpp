/// `rkpm`: reproducing kernel particle method with linear correction C1 + C2 (x - x_J)/a,
/// trapezoidal moments, exact (004 II eq 6.2) or DEM (eq 6.6) derivatives, dilation j.
#include "methods/methods/register.hpp"

#include <cmath>

#include "methods/core/errors.hpp"
#include "methods/kernels/kernel_choice.hpp"

namespace mfv {

ParamSchema rkpm_window_schema(const KernelRegistry& kernels) {
  ParamSchema s = kernel_choice(kernels, "gaussian",
                                "window function (004 II: gaussian, eq 6.8a, or cubic-window, "
                                "eq 6.7; any registered kernel under rule=eq7.4 or custom)");
  for (auto& spec : ParamSchema{
      ParamSpec::number("j", 1.0, "dilation index: a = scale 2^j dx"),
      ParamSpec::choice("rule", "eq7.4", {"eq7.4", "derived", "fit", "eq6.10", "custom"},
                        "window scaling: eq7.4 (004 II read literally: a = 2^{j+0.5} sigma, "
                        "dx/(sigma sqrt(pi)) = 1/sqrt(2)), derived (Gaussian: a = 2^j dx/pi, "
                        "band edge 1/a at the Nyquist wavenumber pi/dx for j = 0), fit "
                        "(Gaussian: a = 0.3297 2^j dx fitted to Table 1), eq6.10 (004 I: "
                        "a0 = 2^j dx sqrt(2/pi)), custom (scale); eq7.4 with a kernel "
                        "other than the two of 004 II: the cubic window's support radius "
                        "2^{j+0.5} dx"),
      ParamSpec::positive("scale", 1.0, "a = scale 2^j dx when rule=custom"),
  })
    s.push_back(std::move(spec));
  return s;
}

double rkpm_dilation_scale(const Params& p, double kernel_support) {
  const std::string& rule = p.text("rule");
  if (rule == "custom") return p.number("scale");
  if (rule == "eq6.10") return std::sqrt(2 / M_PI);
  if ((rule == "derived" || rule == "fit") && p.text("kernel") != "gaussian")
    throw InputError(fmt::format("rule={} is a reading of the Gaussian window of 004 II eq 6.8; "
                                 "with kernel={} use rule=eq7.4 or rule=custom",
                                 rule, p.text("kernel")));
  // derived: the Gaussian's frequency band is [-1/a, 1/a] (004 II eqs 4.15b, 4.17 with
  // Δk̂ = 1 for k̂ = e^{-ω²/4}, eq 4.23b); no aliasing (eq 4.18) puts the band edge at the
  // Nyquist wavenumber π/Δx when j = 0, the stability limit §6 sets j = 0 at, so a_0 = Δx/π
  // and a = 2^j a_0. In eq 6.8b's form a = 2^{j+0.5} σ this is σ = a_0/√2, the standard
  // deviation of the j = 0 window e^{-z²} (eqs 6.8a, 6.9a).
  if (rule == "derived") return 1 / M_PI;
  // fit: the single scale scripts/fit_table1_scale.py fits to Table 1's 21/41/81-node rows.
  if (rule == "fit") return 0.3297;
  // eq 7.4: Gaussian a = 2^{j+0.5} σ, σ = √2 Δx/√π → a = 2^j (2/√π) Δx; the cubic window of
  // eq 6.7 (support 1) takes a = 2^{j+0.5} Δx. Any other kernel, which 004 II does not run,
  // gets the cubic window's support radius 2^{j+0.5} Δx: a = 2^{j+0.5} Δx / support.
  return p.text("kernel") == "gaussian" ? 2 / std::sqrt(M_PI) : std::sqrt(2.0) / kernel_support;
}

void register_rkpm(MethodRegistry& r, const MethodParts& parts) {
  ParamSchema s = common_galerkin_schema(10);
  for (auto& spec : rkpm_window_schema(parts.kernels)) s.push_back(spec);
  s.push_back(ParamSpec::choice("derivative", "exact", {"exact", "diffuse"},
                                "exact (eq 6.2) or DEM approximation (eq 6.6)"));
  r.add("rkpm", "reproducing kernel particle method (004 II §3-7)", s, [parts](const Params& p) {
    GalerkinRecipe g;
    g.trial = parts.approximations.create(
        "rkpm", with_kernel(forward(p, {{"derivative", "derivative"}}), p));
    g.integration = parts.integrations.create("gauss-cells", forward(p, {{"quad", "n"}}));
    g.dilation_over_spacing = rkpm_dilation_scale(p, make_kernel(parts.kernels, p)->support()) *
                              std::pow(2.0, p.number("j"));
    g.essential = essential_from(p);
    g.penalty = p.number("penalty");
    g.description = fmt::format("RKPM {} window, j={}, a={:.4g} dx ({}), {} derivative, bc={}",
                                p.text("kernel"), p.number("j"), g.dilation_over_spacing,
                                p.text("rule"), p.text("derivative"), p.text("bc"));
    g.formal = {2, 1, "linear reproducing conditions, Gauss cells (Liu, Jun & Zhang 1995)"};
    return make_galerkin_method(std::move(g));
  });
}

}  // namespace mfv
