/// The options of the fluid remedies (DynamicsOptions::remedies): what they do, their formulas
/// and references are in dynamics/fluid_remedies.hpp; this header holds only the options, so
/// that explicit.hpp does not carry the remedies' operators.
#pragma once
#include <string>

namespace mfv {

enum class DensityFilter { off, shepard, mls };
enum class DiffusionForm { molteni, antuono };
enum class ShiftingForm { fickian, xu };

/// The remedies' options (DynamicsOptions::remedies); all off by default.
struct FluidRemedies {
  DensityFilter filter = DensityFilter::off;
  int filter_every = 20;  ///< steps between re-initializations (Colagrossi & Landrini: 20-30)
  double diffusion = 0;   ///< δ of the density diffusion; 0: off
  DiffusionForm diffusion_form = DiffusionForm::antuono;
  double shifting = 0;           ///< D of the particle shifting; 0: off
  double shifting_surface = 0.95;  ///< C_I below which a particle shifts tangentially only
  ShiftingForm shifting_form = ShiftingForm::fickian;  ///< Lind et al.'s, or Xu et al.'s
  bool any() const { return filter != DensityFilter::off || diffusion > 0 || shifting > 0; }
  /// Throws InputError naming the parameter (the transient analysis's names) and the fix.
  void validate() const;
  std::string description() const;
};

DensityFilter density_filter_from(const std::string& name);
DiffusionForm diffusion_form_from(const std::string& name);
ShiftingForm shifting_form_from(const std::string& name);

}  // namespace mfv
