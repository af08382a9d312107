/// Speed and memory of the static solve on the cantilever (001 §9.1) with PETSc (solver=petsc:
/// CG or GMRES + GAMG with the rigid-body near-null space; analyses/petsc_solver.hpp) next to
/// UMFPACK, at about 10^4 and 10^5 particles (51 and 159 across the depth: 10,251 and 100,647
/// particles), and 10^6 (501 across: 1,003,001) only when MFV_BENCH_PETSC_1E6=1:
///   BM_StaticSolve/<method>/<particles>/<solver>   solve_constrained: essential conditions
///                                                  and the linear solve (PETSc's set-up, AMG
///                                                  hierarchy included).
/// Counters: particles, unknowns, nnz of K, iterations (PETSc: Krylov iterations summed over
/// the multiplier updates), peak_rss_GB (the process's peak resident memory during the solve,
/// the set-up and the assembled system included: VmHWM, reset before each case). UMFPACK runs
/// where its factors fit: 10^4 for every method, fem at 10^5. Under mpirun every rank runs the
/// program; PETSc distributes the solve. Run:
///   build/release/bench/mfv_bench_petsc --benchmark_out=bench/results/petsc_solve.json
#include <cstdlib>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <benchmark/benchmark.h>

#include "analyses/static_solve.hpp"
#include "bench/bench_catalogue.hpp"
#include "bench/bench_memory.hpp"
#include "methods/core/petsc_session.hpp"

namespace {

using namespace mfv;
using bench::catalogue;

const char* const kMethods[] = {"fem", "efg-ni", "efg-ci", "kbm-si"};

constexpr int lattice_particles(int depth) { return (4 * (depth - 1) + 1) * depth; }

/// One case's discretization and system, kept while its solvers run (one case at a time: a
/// 10^6 meshfree system takes GBs).
struct Case {
  std::string key;
  std::unique_ptr<BoundaryValueProblem> problem;
  std::unique_ptr<Discretization> d;
  std::unique_ptr<AssembledSystem> sys;
};
Case& prepared(const char* method, int depth) {
  static Case c;
  const std::string key = std::string(method) + "/" + std::to_string(depth);
  if (c.key == key) return c;
  c = Case{};  // frees the previous case first
  c.problem = catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  const auto m = catalogue().methods.create(method);
  c.d = std::make_unique<Discretization>(m->discretize(
      c.problem->domain(), c.problem->particles(depth, 0.0), c.problem->derivative_order()));
  c.sys = std::make_unique<AssembledSystem>(c.problem->assemble(*c.d));
  c.key = key;
  return c;
}

void BM_StaticSolve(benchmark::State& state, const char* method, int depth, const char* solver) {
  SolveInfo info;
  Case* c = nullptr;
  try {
    c = &prepared(method, depth);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  bench::reset_peak_resident();
  SolverChoice choice;
  choice.kind = solver;
  for (auto _ : state) {
    try {
      const Eigen::VectorXd u = solve_constrained(*c->sys, *c->d, info, nullptr, choice);
      benchmark::DoNotOptimize(u.data());
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
  }
  if (state.error_occurred()) return;
  state.counters["particles"] = c->d->particles.size();
  state.counters["unknowns"] = static_cast<double>(c->sys->K.rows());
  state.counters["nnz"] = static_cast<double>(c->sys->K.nonZeros());
  state.counters["iterations"] = info.iterations;
  state.counters["residual"] = info.residual;
  state.counters["peak_rss_GB"] = bench::peak_resident_gb();
  state.counters["ranks"] = petsc::size();
  state.SetLabel(info.solver);
}

bool register_petsc_benchmarks() {
  std::vector<int> depths = {51, 159};
  if (const char* big = std::getenv("MFV_BENCH_PETSC_1E6"); big && std::string(big) == "1")
    depths.push_back(501);
  for (const char* method : kMethods)
    for (int depth : depths)
      for (const char* solver : {"petsc", "direct"}) {
        // UMFPACK's factors of the meshfree systems pass 6 GB at 10^5 (bench_cantilever.cpp).
        if (std::string(solver) == "direct" && depth > 51 && std::string(method) != "fem")
          continue;
        if (std::string(solver) == "direct" && depth > 159) continue;
        const std::string name = fmt::format("BM_StaticSolve/{}/{}/{}", method,
                                             lattice_particles(depth),
                                             std::string(solver) == "direct" ? "umfpack" : solver);
        benchmark::RegisterBenchmark(name.c_str(), BM_StaticSolve, method, depth, solver)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(1);
      }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // Under mpirun every rank must know its number before the first solve.
  if (petsc::launched_by_mpirun()) petsc::ensure_initialized();
  register_petsc_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
