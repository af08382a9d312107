#!/usr/bin/env bash
# Particle-steps/s of mfv's explicit engine on the 2D dam break beside PySPH (issue 16), measured
# in one invocation: (a) PySPH, then (b) mfv, same machine, same a, dx and number of steps.
#
#   bench/peer_dam_break.sh                    # a = 0.1 m, dx = 5 mm, steps to T = 3, 1 thread
#   DX=0.0025 THREADS=2 bench/peer_dam_break.sh
#   MFV_CMD='build/release/apps/mfv run dam-break -m sph -n {NX} --problem-params ...' bench/...
#
# Writes bench/results/dam_break_peer.json (both sides, nproc, threads, ratio) and prints one
# ratio line. Rate = fluid particles x steps / CPU seconds of the time loop on each side (mfv
# reports its loop on the process CPU clock, so PySPH's loop is timed the same way; PySPH's
# wall-clock figure is in the JSON too). With THREADS > 1 CPU time sums the threads, so compare
# the wall figures then. Exit 0 both sides ran; 2 the mfv side is not available (mfv exits 2,
# e.g. it does not know the problem, or is not built; the PySPH side is still written); 1 mfv
# failed (its exit 1: unstable, out of memory) or PySPH failed.
set -euo pipefail

# mfv's command; placeholders: {NX} = a/dx (particles across the column), {N} = fluid
# particles, {A}, {DX} (metres), {DT} (PySPH's fixed step, s), {STEPS}, {T_END} (in
# t sqrt(2g/a)), {THREADS}. mfv's dam-break: -n = particles across a, width = a; dt fixed to
# PySPH's so both run the same steps (mfv's own default, 0.5 of its critical step, is ~3.5x
# larger); no VTK frames.
MFV_CMD=${MFV_CMD:-"build/release/apps/mfv run dam-break -m sph -n {NX} --problem-params frame=eulerian,width={A},tank=4,end_T={T_END},dt={DT},frames=0,threads={THREADS}"}
PYTHON=${PYTHON:-/usr/bin/python3}   # Debian's interpreter: python3-pysph lives there
A=${A:-0.1}
DX=${DX:-0.005}
T_END=${T_END:-3}
THREADS=${THREADS:-1}
OUT=${OUT:-bench/results/dam_break_peer.json}

