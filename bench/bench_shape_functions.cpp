/// Speed of the pipeline stages that scale with the node count, on laplace-tanh's domain
/// [0, 6] with N equally spaced nodes (N = 10^3, 10^4, 10^5):
///   BM_ShapeFunctions  Method::discretize: dilations, quadrature rule, neighbour search and
///                      shape functions with first derivatives at every quadrature point.
///   BM_Evaluate        Approximation::evaluate alone on the quadrature points of a fixed
///                      discretization (neighbour search + moment matrices, no quadrature).
///   BM_Assembly        Problem::assemble: the global stiffness matrix and load vector.
///   BM_Solve           solve_constrained: Lagrange-multiplier system and sparse LU.
/// Counters: points/s (quadrature points per second), nodes/s, time/node (wall time of one
/// run divided by the node count). Speed is measured here only; the tests carry no timing assertions.
#include <algorithm>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "problems/problem.hpp"
#include "verify/catalogue.hpp"
#include "verify/runner.hpp"

namespace {

using namespace mfv;

/// One catalogue for the whole program (registries hold references into it).
const Catalogue& catalogue() {
  static const Catalogue c;
  return c;
}

struct MethodCase {
  const char* label;   ///< benchmark name suffix
  const char* method;  ///< catalogue name
  const char* params;  ///< Params::parse text
};

// efg: MLS, linear basis, cubic-window weight, dmax = 2, 10 Gauss points per cell (defaults).
// rkpm: linear correction, j = 1 (a = 2^j·(2/√π)Δx Gaussian, 2^{j+0.5}Δx cubic window).
// fem: linear elements, the reference. All use the method's default 10 Gauss points per cell.
const MethodCase kCases[] = {
    {"fem", "fem", ""},
    {"efg", "efg", ""},
    {"rkpm-gaussian", "rkpm", "kernel=gaussian,j=1"},
    {"rkpm-cubic", "rkpm", "kernel=cubic-window,j=1"},
};

struct Setup {
  std::unique_ptr<Problem> problem;
  std::unique_ptr<Method> method;
  Domain domain;
  int order = 1;
};

Setup make_setup(const MethodCase& mc) {
  Setup s;
  s.problem = catalogue().problems.create("laplace-tanh", {});
  s.method = catalogue().methods.create(mc.method, Params::parse(mc.params));
  s.domain = s.problem->domain();
  s.order = s.problem->derivative_order();
  return s;
}

/// Per-node and per-point figures, from the mean wall time of one run of the timed stage.
/// Inverted rates print as times: "time/node" 4.5us means 4.5 microseconds per node.
void set_counters(benchmark::State& state, int nodes, int points) {
  using benchmark::Counter;
  state.counters["nodes"] = nodes;
  state.counters["qpoints"] = points;
  state.counters["points/s"] =
      Counter(static_cast<double>(points), Counter::kIsIterationInvariantRate);
  state.counters["nodes/s"] =
      Counter(static_cast<double>(nodes), Counter::kIsIterationInvariantRate);
  state.counters["time/node"] = Counter(static_cast<double>(nodes),
                                        Counter::kIsIterationInvariantRate | Counter::kInvert);
}

void BM_ShapeFunctions(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const ParticleSet particles = uniform_line(s.domain, n, 0);
  int nq = 0;
  for (auto _ : state) {
    Discretization d = s.method->discretize(s.domain, particles, s.order);
    nq = d.quadrature.size();
    benchmark::DoNotOptimize(d.trial_q.value.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, n, nq);
}

void BM_Evaluate(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const Discretization d = s.method->discretize(s.domain, uniform_line(s.domain, n, 0), s.order);
  for (auto _ : state) {
    ShapeTable t = d.trial->evaluate(d.particles, d.quadrature.points, s.order);
    benchmark::DoNotOptimize(t.value.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, n, d.quadrature.size());
  state.counters["entries/pt"] =
      static_cast<double>(d.trial_q.entries()) / std::max(1, d.trial_q.points());
}

void BM_Assembly(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const Discretization d = s.method->discretize(s.domain, uniform_line(s.domain, n, 0), s.order);
  for (auto _ : state) {
    AssembledSystem sys = s.problem->assemble(d);
    benchmark::DoNotOptimize(sys.K.valuePtr());
    benchmark::ClobberMemory();
  }
  set_counters(state, n, d.quadrature.size());
}

void BM_Solve(benchmark::State& state, MethodCase mc) {
  const Setup s = make_setup(mc);
  const int n = static_cast<int>(state.range(0));
  const Discretization d = s.method->discretize(s.domain, uniform_line(s.domain, n, 0), s.order);
  const AssembledSystem sys = s.problem->assemble(d);
  SolveInfo info;
  for (auto _ : state) {
    Eigen::VectorXd u = solve_constrained(sys, d, info);
    benchmark::DoNotOptimize(u.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, n, d.quadrature.size());
  state.counters["nnz"] = static_cast<double>(info.nonzeros);
}

using BenchFn = void (*)(benchmark::State&, MethodCase);

void register_family(const char* family, BenchFn fn) {
  for (const MethodCase& mc : kCases) {
    auto* b = benchmark::RegisterBenchmark((std::string(family) + "/" + mc.label).c_str(), fn, mc);
    b->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();
    // Keep the whole program within a few minutes on 2 cores: the 10^5-node cases take
    // tenths of a second per iteration, so a short minimum time is enough for a stable mean.
    b->MinTime(0.2);
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
