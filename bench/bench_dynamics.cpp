/// Throughput of explicit dynamics (dynamics/explicit.hpp) on the 2D plane-strain rod of 001
/// §9.2: 60 × 5 mm, St Venant–Kirchhoff E = 210 GPa, ν = 0, ρ = 7.8e-6 (mm, ms, kg, GPa: the
/// bar wave speed is c ≈ 5189 mm/ms), the Gaussian initial velocity v_x = exp(−0.025(x−30)²),
/// Lagrangian kernel (tables built once), central differences at dt = 0.8 dt_crit.
///   BM_Dynamics/<m>/N:<particles>/omp:<threads>/reorder:<0|1>
///       ExplicitDynamics::step only, kSteps steps per iteration; discretization, engine
///       construction, velocity fit and time-step estimate happen before the timed loop.
///       reorder:1 (sph, kbm-si, efg-ni) is ParticleOrder::hilbert (the transient analysis's
///       reorder=hilbert: the engine renumbers particles and points along the Hilbert curve);
///       reorder:0 the lattice order.
///   BM_DynamicsOrder/sph/N:<particles>/omp:<threads>/order:1/reorder:<0|1>
///       the largest SPH case with the particles randomly permuted before discretize (order:0
///       would be the lattice order of BM_Dynamics/sph), to show what memory order costs, and
///       what the engine's Hilbert renumbering (reorder:1) wins back.
///   BM_DynamicsFrame/<m>/omp:<threads>/eulerian:<0|1>/every:<n>
///       the kernel frames of 001 Tables 1-2 on the 241 × 21 rod (5,061 particles): the
///       Lagrangian run, then the Eulerian one with the tables recomputed every n = 1 or 30
///       steps, 30 steps per iteration so every iteration holds whole update intervals.
///       Counters step_ms (wall) and cpu_ms (process CPU) per step, and eul_over_lag: this
///       case's CPU per step over the Lagrangian case's of the same method and thread count,
///       measured earlier in the same process (the ratio of 001 §9.3 Tables 5-6), and
///       eul_over_lag_wall the same in wall time; retab_ms, the extra CPU per recomputation,
///       (eulerian - lagrangian) × n. Fixed step counts (600, 180, 300), each case from t = 0.
///   BM_DynamicsFrameMaterial/<m>/mat:<svk|j2vp>/omp:1/eulerian:<0|1>/every:<n>
///       the same cases on 1 thread with a material dimension (issue 15: is 001's smaller
///       Eulerian/Lagrangian ratio that of a dearer material?): svk as above, and
///       j2-viscoplastic (Needleman's rate-dependent J2, implicit Newton return in Δε̄) with
///       σ0 = 1e-6 E, so that the points flow from the first steps. Both materials get the
///       Gaussian pulse plus a uniform compression v_x = −ε̇ (x − 30), ε̇ = 0.1/ms (strain
///       ≈ 3e-6 per step), so that every point is loaded. Extra counter plastic_frac: the
///       fraction of integration points whose plastic_strain grew during the measured steps.
///   BM_MaterialPoint/<svk|j2vp>
///       first_piola of one batch of 5,061 points per iteration under the same uniform
///       compression (ε = 3e-6 more per call, dt = 3e-5 ms): counter ns_per_point, and
///       plastic_frac as above.
/// Counters: items_per_second (particle-steps per second), particles, qpoints (integration
/// points), entries and test_entries (of the trial and test tables at the points), setup_s
/// (wall seconds of discretize for this case), engine_s (the engine's
/// constructor, with the renumbering for reorder:1), fit_s (set_particle_velocity), rss_GB (resident set after the
/// run). Speed is measured here only: tests assert no timings.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "dynamics/explicit.hpp"
#include "methods/particles.hpp"
#include "apps/catalogue.hpp"
#include "bench/bench_catalogue.hpp"
#include "bench/bench_memory.hpp"

