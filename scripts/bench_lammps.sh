#!/usr/bin/env bash
# LAMMPS MACHDYN (total-Lagrangian SPH) beside mfv's SPH on the rod pulse (issue 30, item 4).
#
#   scripts/bench_lammps.sh [--lammps-dir DIR] [--nodes 121,241,481] [--pysph 121]
#                           [--steps 1000] [--mfv PATH] [--peer-deck FILE]
#
# 1. Finds lmp: $MFV_LAMMPS, else DIR/lammps-*/build/lmp (DIR: --lammps-dir, $MFV_LAMMPS_DIR,
#    default /work/lammps). If there is none, builds LAMMPS with MACHDYN from Debian's source
#    package in DIR (root: adds a deb-src entry, apt-get source lammps, cmake, ninja -j2; about
#    5-30 minutes on 2 cores, under nice -n 19).
# 2. Runs the peer deck (/work/shared/peers/lammps_tlsph_rod_pulse.in, 20,090 particles) for
#    --steps steps and prints LAMMPS's own particle-steps/s from its "Loop time" line.
# 3. Runs `mfv run rod-pulse` with -m sph and -m external:lammps-machdyn (and external:pysph at
#    the --pysph resolutions) and prints one table: method, n, velocity error at L/c and 2L/c,
#    particle-steps per CPU second as mfv's run output states them (mfv's own methods: the time
#    loop's CPU; an external solver: the solver process's CPU, Python and file I/O included).
#
# Timings: OMP_NUM_THREADS=1, OMP_WAIT_POLICY=passive, nice -n 19; `uptime` is printed before
# and after: compare ratios within one run, not absolute times across runs. Not a CI test.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lammps_dir="${MFV_LAMMPS_DIR:-/work/lammps}"
nodes="121,241,481"
pysph_nodes=""
steps=1000
mfv="$here/build/release/apps/mfv"
deck="/work/shared/peers/lammps_tlsph_rod_pulse.in"

while [ $# -gt 0 ]; do
  case "$1" in
    --lammps-dir) lammps_dir="$2"; shift 2 ;;
    --nodes) nodes="$2"; shift 2 ;;
    --pysph) pysph_nodes="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    --mfv) mfv="$2"; shift 2 ;;
    --peer-deck) deck="$2"; shift 2 ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) echo "bench_lammps.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

export OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive
log() { echo "bench_lammps: $*" >&2; }

find_lmp() {
  if [ -n "${MFV_LAMMPS:-}" ]; then echo "$MFV_LAMMPS"; return; fi
  local f
  for f in "$lammps_dir"/lammps-*/build/lmp "$lammps_dir"/build/lmp "$lammps_dir"/lmp; do
    if [ -x "$f" ]; then echo "$f"; return; fi
  done
}

build_lammps() {
  log "no lmp under $lammps_dir: building LAMMPS with MACHDYN from Debian's source package"
  [ "$(id -u)" = 0 ] || { log "building needs root (apt); see docs/external-lammps.md"; exit 1; }
  if ! grep -rqsE '^(Types: deb-src|deb-src )' /etc/apt/sources.list.d/ /etc/apt/sources.list; then
    # The deb entries of debian.sources, as deb-src.
    sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources \
      > /etc/apt/sources.list.d/debian-src.sources
  fi
  apt-get update
  apt-get install -y --no-install-recommends cmake ninja-build g++ libeigen3-dev dpkg-dev
  mkdir -p "$lammps_dir"
  (cd "$lammps_dir" && apt-get source lammps)
  local src
  src="$(ls -d "$lammps_dir"/lammps-*/ | head -1)"
  mkdir -p "$src/build"
  local t0=$SECONDS
  (cd "$src/build" &&
     nice -n 19 cmake ../cmake -G Ninja -DCMAKE_BUILD_TYPE=Release -DPKG_MACHDYN=on \
       -DBUILD_MPI=off -DBUILD_OMP=off -DDOWNLOAD_EIGEN3=no &&
     nice -n 19 ninja -j2)
  log "LAMMPS built in $((SECONDS - t0)) s: $src/build/lmp"
}

