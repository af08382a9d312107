/// Speed of the 2D pipeline on the cantilever (001 §9.1) for each method of 001 Table 1 and
/// fem, at about 10^3, 10^4 and 10^5 particles (17, 51 and 159 particles across the depth:
/// 1,105, 10,251 and 100,647 particles on the boundary lattice), and with
/// MFV_BENCH_CANTILEVER_1E6=1 in the environment also at about 10^6 (501 across the depth:
/// 1,002,501 particles; setup and assembly of fem, efg-ci, efg-ni and kbm-si only):
///   BM_CantileverSetup     Method::discretize: dilations, quadrature rule, neighbour search,
///                          shape functions / gradient tables at every integration point.
///   BM_CantileverAssembly  BoundaryValueProblem::assemble: stiffness matrix, load vector, constraints.
///   BM_CantileverSolve     solve_constrained: essential conditions, then the sparse solver.
/// Counters: particles, qpoints (integration points), time/particle (wall time of one run
/// divided by the particle count), unknowns and nnz of K, and for the solve the fill of the
/// factors; peak_rss_MB is the process's peak resident memory during the benchmark (VmHWM,
/// reset at its start), with what was already resident (the discretization) included; for the
/// assembly, user/particle and sys/particle split its CPU time into user space and kernel
/// (page faults). A 10^6 case whose estimated memory exceeds MemAvailable is skipped with the
/// estimate in its error. Speed is measured here only: tests assert no timings.
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include <sys/resource.h>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "problems/problem.hpp"
#include "apps/catalogue.hpp"
#include "bench/bench_catalogue.hpp"
#include "bench/bench_memory.hpp"
#include "analyses/static_solve.hpp"
#include "methods/core/resources.hpp"
#include "verify/runner.hpp"