namespace {

using namespace mfv;

using bench::catalogue;

// 001 §9.2 in mm / ms / kg / GPa.
constexpr double kLength = 60, kDepth = 5, kYoung = 210, kPoisson = 0, kDensity = 7.8e-6;
constexpr int kSteps = 10;  // steps per benchmark iteration

const char* const kMethods[] = {"sph", "rlm", "kbm-ni", "kbm-si", "efg-ni", "efg-ci"};
const int kThreads[] = {1, 2};

/// Lattices nx × ny with ny = (nx−1)/12 + 1 (the 60 × 5 aspect ratio, square spacing
/// 60/(nx−1)); the benchmark argument is the particle count nx·ny.
const int kColumns[] = {361, 481, 1201, 3457};  // 11,191 · 19,721 · 121,301 · 999,073
constexpr int rows_of(int nx) { return (nx - 1) / 12 + 1; }
constexpr int lattice_particles(int nx) { return nx * rows_of(nx); }
int columns_of(int particles) {
  for (int nx : kColumns)
    if (lattice_particles(nx) == particles) return nx;
  throw std::logic_error("bench_dynamics: no lattice with " + std::to_string(particles) +
                         " particles");
}

/// Methods whose set-up at 10^6 particles stays under ~20 s and ~6 GB on the 2-core, 24 GB
/// machine: all but efg-ci, since the nodal-velocity fit is Jacobi-preconditioned (0.3-0.8 s
/// at 10^6 instead of 66-123 s with ILUT). efg-ci has 9 Gauss points per particle and would
/// need about 20 GB (see bench/README.md); it stops at 121,301 particles unless
/// MFV_BENCH_DYNAMICS_ALL is set in the environment.
bool runs_at(const std::string& method, int nx) {
  if (nx < 3000) return true;
  if (std::getenv("MFV_BENCH_DYNAMICS_ALL")) return true;
  return method != "efg-ci";
}

Domain rod() { return Domain::rectangle(0, 0, kLength, kDepth); }

/// Random permutation of the particles (every per-particle field moved consistently); the
/// set is then no longer a lattice.
ParticleSet shuffled(const ParticleSet& p, std::uint64_t seed) {
  const int n = p.size();
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::mt19937_64 rng(seed);
  std::shuffle(perm.begin(), perm.end(), rng);
  ParticleSet s = p;
  for (int k = 0; k < n; ++k) {
    s.x.col(k) = p.x.col(perm[k]);
    s.volume[k] = p.volume[perm[k]];
    if (p.dilation.size() == n) s.dilation[k] = p.dilation[perm[k]];
    if (static_cast<int>(p.sides.size()) == n) s.sides[k] = p.sides[perm[k]];
  }
  s.lattice.setZero();
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The rod's material: "svk" (St Venant–Kirchhoff), or "j2vp" (j2-viscoplastic, Needleman
/// 1989) with the rod's E and ν, σ0 = 1e-6 E so that the benchmark's small strains are far
/// into plastic flow, and the floor and softening slope scaled to the GPa units (their
/// defaults are in Pa); the other constants are the material's defaults.
std::unique_ptr<Material> rod_material(const std::string& name) {
  Params mp;
  mp.set("E", kYoung);
  mp.set("nu", kPoisson);
  if (name == "svk") return catalogue().materials.create("svk", mp);
  if (name != "j2vp")
    throw std::logic_error("bench_dynamics: no rod material '" + name + "' (svk or j2vp)");
  const double sigma0 = 1e-6 * kYoung;
  mp.set("sigma0", sigma0);
  mp.set("residual", sigma0 / 100);
  mp.set("h1", -kYoung / 100);
  return catalogue().materials.create("j2-viscoplastic", mp);
}

DynamicsModel rod_model(const ParticleSet& particles, const std::string& material = "svk") {
  DynamicsModel model;
  model.material = rod_material(material);
  model.density = kDensity;
  model.mass = lumped_masses(particles, model.density, MassLumping::volume);
  return model;
}

void set_rod_velocity(ExplicitDynamics& sim, const ParticleSet& particles) {
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, particles.size());
  for (int I = 0; I < particles.size(); ++I)
    v(0, I) = std::exp(-0.025 * std::pow(particles.x(0, I) - 0.5 * kLength, 2));
  sim.set_particle_velocity(v);
}

/// Compression rate of BM_DynamicsFrameMaterial and BM_MaterialPoint, 1/ms.
constexpr double kCompressionRate = 0.1;

/// The Gaussian pulse plus the uniform compression v_x = −ε̇ (x − L/2).
void set_compressed_rod_velocity(ExplicitDynamics& sim, const ParticleSet& particles) {
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, particles.size());
  for (int I = 0; I < particles.size(); ++I) {
    const double x = particles.x(0, I) - 0.5 * kLength;
    v(0, I) = std::exp(-0.025 * x * x) - kCompressionRate * x;
  }
  sim.set_particle_velocity(v);
}