cd "$(dirname "$0")/.."
case "$THREADS" in 1|2) ;; *) echo "THREADS must be 1 or 2, got '$THREADS'" >&2; exit 2 ;; esac
NPROC=$(OMP_NUM_THREADS='' OMP_THREAD_LIMIT='' nproc)  # nproc obeys OMP_NUM_THREADS: ask before it is set
export OMP_NUM_THREADS=$THREADS
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The step both sides take, PySPH's fixed 0.25 h / c0 (h = 1.2 dx), and the count to T_END.
DT=$("$PYTHON" -c "import math; print(repr(0.25 * 1.2 * $DX / math.sqrt(7 * 4.704e5 / 1000)))")
STEPS=${STEPS:-$("$PYTHON" -c "
import math
print(math.ceil($T_END / math.sqrt(2 * 9.81 / $A) / $DT - 1e-9))")}
NX=$("$PYTHON" -c "print(round($A / $DX))")
N=$((NX * 2 * NX))

echo "nproc $NPROC, threads $THREADS, a = $A m, dx = $DX m, $N fluid particles, $STEPS steps"
echo "(a) PySPH"
"$PYTHON" bench/peers/pysph_dam_break.py --a "$A" --dx "$DX" --steps "$STEPS" \
  --threads "$THREADS" --series "$tmp/pysph_series.csv" | tee "$tmp/pysph.out"
tail -n 1 "$tmp/pysph.out" > "$tmp/pysph.json"

cmd=${MFV_CMD//\{NX\}/$NX}
cmd=${cmd//\{N\}/$N}
cmd=${cmd//\{A\}/$A}
cmd=${cmd//\{DX\}/$DX}
cmd=${cmd//\{STEPS\}/$STEPS}
cmd=${cmd//\{T_END\}/$T_END}
cmd=${cmd//\{DT\}/$DT}
cmd=${cmd//\{THREADS\}/$THREADS}
echo "(b) mfv: $cmd"
mfv_rc=0
w0=$(date +%s.%N)
# shellcheck disable=SC2086  # the command is a word list on purpose
$cmd > "$tmp/mfv.out" 2>&1 || mfv_rc=$?
w1=$(date +%s.%N)
cat "$tmp/mfv.out"
mfv_ok=1
if [[ $mfv_rc -ne 0 ]] || ! grep -q 'time loop' "$tmp/mfv.out"; then
  mfv_ok=0
fi

status=$("$PYTHON" - "$tmp" "$OUT" "$mfv_ok" "$mfv_rc" "$w0" "$w1" "$cmd" "$N" "$THREADS" "$NPROC" <<'EOF'
import json, os, re, sys
tmp, out, ok, rc, w0, w1, cmd, n, threads, nproc = sys.argv[1:]
peer = json.load(open(os.path.join(tmp, "pysph.json")))
text = open(os.path.join(tmp, "mfv.out")).read()
res = {"nproc": int(nproc), "threads": int(threads), "fluid_particles": int(n),
       "pysph": peer, "mfv": None, "ratio_mfv_over_pysph": None}
if ok == "1":
    steps = re.search(r"^steps\s+(\d+)", text, re.M)
    nodes = re.search(r"^nodes\s+(\d+)", text, re.M)
    loop = re.search(r"time loop ([0-9.eE+-]+) s \(([0-9.eE+-]+) particle-steps/s\)", text)
    if not (steps and loop):
        ok = "0"
    else:
        s, loop_s = int(steps.group(1)), float(loop.group(1))
        res["mfv"] = {
            "command": cmd, "steps": s, "nodes": int(nodes.group(1)) if nodes else None,
            "loop_cpu_seconds": loop_s, "reported_particle_steps_per_s": float(loop.group(2)),
            "particle_steps_per_cpu_s": int(n) * s / loop_s if loop_s > 0 else None,
            "command_wall_seconds": float(w1) - float(w0),
        }
        if res["mfv"]["particle_steps_per_cpu_s"]:
            res["ratio_mfv_over_pysph"] = (res["mfv"]["particle_steps_per_cpu_s"]
                                           / peer["particle_steps_per_cpu_s"])
        # Wall clock: mfv's whole command (its setup is milliseconds) against PySPH's loop.
        mw = res["mfv"]["command_wall_seconds"]
        res["mfv"]["particle_steps_per_wall_s"] = int(n) * s / mw
        res["ratio_wall_mfv_over_pysph"] = int(n) * s / mw / peer["particle_steps_per_s"]
        res["same_steps"] = s == peer["steps"]
if ok != "1":
    res["mfv_unavailable"] = f"exit {rc}; output: " + text.strip().splitlines()[-1][:200] \
        if text.strip() else f"exit {rc}, no output"
os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
with open(out, "w") as f:
    json.dump(res, f, indent=1)
    f.write("\n")
if res["ratio_mfv_over_pysph"] is not None:
    m = res["mfv"]
    print(f"ratio mfv/pysph = {res['ratio_mfv_over_pysph']:.3g} "
          f"(mfv {m['particle_steps_per_cpu_s']:.3g}, pysph {peer['particle_steps_per_cpu_s']:.3g}"
          f" fluid particle-steps per CPU s; {n} particles, steps {m['steps']} / {peer['steps']},"
          f" {threads} thread(s), nproc {res['nproc']}); wall-clock ratio "
          f"{res['ratio_wall_mfv_over_pysph']:.3g}")
else:
    print("unavailable")
EOF
)
echo "$status"
echo "wrote $OUT"
if [[ $status == unavailable ]]; then
  if [[ $mfv_rc -eq 1 ]]; then
    echo "mfv side failed (exit 1, see its output above)" >&2
    exit 1
  fi
  echo "mfv side not available (exit $mfv_rc, or no 'time loop' line in its output): only the PySPH side was measured" >&2
  exit 2
fi
