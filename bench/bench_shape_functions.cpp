/// Speed of the pipeline stages that scale with the node count, on laplace-tanh's domain
/// [0, 6] with N equally spaced nodes (N = 10^3, 10^4, 10^5):
///   BM_ShapeFunctions  Method::discretize: dilations, quadrature rule, neighbour search and
///                      shape functions with first derivatives at every quadrature point.
///   BM_Evaluate        Approximation::evaluate alone on the quadrature points of a fixed
///                      discretization (neighbour search + moment matrices, no quadrature).
///   BM_Assembly        BoundaryValueProblem::assemble: the global stiffness matrix and load vector.
///   BM_Solve           solve_constrained: Lagrange-multiplier system and sparse LU.
/// Counters: points/s (quadrature points per second), nodes/s, time/node (wall time of one
/// run divided by the node count). Speed is measured here only: tests assert no timings.
#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include <benchmark/benchmark.h>

#include "problems/problem.hpp"
#include "apps/catalogue.hpp"
#include "bench/bench_catalogue.hpp"
#include "analyses/static_solve.hpp"
#include "verify/runner.hpp"

namespace {

using namespace mfv;

/// One catalogue for the whole program (registries hold references into it).
using bench::catalogue;

struct MethodCase {
  const char* label;   ///< benchmark name suffix
  const char* method;  ///< catalogue name
  const char* params;  ///< Params::parse text
};

// efg: MLS, linear basis, cubic-window weight, dmax = 2 (defaults).
// rkpm: linear correction, j = 1 (a = 2^j·(2/√π)Δx Gaussian, 2^{j+0.5}Δx cubic window).
// fem: linear elements, the reference. All use the default 10 Gauss points per cell.
// rkpm-gaussian is the slow one: the Gaussian truncated at 6 dilations covers ~27 particles
// per point (cubic window ~5), and assembly cost grows with that count squared; its 10^5-node
// assembly is the longest single iteration of the program (~20 s on 2 cores).
const MethodCase kCases[] = {
    {"fem", "fem", ""},
    {"efg", "efg", ""},
    {"rkpm-gaussian", "rkpm", "kernel=gaussian,j=1"},
    {"rkpm-cubic", "rkpm", "kernel=cubic-window,j=1"},
};

struct Setup {
  std::unique_ptr<BoundaryValueProblem> problem;
  std::unique_ptr<Method> method;
  Domain domain;
  int order = 1;
};

Setup make_setup(const MethodCase& mc) {
  Setup s;
  s.problem = catalogue().problems.create_as<BoundaryValueProblem>("laplace-tanh", {});
  s.method = catalogue().methods.create(mc.method, Params::parse(mc.params));
  s.domain = s.problem->domain();
  s.order = s.problem->derivative_order();
  return s;
}

/// Discretizations and assembled systems are kept across families (key "label/N"), so each
/// is built once: BM_ShapeFunctions leaves its last discretization for BM_Evaluate,
/// BM_Assembly and BM_Solve, BM_Assembly its last system for BM_Solve. A family run alone
/// (--benchmark_filter) builds what it needs outside the timing loop.
struct Cached {
  std::shared_ptr<const Discretization> d;
  std::shared_ptr<const AssembledSystem> sys;
};
std::map<std::string, Cached>& cache() {
  static std::map<std::string, Cached> c;
  return c;
}
std::string key(const MethodCase& mc, int n) {
  return std::string(mc.label) + "/" + std::to_string(n);
}

const Discretization& discretization(const Setup& s, const MethodCase& mc, int n) {
  Cached& c = cache()[key(mc, n)];
  if (!c.d)
    c.d = std::make_shared<const Discretization>(
        s.method->discretize(s.domain, uniform_line(s.domain, n, 0), s.order));
  return *c.d;
}

const AssembledSystem& assembled(const Setup& s, const MethodCase& mc, int n) {
  Cached& c = cache()[key(mc, n)];
  if (!c.sys)
    c.sys = std::make_shared<const AssembledSystem>(s.problem->assemble(discretization(s, mc, n)));
  return *c.sys;
}

/// Per-node and per-point figures, from the mean wall time of one run of the timed stage.
/// Inverted rates print as times: "time/node" 4.5us means 4.5 microseconds per node.
void set_counters(benchmark::State& state, const Discretization& d) {
  using benchmark::Counter;
  const double nodes = d.particles.size(), points = d.quadrature.size();
  state.counters["nodes"] = nodes;
  state.counters["qpoints"] = points;
  state.counters["entries/pt"] = d.trial_q.entries() / std::max(1.0, points);
  state.counters["points/s"] = Counter(points, Counter::kIsIterationInvariantRate);
  state.counters["nodes/s"] = Counter(nodes, Counter::kIsIterationInvariantRate);
  state.counters["time/node"] =
      Counter(nodes, Counter::kIsIterationInvariantRate | Counter::kInvert);
}

void BM_ShapeFunctions(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const ParticleSet particles = uniform_line(s.domain, n, 0);
  Discretization d;
  for (auto _ : state) {
    // The assignment frees the previous iteration's tables, as a scope exit would.
    d = s.method->discretize(s.domain, particles, s.order);
    benchmark::DoNotOptimize(d.trial_q.value.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, d);
  Cached& c = cache()[key(mc, n)];
  if (!c.d) c.d = std::make_shared<const Discretization>(std::move(d));
}

void BM_Evaluate(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const Discretization& d = discretization(s, mc, n);
  for (auto _ : state) {
    ShapeTable t = d.trial->evaluate(d.particles, d.quadrature.points, s.order);
    benchmark::DoNotOptimize(t.value.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, d);
}

void BM_Assembly(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const Discretization& d = discretization(s, mc, n);
  AssembledSystem sys;
  for (auto _ : state) {
    sys = s.problem->assemble(d);
    benchmark::DoNotOptimize(sys.K.valuePtr());
    benchmark::ClobberMemory();
  }
  set_counters(state, d);
  Cached& c = cache()[key(mc, n)];
  if (!c.sys) c.sys = std::make_shared<const AssembledSystem>(std::move(sys));
}

void BM_Solve(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const Discretization& d = discretization(s, mc, n);
  const AssembledSystem& sys = assembled(s, mc, n);
  SolveInfo info;
  for (auto _ : state) {
    Eigen::VectorXd u = solve_constrained(sys, d, info);
    benchmark::DoNotOptimize(u.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, d);
  state.counters["nnz"] = static_cast<double>(info.nonzeros);
}

using BenchFn = void (*)(benchmark::State&, MethodCase);

const int kNodes[] = {1000, 10000, 100000};

void register_family(const char* family, BenchFn fn) {
  for (const MethodCase& mc : kCases) {
    auto* b = benchmark::RegisterBenchmark((std::string(family) + "/" + mc.label).c_str(), fn, mc);
    for (int n : kNodes) b->Arg(n);
    b->Unit(benchmark::kMillisecond)->UseRealTime();
    // Whole program ~80 s on 2 cores: 10^5-node cases take one iteration of 0.2-20 s,
    // small ones repeat until half a second has passed.
    b->MinTime(0.5);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_family("BM_ShapeFunctions", BM_ShapeFunctions);
  register_family("BM_Evaluate", BM_Evaluate);
  register_family("BM_Assembly", BM_Assembly);
  register_family("BM_Solve", BM_Solve);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
