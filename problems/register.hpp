/// The problem registry's one-line-per-problem registration list.
#pragma once
#include "problems/problem.hpp"

namespace mfv {

void register_laplace_tanh(ProblemRegistry&);
void register_advection_diffusion(ProblemRegistry&);
void register_cantilever(ProblemRegistry&);
void register_elastic_patch(ProblemRegistry&);
void register_rod_pulse(ProblemRegistry&);
void register_prestressed_rod(ProblemRegistry&);
void register_grk_bar(ProblemRegistry&);
void register_dispersion(ProblemRegistry&);
void register_time_step(ProblemRegistry&);
void register_enriched_bar(ProblemRegistry&);
void register_stretch_map(ProblemRegistry&);
void register_rings(ProblemRegistry&);
void register_funnel(ProblemRegistry&);
void register_plate(ProblemRegistry&);
void register_notched_beam(ProblemRegistry&);
void register_hydrostatic_column(ProblemRegistry&);
void register_dam_break(ProblemRegistry&);
void register_oscillating_plate(ProblemRegistry&);

/// Registers every problem: add one line here for a new one.
inline void register_all_problems(ProblemRegistry& r) {
  register_laplace_tanh(r);
  register_advection_diffusion(r);
  register_cantilever(r);
  register_elastic_patch(r);
  register_rod_pulse(r);
  register_prestressed_rod(r);
  register_grk_bar(r);
  register_dispersion(r);
  register_time_step(r);
  register_enriched_bar(r);
  register_stretch_map(r);
  register_rings(r);
  register_funnel(r);
  register_plate(r);
  register_notched_beam(r);
  register_hydrostatic_column(r);
  register_dam_break(r);
  register_oscillating_plate(r);
}

}  // namespace mfv
