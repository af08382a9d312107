/// Constitutive models of explicit dynamics: the first Piola–Kirchhoff stress P(F) of a batch
/// of points (001 eqs 1–7: P is what Table 1's internal forces sum), with per-point history
/// variables so that hyperelastic, J2-plastic and equation-of-state models share one interface.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "methods/core/registry.hpp"

namespace mfv {

class Material {
 public:
  virtual ~Material() = default;
  /// History variables per point (plastic strain, back stress, ...); 0 for elastic models.
  virtual int state_size(int dim) const { return 0; }
  /// Sets the history of n points once, after the engine has zero-filled it (state_size(dim)
  /// values per point, point q at state + q·state_size): e.g. a seeded per-point yield
  /// imperfection. The default leaves the zeros.
  virtual void initial_state(int dim, int n, double* state) const {}
  /// One name per history slot (state_size(dim) names, empty when there is no history). The
  /// slot named "plastic_strain" is the effective plastic strain ε̄ that outputs and
  /// shear-band measurements look up by that name.
  virtual std::vector<std::string> state_names(int dim) const { return {}; }
  /// P of n points. F and P hold dim×dim column-major matrices one after another; state holds
  /// state_size(dim) values per point, updated in place (call once per time step). Called
  /// once per batch of points, never per point, so the virtual call costs nothing.
  virtual void first_piola(int dim, int n, const double* F, double* P, double* state) const = 0;
  /// P of n points after a time step dt (seconds) of the engine: rate-dependent models need it
  /// (j2-viscoplastic's flow rate Δε̄/Δt). dt = 0 is a trial evaluation (a tangent or
  /// critical-step probe, an imposed displacement): no time passes, so a rate-dependent model
  /// responds elastically. The default ignores dt, so rate-independent models are unchanged.
  virtual void first_piola(int dim, int n, const double* F, double* P, double* state,
                           double dt) const {
    first_piola(dim, n, F, P, state);
  }
  /// True when P depends on dt (the engine must pass the step's dt, not 0).
  virtual bool rate_dependent() const { return false; }
  /// Dilatational wave speed √(M/ρ) in the model's small-strain limit: the elastic bound used
  /// by time-step estimates and instability detectors.
  virtual double wave_speed(int dim, double density) const = 0;
  /// Parameters as resolved, for reports ("St Venant-Kirchhoff E=210 nu=0 plane strain").
  virtual std::string description(int dim) const = 0;
};

using MaterialRegistry = Registry<Material>;

/// Registers every material (the list: methods/materials/register_all.cpp).
void register_all_materials(MaterialRegistry& r);

}  // namespace mfv