if [ -n "${MFV_LAMMPS:-}" ] && [ ! -x "$MFV_LAMMPS" ]; then
  log "MFV_LAMMPS=$MFV_LAMMPS is not an executable file"; exit 1
fi
lmp="$(find_lmp)"
if [ -z "$lmp" ]; then
  build_lammps
  lmp="$(find_lmp)"
fi
[ -n "$lmp" ] || { log "no lmp after the build"; exit 1; }
"$lmp" -h | sed -n '/Installed packages/,/List of individual/p' | grep -qw MACHDYN ||
  { log "$lmp has no MACHDYN package"; exit 1; }
export MFV_LAMMPS="$lmp"
[ -x "$mfv" ] || { log "no mfv at $mfv (build it, or give --mfv)"; exit 1; }

echo "# bench_lammps.sh, $(date -u '+%Y-%m-%d %H:%M UTC'), $(getconf _NPROCESSORS_ONLN) CPUs, lmp: $lmp"
echo "# load before: $(uptime)"

# The peer deck: LAMMPS's own particle-steps/s.
work="$(mktemp -d /tmp/bench_lammps.XXXXXX)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && nice -n 19 "$lmp" -in "$deck" -var NSTEPS "$steps" -log none > peer.out 2>&1) ||
  { tail -20 "$work/peer.out" >&2; log "the peer deck failed"; exit 1; }
loop="$(grep '^Loop time' "$work/peer.out")"
echo "# peer deck $(basename "$deck"): $loop"
# "Loop time of T on P procs for S steps with N atoms"
echo "$loop" | awk '{ for (i = 1; i < NF; i++) { if ($i == "of") t = $(i + 1);
                        if ($i == "for") s = $(i + 1); if ($i == "with") n = $(i + 1) }
                      printf "# peer deck: %.3g particle-steps/s (%d atoms x %d steps / %.4g s)\n",
                             n * s / t, n, s, t }'

# mfv's run output: "velocity error at L/c      X", "CPU ... (Y particle-steps/s)".
run_mfv() {  # method n
  local out rc=0 tries=0
  while :; do
    out="$(nice -n 19 "$mfv" run rod-pulse -m "$1" -n "$2" 2>&1)" || rc=$?
    # mfv may be replaced by a rebuild for a minute: retry a missing binary.
    if [ $rc -ne 0 ] && [ ! -x "$mfv" ] && [ $tries -lt 6 ]; then
      tries=$((tries + 1)); rc=0; sleep 20; continue
    fi
    break
  done
  if [ $rc -ne 0 ]; then
    printf '%-26s %6s  failed: %s\n' "$1" "$2" "$(echo "$out" | tail -1 | cut -c1-160)"
    return
  fi
  echo "$out" | awk -v m="$1" -v n="$2" '
    /^velocity error at L\/c +[-+0-9.eEnaif]+$/ { l1 = $NF }
    /^velocity error at 2L\/c +[-+0-9.eEnaif]+$/ { l2 = $NF }
    /^CPU / && match($0, /\(([-+0-9.eE]+) particle-steps\/s\)/) {
      s = substr($0, RSTART + 1); sub(/ particle-steps\/s\)/, "", s) }
    END { printf "%-26s %6s  %12s %12s %14s\n", m, n, (l1 == "" ? "-" : l1),
                 (l2 == "" ? "-" : l2), (s == "" ? "-" : s) }'
}

printf '%-26s %6s  %12s %12s %14s\n' method n "err L/c" "err 2L/c" "p-steps/CPU s"
for n in ${nodes//,/ }; do
  run_mfv sph "$n"
  run_mfv external:lammps-machdyn "$n"
done
for n in ${pysph_nodes//,/ }; do
  run_mfv external:pysph "$n"
done
echo "# load after: $(uptime)"