/// The fraction of entries that grew from `before` to `after` (0 when there are none).
double grown_fraction(const Eigen::VectorXd& before, const Eigen::VectorXd& after) {
  if (after.size() == 0 || before.size() != after.size()) return 0;
  return static_cast<double>((after.array() > before.array()).count()) /
         static_cast<double>(after.size());
}

/// dt_crit / (Δx / c) of a method on the rod, from the power iteration on a 241 × 21 lattice
/// (cached per method). On a uniform lattice the largest frequency is set by the interior
/// stencil, so the ratio does not depend on the size, and the large cases need not run 120
/// force evaluations for their estimate.
double critical_ratio(const std::string& method) {
  static std::map<std::string, double> ratios;
  if (auto it = ratios.find(method); it != ratios.end()) return it->second;
  const auto m = catalogue().methods.create(method);
  const ParticleSet p = rectangle_lattice(rod(), 241, rows_of(241), Placement::boundary);
  ExplicitDynamics sim(*m, m->discretize(rod(), p, 1), rod_model(p), DynamicsOptions{});
  set_rod_velocity(sim, p);
  const double c = std::sqrt(kYoung / kDensity);
  return ratios[method] = sim.critical_time_step() / (p.spacing / c);
}

/// One case (method, size, order) with its discretization and the engine of the thread count
/// being measured. The library calls a benchmark function several times while it settles the
/// iteration count, so the engine is kept between those calls (its time simply runs on), and
/// the thread counts of a case, registered one after the other, share the discretization.
/// One case is held at a time: at 10^6 particles a discretization takes GBs.
struct Case {
  std::string key;
  std::unique_ptr<Method> method;  // must outlive the engine built on it
  ParticleSet particles;
  std::optional<Discretization> d;  // handed to the engine of the last thread count
  double setup_seconds = 0, engine_seconds = 0, fit_seconds = 0, dt = 0;
  int threads = 0;
  std::unique_ptr<ExplicitDynamics> sim;
};

ExplicitDynamics& engine(Case& c, const std::string& method, int particles, bool random_order,
                         bool hilbert, int threads) {
  const std::string key = method + "/" + std::to_string(particles) + (random_order ? "/r" : "") +
                          (hilbert ? "/h" : "");
  if (c.key == key && c.sim && c.threads == threads) return *c.sim;
  c.sim.reset();  // frees the previous engine, and below the previous case, first
  if (c.key != key || !c.d) {
    c = Case{};
    c.key = key;
    c.method = catalogue().methods.create(method);
    const int nx = columns_of(particles);
    c.particles = rectangle_lattice(rod(), nx, rows_of(nx), Placement::boundary);
    if (random_order) c.particles = shuffled(c.particles, 12345);
    const auto t0 = std::chrono::steady_clock::now();
    c.d = c.method->discretize(rod(), c.particles, 1);
    c.setup_seconds = seconds_since(t0);
  }
  DynamicsOptions opt;
  opt.frame = KernelFrame::lagrangian;
  opt.threads = threads;
  // The transient analysis's reorder=hilbert: the engine renumbers inside.
  if (hilbert) opt.order = ParticleOrder::hilbert;
  const auto t0 = std::chrono::steady_clock::now();
  // The last thread count takes the tables; the earlier ones copy them.
  const bool last = threads == kThreads[std::size(kThreads) - 1];
  c.sim = std::make_unique<ExplicitDynamics>(*c.method, last ? std::move(*c.d) : *c.d,
                                             rod_model(c.particles), opt);
  if (last) c.d.reset();
  c.threads = threads;
  c.engine_seconds = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  set_rod_velocity(*c.sim, c.particles);
  c.fit_seconds = seconds_since(t1);
  c.dt = 0.8 * critical_ratio(method) * c.particles.spacing / std::sqrt(kYoung / kDensity);
  return *c.sim;
}

