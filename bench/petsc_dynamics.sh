#!/usr/bin/env bash
# Throughput of the PETSc dynamics engine at 1 and 2 MPI ranks against the native engine at 1
# and 2 OpenMP threads (bench/bench_petsc_dynamics.cpp), on the rod at 19,721 and 121,301
# particles for sph and kbm-si (and the PETSc engine at 2 ranks on the rod turned across the
# numbering, see bench_petsc_dynamics.cpp), and sph at 999,073 with LARGE=1 (about 3 GB per PETSc rank:
# check `free -g`). Every configuration runs REPS times (default 3), one process at a time;
# the JSON keeps every run and the best (highest throughput) of each configuration, since the
# other jobs on a shared machine only ever slow a run down. Waiting threads and ranks yield
# their core (OMP_WAIT_POLICY=passive, Open MPI's mpi_yield_when_idle): on a machine shared
# with other jobs, spinning waits multiply every stall.
#   bench/petsc_dynamics.sh [build dir]   → bench/results/petsc_dynamics.json (or $OUT)
#   COLUMNS=3457 OUT=bench/results/petsc_dynamics_1e6.json bench/petsc_dynamics.sh
#                                         → the 10⁶ set alone (COLUMNS: lattice columns)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/release}
exe=$build/bench/bench_petsc_dynamics
mpiexec=$(sed -n 's/^MPIEXEC_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
out=${OUT:-$root/bench/results/petsc_dynamics.json}
reps=${REPS:-3}
[[ -x $exe ]] || { echo "build bench_petsc_dynamics first" >&2; exit 1; }
[[ -n $mpiexec ]] || { echo "no MPIEXEC_EXECUTABLE in $build/CMakeCache.txt" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
runs=$(mktemp)
trap 'rm -f "$runs"' EXIT

one() {  # method columns engine threads-or-ranks [along|across]
  local load line
  load=$(cut -d' ' -f1 /proc/loadavg)
  if [[ $3 == native ]]; then
    line=$(OMP_NUM_THREADS=$4 OMP_WAIT_POLICY=passive nice "$exe" "$1" "$2" native "$4" "${5:-along}")
  else  # one OpenMP thread per rank: the ranks are the parallelism
    line=$(OMP_NUM_THREADS=1 nice "$mpiexec" -n "$4" --oversubscribe --mca mpi_yield_when_idle 1 \
             "$exe" "$1" "$2" petsc 1 "${5:-along}")
  fi
  echo "$line" | jq -c --argjson load "$load" '. + {load_before: $load}' | tee -a "$runs"
}

columns_set=${COLUMNS:-481 1201 ${LARGE:+3457}}
for columns in $columns_set; do
  for method in sph kbm-si; do
    # kbm-si at 10^6: the velocity fit alone takes minutes and ~8 GB per engine (README).
    [[ $columns == 3457 && $method != sph ]] && continue
    n=$reps
    [[ $columns == 3457 ]] && n=1
    for config in "native 1" "native 2" "petsc 1" "petsc 2"; do
      for ((r = 0; r < n; ++r)); do one "$method" "$columns" $config; done
    done
  done
done

# The same rods turned across the numbering (bench_petsc_dynamics.cpp): the contiguous split
# then cuts across the rod, the halo a good partition gives.
for columns in $columns_set; do
  for method in sph kbm-si; do
    [[ $columns == 3457 && $method != sph ]] && continue
    n=$reps
    [[ $columns == 3457 ]] && n=1
    for ((r = 0; r < n; ++r)); do one "$method" "$columns" petsc 2 across; done
  done
done

jq -s --arg cores "$(nproc)" --arg date "$(date -u +%FT%TZ)" '{
  machine: {cores: ($cores | tonumber), date: $date,
            note: "2 cores shared with other jobs: np = 2 and 2 threads compete with them"},
  best: (group_by([.method, .particles, .orientation, .engine, .ranks, .threads])
         | map(max_by(.particle_steps_per_s))
         | map({method, particles, orientation, engine, ranks, threads, particle_steps_per_s,
                particle_steps_per_cpu_s, load_before, setup_s,
                rss_GB_max_rank, rss_GB_sum, native_table_bytes_per_step,
                ghost_trial_per_rank: (if .halo then [.halo[].ghost_trial] else null end),
                halo_bytes_per_step_per_rank: (if .halo then [.halo[].halo_bytes_per_step]
                                               else null end),
                operator_bytes_per_step_per_rank: (if .halo then
                                                     [.halo[].operator_bytes_per_step]
                                                   else null end)})),
  runs: .
}' "$runs" > "$out"
echo "wrote $out"
