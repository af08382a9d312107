/// Throughput of free-surface water (issue 16) with the Eulerian kernel: the dam break of
/// Martin & Moyce's experiment as the `dam-break` problem and the PySPH peer
/// (bench/peers/pysph_dam_break.py) set it up — a water column a wide and 2a high (a = 0.1 m)
/// at rest and hydrostatic on the floor of a tank 4a long, collapsing under gravity; the
/// Tait fluid of 001 eq 77 (ρ0 = 1000 kg/m³, γ = 7, B = 0.4704 MPa, c0 = 57.4 m/s), penalty
/// walls and gravity (problems/fluid.hpp), Monaghan viscosity α = 0.1, time step
/// 0.25 Δx / c0.
///   BM_FluidDamBreak/<m>/dx_mm:<5|2.5>/omp:<threads>/every:<n>
///       ExplicitDynamics::step only, kFluidSteps steps from t = 0 (the collapse's first
///       0.4–0.9 ms... of flow at 5 and 2.5 mm), the tables recomputed every n steps with
///       neighbour lists (skin 0.3 Δx). Set-up (discretize, engine) is not timed.
/// Counters: items_per_second (particle-steps per second, the figure compared with the peer),
/// particles, sim_per_wall (simulated seconds per wall second), retabulations, rebuilds
/// (fresh neighbour searches), degenerate (points on the fallback at the last recomputation).
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "apps/catalogue.hpp"
#include "bench/bench_catalogue.hpp"
#include "dynamics/explicit.hpp"
#include "methods/particles.hpp"
#include "problems/fluid.hpp"

namespace {

using namespace mfv;

constexpr double kColumn = 0.1;  ///< a (m)
constexpr int kFluidSteps = 200;

using bench::catalogue;

void dam_break_case(benchmark::State& state, const std::string& method, double dx, int threads,
                    int every) {
  const double a = kColumn;
  const int nx = static_cast<int>(std::lround(a / dx)), ny = 2 * nx;
  const Domain column = Domain::rectangle(0, 0, a, 2 * a);
  const ParticleSet p = rectangle_lattice(column, nx, ny, Placement::inset);
  std::unique_ptr<Method> m;
  std::unique_ptr<ExplicitDynamics> sim;
  fluid::Setup setup;
  setup.surface = 2 * a;
  setup.walls = {{{0, 0}, {4 * a, 0}}, {{0, 0}, {0, 4 * a}}, {{4 * a, 0}, {4 * a, 4 * a}}};
  try {
    m = catalogue().methods.create(method);
    Discretization d = m->discretize(column, p, 1);
    DynamicsModel model = fluid::water_model(d, catalogue().materials, setup);
    DynamicsOptions opt;
    opt.frame = KernelFrame::eulerian;
    opt.update_every = every;
    opt.threads = threads;
    opt.viscosity.alpha = 0.1;
    sim = std::make_unique<ExplicitDynamics>(*m, std::move(d), std::move(model), opt);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const double dt = 0.25 * dx / setup.water.sound_speed();
  double wall = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < kFluidSteps; ++s) sim->step(dt);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    benchmark::DoNotOptimize(sim->velocity().data());
  }
  if (!std::isfinite(sim->kinetic_energy())) {
    state.SkipWithError("the run blew up (non-finite kinetic energy)");
    return;
  }
  const double steps = static_cast<double>(state.iterations()) * kFluidSteps;
  state.SetItemsProcessed(static_cast<std::int64_t>(steps) * p.size());
  state.counters["particles"] = p.size();
  state.counters["dt_us"] = 1e6 * dt;
  state.counters["sim_per_wall"] = steps * dt / wall;
  state.counters["retabulations"] = static_cast<double>(sim->counters().retabulations);
  state.counters["rebuilds"] = static_cast<double>(sim->counters().neighbour_rebuilds);
  state.counters["degenerate"] = static_cast<double>(sim->counters().degenerate_points);
}

bool register_fluid_benchmarks() {
  for (const char* method : {"sph", "kbm-si", "efg-ni"})
    for (const auto& [dx_mm, iterations] : {std::pair{5.0, 5}, std::pair{2.5, 2}})
      for (int threads : {1, 2})
        for (int every : {1, 5})
          benchmark::RegisterBenchmark(
              fmt::format("BM_FluidDamBreak/{}/dx_mm:{:g}/omp:{}/every:{}", method, dx_mm,
                          threads, every)
                  .c_str(),
              [=](benchmark::State& s) { dam_break_case(s, method, dx_mm * 1e-3, threads, every); })
              ->Unit(benchmark::kMillisecond)
              ->UseRealTime()
              ->Iterations(iterations);
  return true;
}

[[maybe_unused]] const bool kFluidRegistered = register_fluid_benchmarks();

}  // namespace