void run(benchmark::State& state, const std::string& method, bool random_order, bool hilbert) {
  static Case c;
  const int n = static_cast<int>(state.range(0));
  ExplicitDynamics* sim = nullptr;
  try {
    sim = &engine(c, method, n, random_order, hilbert, static_cast<int>(state.range(1)));
  } catch (const std::exception& e) {
    c = Case{};
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) {
    for (int s = 0; s < kSteps; ++s) sim->step(c.dt);
    benchmark::DoNotOptimize(sim->velocity().data());
    benchmark::ClobberMemory();
  }
  if (!std::isfinite(sim->kinetic_energy())) {
    state.SkipWithError("the run blew up (non-finite kinetic energy)");
    return;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kSteps * n);
  state.counters["particles"] = n;
  state.counters["qpoints"] = sim->discretization().quadrature.size();
  state.counters["entries"] = sim->discretization().trial_q.entries();
  state.counters["test_entries"] = sim->discretization().test_q.entries();
  state.counters["setup_s"] = c.setup_seconds;
  state.counters["engine_s"] = c.engine_seconds;
  state.counters["fit_s"] = c.fit_seconds;
  state.counters["rss_GB"] = bench::resident_gb();
}

void BM_Dynamics(benchmark::State& state, const char* method) {
  run(state, method, false, state.range(2) != 0);
}

void BM_DynamicsOrder(benchmark::State& state) {
  run(state, "sph", state.range(2) != 0, state.range(3) != 0);
}

void configure(benchmark::internal::Benchmark* b, int particles) {
  b->Unit(benchmark::kMillisecond)->UseRealTime();
  // One iteration is kSteps steps. Up to 10^5 particles, repeat for 0.5 s; at 10^6 three
  // iterations (0.1-0.3 s per step), so the whole set finishes in about 5 minutes on 2 cores.
  if (particles > 500000)
    b->Iterations(3);
  else
    b->MinTime(0.5);
}

/// The methods of the scaling figures (issue 17), measured with and without reorder=hilbert.
bool reorders(const std::string& method) {
  return method == "sph" || method == "kbm-si" || method == "efg-ni";
}

bool register_dynamics_benchmarks() {
  for (const char* method : kMethods)
    for (int nx : kColumns) {
      if (!runs_at(method, nx)) continue;
      const int n = lattice_particles(nx);
      auto* b = benchmark::RegisterBenchmark((std::string("BM_Dynamics/") + method).c_str(),
                                             BM_Dynamics, method);
      b->ArgNames({"N", "omp", "reorder"});
      for (int reorder : {0, 1})
        if (reorder == 0 || reorders(method))
          for (int t : kThreads) b->Args({n, t, reorder});
      configure(b, n);
    }
  // Particle order: a random permutation at the largest size. The lattice-order reference is
  // BM_Dynamics/sph/N:999073 (--benchmark_filter=sph/N:999073 runs both); order:0 repeats it.
  const int n = lattice_particles(kColumns[std::size(kColumns) - 1]);
  auto* b = benchmark::RegisterBenchmark("BM_DynamicsOrder/sph", BM_DynamicsOrder);
  b->ArgNames({"N", "omp", "order", "reorder"});
  for (int reorder : {0, 1})
    for (int t : kThreads) b->Args({n, t, 1, reorder});
  configure(b, n);
  return true;
}

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

constexpr int kFrameColumns = 241;  // 241 × 21 = 5,061 particles
constexpr int kFrameSteps = 30;     // steps per iteration: a whole number of update intervals

struct Timing {
  double cpu = 0, wall = 0;  // seconds
};
/// Seconds per step of the Lagrangian run per (method, threads), for the Eulerian ratios.
std::map<std::string, Timing>& lagrangian_per_step() {
  static std::map<std::string, Timing> m;
  return m;
}

