/// Throughput of the total-Lagrangian engine on PETSc (dynamics/petsc_dynamics.hpp) against the
/// native engine (dynamics/explicit.hpp) on bench_dynamics's rod: 60 × 5 mm plane strain, St
/// Venant–Kirchhoff E = 210 GPa, ν = 0, ρ = 7.8e-6 (mm, ms, kg, GPa), the Gaussian initial
/// velocity v_x = exp(−0.025(x−30)²), velocity Verlet at dt = 0.8 dt_crit (the critical ratio
/// from the power iteration on the 241 × 21 lattice, as bench_dynamics).
///
/// A plain program rather than a Google Benchmark one, because the PETSc runs are MPI jobs
/// whose ranks must time the same steps: one case per process,
///   bench_petsc_dynamics <method> <columns> native <threads> [along|across] [steps]
///   mpiexec -n <ranks> bench_petsc_dynamics <method> <columns> petsc 1 [along|across] [steps]
/// builds the rod with `columns` × ((columns − 1)/12 + 1) particles, the engine, the initial
/// velocity, takes 5 untimed steps, then times `steps` steps (default 3×10⁷ particle-steps,
/// at least 20) between barriers and prints one JSON object (rank 0): particle-steps per
/// second over the wall time and per CPU second (the process CPU time of the timed steps,
/// summed over the ranks: what the step costs, whatever else shares the cores), the set-up's wall seconds, the resident set (largest rank and
/// sum), and for PETSc each rank's halo (PetscHalo: ghost unknowns of F's MatMult and the
/// force's MatMultTranspose, halo bytes per step, operator bytes streamed per step); for the
/// native engine the bytes of its two tables streamed per step.
///
/// PETSc gives each rank a contiguous range of particle numbers, and the lattice numbers x
/// fastest. `along` (default) lays the rod along x, as bench_dynamics does: the ranges are
/// bands of rows, so the cut between two ranks runs the rod's length (481 particles at
/// 19,721). `across` lays the same rod along y: the ranges are bands of the length, and the
/// cut crosses the rod (41 particles), the partition a space-filling-curve numbering or a
/// graph partitioner would find. The physics is the same, turned by 90°.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "apps/catalogue.hpp"
#include "bench/bench_catalogue.hpp"
#include "bench/bench_memory.hpp"
#include "dynamics/petsc_dynamics.hpp"
#include "methods/core/petsc_session.hpp"
#include "methods/particles.hpp"

namespace {

using namespace mfv;

constexpr double kLength = 60, kDepth = 5, kYoung = 210, kPoisson = 0, kDensity = 7.8e-6;

Domain rod(bool across = false) {
  return across ? Domain::rectangle(0, 0, kDepth, kLength) : Domain::rectangle(0, 0, kLength, kDepth);
}
int rows_of(int nx) { return (nx - 1) / 12 + 1; }

ParticleSet rod_particles(int nx, bool across) {
  return across ? rectangle_lattice(rod(true), rows_of(nx), nx, Placement::boundary)
                : rectangle_lattice(rod(), nx, rows_of(nx), Placement::boundary);
}

DynamicsModel rod_model(const ParticleSet& particles) {
  Params mp;
  mp.set("E", kYoung);
  mp.set("nu", kPoisson);
  DynamicsModel model;
  model.material = bench::catalogue().materials.create("svk", mp);
  model.density = kDensity;
  model.mass = lumped_masses(particles, kDensity, MassLumping::volume);
  return model;
}

/// The Gaussian pulse along the rod's axis (x, or y for a rod laid `across`).
Eigen::MatrixXd rod_velocity(const ParticleSet& particles, bool across) {
  const int axis = across ? 1 : 0;
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, particles.size());
  for (int I = 0; I < particles.size(); ++I)
    v(axis, I) = std::exp(-0.025 * std::pow(particles.x(axis, I) - 0.5 * kLength, 2));
  return v;
}