namespace {

using namespace mfv;

/// One catalogue for the whole program (registries hold references into it).
using bench::catalogue;

// Catalogue names, default parameters: the methods as the cantilever study runs them.
const char* const kMethods[] = {"fem", "efg-ci", "efg-ni", "kbm-si", "kbm-ni", "rlm", "sph"};

/// Particles across the depth. The benchmark argument is the particle count of the
/// boundary lattice, (4(ny-1)+1)·ny (Cantilever::particles), so the names read
/// BM_CantileverSetup/fem/1105.
const int kDepths[] = {17, 51, 159, 501};

/// The 10^6 lattice takes GBs and minutes per case: registered only on request.
constexpr int kMillionDepth = 501;
const char* const kMillionMethods[] = {"fem", "efg-ci", "efg-ni", "kbm-si"};
bool million_requested() {
  const char* v = std::getenv("MFV_BENCH_CANTILEVER_1E6");
  return v && std::string(v) != "0" && std::string(v) != "";
}

constexpr int lattice_particles(int depth) { return (4 * (depth - 1) + 1) * depth; }

int depth_of(int particles) {
  for (int depth : kDepths)
    if (lattice_particles(depth) == particles) return depth;
  throw std::logic_error("bench_cantilever: no lattice with " + std::to_string(particles) +
                         " particles");
}

struct Setup {
  std::unique_ptr<BoundaryValueProblem> problem;
  std::unique_ptr<Method> method;
  Domain domain;
  int order = 1;
};

Setup make_setup(const char* method) {
  Setup s;
  s.problem = catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  s.method = catalogue().methods.create(method);
  s.domain = s.problem->domain();
  s.order = s.problem->derivative_order();
  return s;
}

/// The discretization and system of one "method/N" case, kept between its three benchmarks
/// (registered one after the other: Setup leaves its discretization for Assembly, Assembly
/// its system for Solve). Only one case is held: at 10^5 particles a meshfree
/// discretization takes GBs, and keeping all 21 would not fit. A filtered run builds what
/// it needs outside the timing loop.
struct Cached {
  std::string key;
  std::shared_ptr<const Discretization> d;
  std::shared_ptr<const AssembledSystem> sys;
};
Cached& cached(const char* method, int particles) {
  static Cached c;
  const std::string key = std::string(method) + "/" + std::to_string(particles);
  if (c.key != key) c = Cached{key, nullptr, nullptr};  // frees the previous case first
  return c;
}

const Discretization& discretization(const Setup& s, const char* method, int particles) {
  Cached& c = cached(method, particles);
  if (!c.d)
    c.d = std::make_shared<const Discretization>(
        s.method->discretize(s.domain, s.problem->particles(depth_of(particles), 0.0), s.order));
  return *c.d;
}

const AssembledSystem& assembled(const Setup& s, const char* method, int particles) {
  const Discretization& d = discretization(s, method, particles);
  Cached& c = cached(method, particles);
  if (!c.sys)
    c.sys = std::shared_ptr<const AssembledSystem>(new AssembledSystem(s.problem->assemble(d)));
  return *c.sys;
}

/// CPU time of the process so far (all threads), user and system (kernel: page faults).
struct CpuTimes {
  double user = 0, sys = 0;
  static CpuTimes now() {
    rusage r{};
    getrusage(RUSAGE_SELF, &r);
    return {r.ru_utime.tv_sec + 1e-6 * r.ru_utime.tv_usec,
            r.ru_stime.tv_sec + 1e-6 * r.ru_stime.tv_usec};
  }
};

/// user/particle and sys/particle: CPU seconds per iteration and particle spent in user space
/// (the arithmetic) and in the kernel (mostly first-touch page faults of fresh allocations,
/// which glibc hands out for every block above its mmap threshold, up to 32 MB, but recycles
/// below it: small cases repeated in a loop do not pay them, a 10^5 or 10^6 case does).
void set_cpu_counters(benchmark::State& state, const CpuTimes& before, double particles) {
  const CpuTimes after = CpuTimes::now();
  const double per = static_cast<double>(state.iterations()) * particles;
  if (per <= 0) return;
  state.counters["user/particle"] = (after.user - before.user) / per;
  state.counters["sys/particle"] = (after.sys - before.sys) / per;
}

void set_peak_counter(benchmark::State& state) {
  state.counters["peak_rss_MB"] = static_cast<double>(bench::peak_resident_bytes()) / 1e6;
}

/// Per-particle figures from the mean wall time of one run of the timed stage. Inverted
/// rates print as times: "time/particle" 4.5us means 4.5 microseconds per particle.
void set_counters(benchmark::State& state, const Discretization& d) {
  using benchmark::Counter;
  const double particles = d.particles.size();
  state.counters["particles"] = particles;
  state.counters["qpoints"] = d.quadrature.size();
  state.counters["time/particle"] =
      Counter(particles, Counter::kIsIterationInvariantRate | Counter::kInvert);
}

void set_system_counters(benchmark::State& state, const AssembledSystem& sys) {
  state.counters["unknowns"] = sys.K.rows();
  state.counters["nnz"] = sys.K.nonZeros();
}

/// Runs `body` under the benchmark's timer. A method that cannot build or solve its system
/// (singular moment matrix or global matrix) is reported as an error row, not an abort, so
/// the other cases still run.
template <class F>
bool guarded(benchmark::State& state, F&& body) {
  try {
    body();
    return true;
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return false;
  }
}

/// Estimated memory of a case at `particles` from the same method's 10^3 discretization: its
/// table entries per particle (integration points × support size) at 28 bytes each (index,
/// value, two gradients) for the trial and, when different, the test table, plus K (about
/// 4 entries per coupled particle pair, 12 bytes each) and the transposed table of the
/// assembly (8 bytes per entry), doubled: efg-ci's measured peak at 10^6 (14.2 GB) was 1.75×
/// that sum (8.1 GB), the rest being the discretization's other arrays and the neighbour
/// search. Supports keep their size under refinement of the lattice.
double estimated_case_bytes(const Setup& s, int particles) {
  const Discretization small = s.method->discretize(
      s.domain, s.problem->particles(kDepths[0], 0.0), s.order);
  const double n0 = small.particles.size();
  double entries = small.trial_q.entries();
  if (small.test_q.index != small.trial_q.index || small.test_q.grad != small.trial_q.grad)
    entries += small.test_q.entries();
  const AssembledSystem sys = s.problem->assemble(small);
  const double per_particle =
      (entries * (28.0 + 8.0) + static_cast<double>(sys.K.nonZeros()) * 12.0) / n0;
  return 2.0 * per_particle * particles;
}

/// Skips a 10^6 case whose estimate exceeds the available memory (with the figures).
bool fits_in_memory(benchmark::State& state, const Setup& s, int particles) {
  if (particles < 500000) return true;
  double need = 0;
  // A method that fails at 10^3 reports its own error in the case itself.
  if (!guarded(state, [&] { need = estimated_case_bytes(s, particles); })) return false;
  const double have = static_cast<double>(available_memory_bytes());
  if (have == 0 || need < have) return true;
  state.SkipWithError(fmt::format("estimated {:.1f} GB (twice the tables, transposed table and K) exceed "
                                  "the {:.1f} GB available",
                                  need / 1e9, have / 1e9)
                          .c_str());
  return false;
}

void BM_CantileverSetup(benchmark::State& state, const char* method) {
  const Setup s = make_setup(method);
  const int n = static_cast<int>(state.range(0));
  if (!fits_in_memory(state, s, n)) return;
  const ParticleSet particles = s.problem->particles(depth_of(n), 0.0);
  Discretization d;
  bench::reset_peak_resident();
  for (auto _ : state) {
    // The assignment frees the previous iteration's tables, as a scope exit would.
    if (!guarded(state, [&] { d = s.method->discretize(s.domain, particles, s.order); })) break;
    benchmark::DoNotOptimize(d.trial_q.value.data());
    benchmark::ClobberMemory();
  }
  if (state.error_occurred()) return;
  set_peak_counter(state);
  set_counters(state, d);
  Cached& c = cached(method, n);
  if (!c.d) c.d = std::make_shared<const Discretization>(std::move(d));
}

void BM_CantileverAssembly(benchmark::State& state, const char* method) {
  const Setup s = make_setup(method);
  const int n = static_cast<int>(state.range(0));
  const Discretization* d = nullptr;
  if (!fits_in_memory(state, s, n)) return;
  // An error before the loop skips the benchmark (the library then does not run it).
  if (!guarded(state, [&] { d = &discretization(s, method, n); })) return;
  // Built in place (new T(prvalue) elides the copy): Eigen 3.4's SparseMatrix has no move
  // assignment, so `sys = assemble(d)` would time a deep copy of K on top of the assembly.
  std::unique_ptr<AssembledSystem> sys;
  bench::reset_peak_resident();
  const CpuTimes cpu = CpuTimes::now();
  for (auto _ : state) {
    // The previous iteration's system is freed first, as a scope exit would.
    sys.reset();
    if (!guarded(state, [&] { sys.reset(new AssembledSystem(s.problem->assemble(*d))); })) break;
    benchmark::DoNotOptimize(sys->K.valuePtr());
    benchmark::ClobberMemory();
  }
  if (state.error_occurred()) return;
  set_cpu_counters(state, cpu, d->particles.size());
  set_peak_counter(state);
  set_counters(state, *d);
  set_system_counters(state, *sys);
  Cached& c = cached(method, n);
  if (!c.sys) c.sys = std::shared_ptr<const AssembledSystem>(std::move(sys));
}

void BM_CantileverSolve(benchmark::State& state, const char* method) {
  const Setup s = make_setup(method);
  const int n = static_cast<int>(state.range(0));
  const Discretization* d = nullptr;
  const AssembledSystem* sys = nullptr;
  if (!guarded(state, [&] {
        sys = &assembled(s, method, n);
        d = &discretization(s, method, n);
      }))
    return;
  SolveInfo info;
  bench::reset_peak_resident();
  for (auto _ : state) {
    Eigen::VectorXd u;
    if (!guarded(state, [&] { u = solve_constrained(*sys, *d, info); })) break;
    benchmark::DoNotOptimize(u.data());
    benchmark::ClobberMemory();
  }
  if (state.error_occurred()) return;
  set_peak_counter(state);
  set_counters(state, *d);
  set_system_counters(state, *sys);
  state.counters["fill"] = static_cast<double>(info.fill);
  // "auto" may fall back to an iterative solver: the label says which solver was timed.
  state.SetLabel(info.solver);
}

using BenchFn = void (*)(benchmark::State&, const char*);

void add(const char* family, BenchFn fn, const char* method, int depth) {
  const int particles = lattice_particles(depth);
  auto* b = benchmark::RegisterBenchmark((std::string(family) + "/" + method).c_str(), fn, method);
  b->Arg(particles)->Unit(benchmark::kMillisecond)->UseRealTime();
  // 10^3 and 10^4 repeat until half a second has passed. A 10^5 case takes 0.6-47 s and
  // up to 5.4 GB per run: one iteration, so the cantilever set finishes in a few minutes
  // on 2 cores (a second would also hold two systems at once).
  if (particles > 50000)
    b->Iterations(1);
  else
    b->MinTime(0.5);
}

/// Registers the cantilever benchmarks case by case (method, then size, then the three
/// stages), so the one-entry cache serves Assembly and Solve from Setup's work.
bool register_cantilever_benchmarks() {
  for (const char* method : kMethods)
    for (int depth : kDepths) {
      if (depth == kMillionDepth) {
        if (!million_requested()) continue;
        bool listed = false;
        for (const char* m : kMillionMethods) listed = listed || std::string(m) == method;
        if (!listed) continue;
        // No solve: UMFPACK's factors at 10^6 would pass the machine's memory.
        add("BM_CantileverSetup", BM_CantileverSetup, method, depth);
        add("BM_CantileverAssembly", BM_CantileverAssembly, method, depth);
        continue;
      }
      add("BM_CantileverSetup", BM_CantileverSetup, method, depth);
      add("BM_CantileverAssembly", BM_CantileverAssembly, method, depth);
      // The meshfree systems at 10^5 particles (27 M non-zeros of K) are not solved: the
      // sparse LU grows like N^2 here (6 s at 10^4) and its factors would pass 6 GB.
      if (depth < 100 || std::string(method) == "fem")
        add("BM_CantileverSolve", BM_CantileverSolve, method, depth);
    }
  return true;
}

// Registered during static initialization, as the BENCHMARK macros do, so the program's
// main (bench_shape_functions.cpp) runs these too without knowing about this file.
[[maybe_unused]] const bool kRegistered = register_cantilever_benchmarks();

}  // namespace