/// One frame case; `material` null is BM_DynamicsFrame (svk, the Gaussian pulse), otherwise
/// BM_DynamicsFrameMaterial (that rod material, the pulse plus the compression).
void frame_case(benchmark::State& state, const std::string& method, int threads, bool eulerian,
                int every, const char* material = nullptr) {
  // A fixed iteration count: the library calls this once per case, and each case starts from
  // t = 0 with its own engine.
  const ParticleSet p =
      rectangle_lattice(rod(), kFrameColumns, rows_of(kFrameColumns), Placement::boundary);
  std::unique_ptr<Method> m;
  std::unique_ptr<ExplicitDynamics> sim;
  double dt = 0;
  try {
    m = catalogue().methods.create(method);
    DynamicsOptions opt;
    opt.frame = eulerian ? KernelFrame::eulerian : KernelFrame::lagrangian;
    opt.update_every = every;
    opt.threads = threads;
    sim = std::make_unique<ExplicitDynamics>(*m, m->discretize(rod(), p, 1),
                                             rod_model(p, material ? material : "svk"), opt);
    if (material)
      set_compressed_rod_velocity(*sim, p);
    else
      set_rod_velocity(*sim, p);
    dt = 0.8 * critical_ratio(method) * p.spacing / std::sqrt(kYoung / kDensity);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const Eigen::VectorXd plastic_before = sim->point_state("plastic_strain");
  double cpu = 0, wall = 0;
  for (auto _ : state) {
    const double c0 = process_cpu_seconds();
    const auto w0 = std::chrono::steady_clock::now();
    for (int s = 0; s < kFrameSteps; ++s) sim->step(dt);
    cpu += process_cpu_seconds() - c0;
    wall += seconds_since(w0);
    benchmark::DoNotOptimize(sim->velocity().data());
    benchmark::ClobberMemory();
  }
  if (!std::isfinite(sim->kinetic_energy())) {
    state.SkipWithError("the run blew up (non-finite kinetic energy)");
    return;
  }
  const double steps = static_cast<double>(state.iterations()) * kFrameSteps;
  const Timing per_step{cpu / steps, wall / steps};
  const std::string lag_key =
      fmt::format("{}/{}{}", method, threads, material ? std::string("/") + material : "");
  state.SetItemsProcessed(static_cast<std::int64_t>(steps) * p.size());
  state.counters["particles"] = p.size();
  state.counters["qpoints"] = sim->discretization().quadrature.size();
  state.counters["step_ms"] = 1e3 * per_step.wall;
  state.counters["cpu_ms"] = 1e3 * per_step.cpu;
  if (material)
    state.counters["plastic_frac"] =
        grown_fraction(plastic_before, sim->point_state("plastic_strain"));
  if (!eulerian) {
    lagrangian_per_step()[lag_key] = per_step;
    return;
  }
  state.counters["retabulations"] = static_cast<double>(sim->counters().retabulations);
  if (auto it = lagrangian_per_step().find(lag_key); it != lagrangian_per_step().end()) {
    state.counters["eul_over_lag"] = per_step.cpu / it->second.cpu;
    state.counters["eul_over_lag_wall"] = per_step.wall / it->second.wall;
    state.counters["retab_ms"] = 1e3 * (per_step.cpu - it->second.cpu) * every;
  }
}

bool register_frame_benchmarks() {
  // The Lagrangian case of a (method, thread count) first: the Eulerian ratios divide by it.
  // Fixed step counts (not a minimum time): the same work before and after a change, and no
  // run long enough for the rod to go unstable (rlm's Lagrangian run blows up after a few
  // thousand steps). 600 steps Lagrangian, 180 Eulerian every step (60 left the ratio to the
  // noise of a shared machine), 300 every 30th step.
  for (const char* method : kMethods)
    for (int t : kThreads)
      for (const auto& [eulerian, every, iterations] :
           {std::tuple{0, 1, 20}, std::tuple{1, 1, 6}, std::tuple{1, 30, 10}})
        benchmark::RegisterBenchmark(
            fmt::format("BM_DynamicsFrame/{}/omp:{}/eulerian:{}/every:{}", method, t, eulerian,
                        every)
                .c_str(),
            [method, t, eulerian, every](benchmark::State& s) {
              frame_case(s, method, t, eulerian != 0, every);
            })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(iterations);
  return true;
}

[[maybe_unused]] const bool kFrameRegistered = register_frame_benchmarks();

const char* const kRodMaterials[] = {"svk", "j2vp"};

bool register_frame_material_benchmarks() {
  // As register_frame_benchmarks, on 1 thread, each material's Lagrangian case first.
  for (const char* method : kMethods)
    for (const char* material : kRodMaterials)
      for (const auto& [eulerian, every, iterations] :
           {std::tuple{0, 1, 20}, std::tuple{1, 1, 2}, std::tuple{1, 30, 10}})
        benchmark::RegisterBenchmark(
            fmt::format("BM_DynamicsFrameMaterial/{}/mat:{}/omp:1/eulerian:{}/every:{}", method,
                        material, eulerian, every)
                .c_str(),
            [method, material, eulerian, every](benchmark::State& s) {
              frame_case(s, method, 1, eulerian != 0, every, material);
            })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(iterations);
  return true;
}

[[maybe_unused]] const bool kFrameMaterialRegistered = register_frame_material_benchmarks();

/// The cost of the material alone: first_piola of 5,061 points (the frame rod's particle
/// count) per iteration, every point compressed uniformly by a further 3e-6 per call, as a
/// point of BM_DynamicsFrameMaterial is per step. The engine calls the material in batches of
/// the same kind, so this is its per-point cost inside a step.
void BM_MaterialPoint(benchmark::State& state, const char* name) {
  constexpr int kDim = 2, kPoints = 5061;
  constexpr double kStrainPerCall = 3e-6, kDt = 3e-5;  // ms, about the rod's dt
  const std::unique_ptr<Material> material = rod_material(name);
  const int ns = material->state_size(kDim);
  std::vector<double> F(4 * kPoints), P(4 * kPoints), state_values(ns * kPoints, 0.0);
  material->initial_state(kDim, kPoints, state_values.data());
  // The engine's F is the identity before the first step; the material's history starts there.
  const std::vector<std::string> names = material->state_names(kDim);
  const auto slot = std::find(names.begin(), names.end(), "plastic_strain");
  const auto plastic = [&] {
    Eigen::VectorXd e(slot == names.end() ? 0 : kPoints);
    for (int q = 0; q < e.size(); ++q) e[q] = state_values[ns * q + (slot - names.begin())];
    return e;
  };
  const auto set_F = [&](double strain) {
    for (int q = 0; q < kPoints; ++q) {
      // Column-major 2 × 2; a slight per-point shear so that the points are not all equal.
      F[4 * q + 0] = 1 - strain;
      F[4 * q + 1] = 0;
      F[4 * q + 2] = 1e-7 * (q % 7);
      F[4 * q + 3] = 1;
    }
  };
  // A few calls first, so that the measured ones are in flow, not at the elastic start.
  long calls = 0;
  for (; calls < 5; ++calls) {
    set_F(kStrainPerCall * static_cast<double>(calls + 1));
    material->first_piola(kDim, kPoints, F.data(), P.data(), state_values.data(), kDt);
  }
  const Eigen::VectorXd before = plastic();
  for (auto _ : state) {
    state.PauseTiming();
    set_F(kStrainPerCall * static_cast<double>(++calls));
    state.ResumeTiming();
    material->first_piola(kDim, kPoints, F.data(), P.data(), state_values.data(), kDt);
    benchmark::DoNotOptimize(P.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kPoints);
  state.counters["ns_per_point"] = benchmark::Counter(
      1e-9 * static_cast<double>(kPoints) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["plastic_frac"] = grown_fraction(before, plastic());
}

bool register_material_benchmarks() {
  for (const char* name : kRodMaterials)
    benchmark::RegisterBenchmark((std::string("BM_MaterialPoint/") + name).c_str(),
                                 BM_MaterialPoint, name)
        ->Unit(benchmark::kMicrosecond)
        ->MinTime(0.5);
  return true;
}

[[maybe_unused]] const bool kMaterialRegistered = register_material_benchmarks();

// Registered during static initialization, like bench_cantilever.cpp.
[[maybe_unused]] const bool kRegistered = register_dynamics_benchmarks();

}  // namespace
