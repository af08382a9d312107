/// `wavelet`: multi-scale RKPM with M wavelet dilations on top of the Gaussian RK window
/// (004 I Table 6.1 rows "2 WL dil." and "4 WL dil.").
#include "methods/methods/register.hpp"

#include <cmath>

namespace mfv {

namespace {

/// M, at most 16: band m has dilation 2^(m-1)·wscale·Δx, so band 16 already spans 32,768
/// spacings; more bands only multiply the work (bands=1e9 used to run for ever).
ParamSpec wavelet_bands_spec() {
  ParamSpec s = ParamSpec::count("bands", 2, 0, "number of wavelet dilations M (at most 16)");
  s.max = 16;
  return s;
}

}  // namespace

void register_wavelet(MethodRegistry& r, const MethodParts& parts) {
  ParamSchema s = common_galerkin_schema(10);
  // The kernel is declared with its one value so that kernel=<another> says why (rather than
  // "unknown parameter"): the family is built on the Gaussian.
  s.push_back(ParamSpec::choice(
      "kernel", "gaussian", {"gaussian"},
      "the Gaussian only: the low band is its RK window and the wavelet bands are built from "
      "it (Mexican hats, its second derivative; 004 I §6), so no other kernel makes this "
      "family"));
  for (auto& spec : rkpm_window_schema(parts.kernels))
    if (spec.name != "kernel" && !spec.name.starts_with("kernel-")) s.push_back(spec);
  s.push_back(wavelet_bands_spec());
  s.push_back(ParamSpec::positive("wscale", 1.0, "first wavelet dilation over dx"));
  r.add("wavelet", "multi-scale RKPM: Gaussian RK low band plus M Mexican-hat wavelet bands", s,
        [parts](const Params& p) {
          GalerkinRecipe g;
          g.trial = parts.approximations.create(
              "wavelet", forward(p, {{"bands", "bands"}, {"wscale", "wscale"}}));
          g.integration = parts.integrations.create("gauss-cells", forward(p, {{"quad", "n"}}));
          Params window = p;
          window.set("kernel", "gaussian");
          g.dilation_over_spacing = rkpm_dilation_scale(window) * std::pow(2.0, p.number("j"));
          g.essential = essential_from(p);
          g.penalty = p.number("penalty");
          g.description = fmt::format("Gaussian RK low band j={} (a={:.4g} dx, {}) + {} wavelet "
                                      "dilations from {} dx, bc={}",
                                      p.number("j"), g.dilation_over_spacing, p.text("rule"),
                                      p.integer("bands"), p.number("wscale"), p.text("bc"));
          g.formal = {2, 1, "the RK low band's linear reproducing conditions, Gauss cells (004 I "
                            "§4)"};
          return make_galerkin_method(std::move(g));
        });
}

}  // namespace mfv