/// dt_crit / (Δx/c) on the 241 × 21 lattice (the interior stencil sets it at any size).
double critical_ratio(const std::string& method) {
  const auto m = bench::catalogue().methods.create(method);
  const ParticleSet p = rectangle_lattice(rod(), 241, rows_of(241), Placement::boundary);
  DynamicsOptions opt;
  opt.threads = 1;
  ExplicitDynamics sim(*m, m->discretize(rod(), p, 1), rod_model(p), opt);
  return sim.critical_time_step() / (p.spacing / std::sqrt(kYoung / kDensity));
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

long table_bytes(const ShapeTable& t, int dim) {
  return static_cast<long>(t.entries()) * static_cast<long>(sizeof(int) + dim * sizeof(double));
}

int run(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr,
                 "usage: %s <method> <columns> native|petsc <threads> [along|across] [steps]\n",
                 argv[0]);
    return 2;
  }
  const std::string method = argv[1], engine = argv[3];
  const int nx = std::atoi(argv[2]), threads = std::atoi(argv[4]);
  const std::string orientation = argc > 5 ? argv[5] : "along";
  long steps = argc > 6 ? std::atol(argv[6]) : 0;
  if (nx < 13 || (nx - 1) % 12 != 0 || threads < 1 || (engine != "native" && engine != "petsc") ||
      (orientation != "along" && orientation != "across")) {
    std::fprintf(stderr, "columns must be 12k + 1 >= 13, threads >= 1, engine native|petsc, "
                         "orientation along|across\n");
    return 2;
  }
  const bool across = orientation == "across";
  const bool distributed = engine == "petsc";
  if (distributed) petsc::ensure_initialized();
  const int rank = petsc::rank(), ranks = petsc::size();
  const double ratio = critical_ratio(method);
  const auto m = bench::catalogue().methods.create(method);
  const ParticleSet particles = rod_particles(nx, across);
  const int n = particles.size();
  if (steps <= 0) steps = std::max(20L, std::lround(3e7 / n));
  const double dt = 0.8 * ratio * particles.spacing / std::sqrt(kYoung / kDensity);
  const double t_setup = now();
  Discretization d = m->discretize(rod(across), particles, 1);
  const int nq = d.quadrature.size();
  const long native_bytes = table_bytes(d.trial_q, 2) + table_bytes(d.test_q, 2);
  DynamicsOptions opt;
  opt.threads = threads;
  std::unique_ptr<DynamicsEngine> sim =
      make_dynamics_engine(engine, *m, std::move(d), rod_model(particles), opt);
  sim->set_particle_velocity(rod_velocity(particles, across));
  const double setup = now() - t_setup;
  for (int s = 0; s < 5; ++s) sim->step(dt);
  if (distributed) MPI_Barrier(PETSC_COMM_WORLD);
  const double t0 = now(), c0 = cpu_seconds();
  for (long s = 0; s < steps; ++s) sim->step(dt);
  double cpu = cpu_seconds() - c0;
  if (distributed) MPI_Barrier(PETSC_COMM_WORLD);
  const double wall = now() - t0;
  if (!sim->fields_finite() || !std::isfinite(sim->energy().kinetic)) {
    std::fprintf(stderr, "the run blew up\n");
    return 1;
  }
  double rss = bench::resident_gb(), rss_max = rss, rss_sum = rss;
  std::string halo = "null";
  if (distributed) {
    MPI_Allreduce(&rss, &rss_max, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
    MPI_Allreduce(&rss, &rss_sum, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    const double cpu_rank = cpu;
    MPI_Allreduce(&cpu_rank, &cpu, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    const PetscHalo h = dynamic_cast<PetscDynamics&>(*sim).halo();
    const long mine[6] = {h.owned_points, h.owned_unknowns, h.ghost_trial,
                          h.ghost_test,   h.halo_bytes,     h.matrix_bytes};
    std::vector<long> all(6 * ranks);
    MPI_Gather(mine, 6, MPI_LONG, all.data(), 6, MPI_LONG, 0, PETSC_COMM_WORLD);
    halo = "[";
    for (int r = 0; r < ranks; ++r)
      halo += fmt::format("{}{{\"rank\": {}, \"owned_points\": {}, \"owned_unknowns\": {}, "
                          "\"ghost_trial\": {}, \"ghost_test\": {}, \"halo_bytes_per_step\": {}, "
                          "\"operator_bytes_per_step\": {}}}",
                          r ? ", " : "", r, all[6 * r], all[6 * r + 1], all[6 * r + 2],
                          all[6 * r + 3], all[6 * r + 4], all[6 * r + 5]);
    halo += "]";
  }
  if (rank == 0)
    std::printf("{\"method\": \"%s\", \"engine\": \"%s\", \"ranks\": %d, \"threads\": %d, "
                "\"orientation\": \"%s\", "
                "\"particles\": %d, \"qpoints\": %d, \"steps\": %ld, \"wall_s\": %.4f, "
                "\"particle_steps_per_s\": %.4g, \"cpu_s\": %.4f, "
                "\"particle_steps_per_cpu_s\": %.4g, \"setup_s\": %.2f, \"rss_GB_max_rank\": %.3f, "
                "\"rss_GB_sum\": %.3f, \"native_table_bytes_per_step\": %ld, \"halo\": %s}\n",
                method.c_str(), engine.c_str(), ranks, threads, orientation.c_str(), n, nq, steps,
                wall,
                static_cast<double>(n) * steps / wall, cpu, static_cast<double>(n) * steps / cpu,
                setup, rss_max, rss_sum, native_bytes,
                halo.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_petsc_dynamics: %s\n", e.what());
    return 1;
  }
}
