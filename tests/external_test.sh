#!/usr/bin/env bash
# External solvers through the command line (issue 30; docs/external-solvers.md):
#   1. solvers/fem-rod (the protocol's example) runs the rod pulse like any method: run,
#      compare beside sph with a report (page section, results.json valid against the
#      schema), and a manifest case judged by its bands;
#   2. refusals with exit 2: a problem or an analysis the solver does not support, a solver
#      defined twice, a broken solver file;
#   3. broken solvers (timeout, exit code, missing checkpoint, NaN, wrong particle count, not
#      installed) fail naming the cause, never with a number; the other studies still run.
# Usage: external_test.sh <mfv> <source dir>
set -u
mfv=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
checks=0
ok() { checks=$((checks + 1)); }

# 1. The example solver.
out=$("$mfv" run rod-pulse -m external:fem-rod -n 61 2>&1) || { echo "$out"; fail "run: exit $?"; }
err=$(echo "$out" | awk '/^velocity error at L\/c  /{print $NF}')
python3 -c "import sys; e=float('$err'); sys.exit(0 if 0 < e < 0.05 else 1)" ||
  { echo "$out"; fail "run: velocity error at L/c '$err' not in (0, 0.05)"; }
echo "$out" | grep -q "^solver    python3 .*fem_rod.py <case directory>: .* frames to t = " ||
  { echo "$out"; fail "run: no solver line"; }
ok

"$mfv" compare rod-pulse -m sph -m external:fem-rod -n 25,49 -r "$work/rep" > "$work/cmp.out" 2>&1 ||
  { cat "$work/cmp.out"; fail "compare: exit $?"; }
grep -rq "External solvers" "$work/rep" || fail "compare: no 'External solvers' section in the report"
# The page beside mfv's methods: sph and fem-rod at both resolutions, fem-rod's energy drift
# from its own account (frames/energy.csv), linked from the index.
[ "$(grep -c '^| rod-pulse ' "$work/rep/external.md")" = 4 ] ||
  { cat "$work/rep/external.md"; fail "compare: external.md has not 4 rows"; }
grep -qE '^\| rod-pulse \| +49 \| external:fem-rod \| velocity error at 2L/c [0-9.e-]+; velocity error at L/c [0-9.e-]+ +\| +0\.00[0-9]+ \|' \
  "$work/rep/external.md" || { cat "$work/rep/external.md"; fail "compare: fem-rod's row"; }
grep -q '(external.md)' "$work/rep/index.md" || fail "compare: index.md does not link external.md"
python3 - "$work/rep/results.json" <<'EOF' || fail "compare: results.json has no transient.external"
import json, sys
r = json.load(open(sys.argv[1]))
ext = [res["transient"]["external"] for s in r["studies"] for res in s["resolutions"]
       if "external" in res.get("transient", {})]
assert len(ext) == 2 and ext[0]["solver"] == "fem-rod" and ext[0]["protocol"] == "mfv-external-1", ext
EOF
if python3 -c "import jsonschema" 2> /dev/null; then
  python3 "$src/scripts/validate_json.py" results \
    "$work/rep/results.json" > "$work/val.out" 2>&1 || { cat "$work/val.out"; fail "results.json invalid"; }
fi
ok

cat > "$work/suite.toml" <<'EOF'
[suite]
name = "external"
[[case]]
id = "rod-pulse/external-fem-rod"
problem = "rod-pulse"
method = "external:fem-rod"
nodes = [25, 49]
[case.bands]
l2_rel_finest = [0.0, 0.05]
EOF
"$mfv" verify "$work/suite.toml" > "$work/ver.out" 2>&1 || { cat "$work/ver.out"; fail "verify: exit $?"; }
grep -q "PASS" "$work/ver.out" || { cat "$work/ver.out"; fail "verify: no PASS"; }
ok

# 2. Refusals.
expect_exit() {  # expect_exit <code> <text> <command...>
  local code=$1 text=$2
  shift 2
  "$@" > "$work/o" 2>&1
  local rc=$?
  [ $rc -eq "$code" ] || { cat "$work/o"; fail "$*: exit $rc, expected $code"; }
  grep -q -- "$text" "$work/o" || { cat "$work/o"; fail "$*: no '$text' in the message"; }
  ok
}
expect_exit 2 "supports rod-pulse, not problem 'oscillating-plate'" \
  "$mfv" run oscillating-plate -m external:fem-rod -n 9
expect_exit 2 "runs through the transient analysis only" "$mfv" run cantilever -m external:fem-rod -n 5
expect_exit 2 "unknown parameter\|keep" "$mfv" run rod-pulse -m external:fem-rod -p keep=2 -n 25

mkdir -p "$work/dup" "$work/bad"
cp "$src/solvers/fem-rod.toml" "$work/dup/"
expect_exit 2 "external solver 'fem-rod' is defined twice" env MFV_SOLVERS="$work/dup" "$mfv" list
echo '[solver]
command = "python3 x.py"
problems = ["rod-pulse"]' > "$work/bad/bad.toml"
# A broken solver file stops only its own solver (issue 45): listed as not usable, refused
# when used, every other command unaffected.
expect_exit 0 "external:bad .*NOT USABLE.*command must be an array of strings" \
  env MFV_SOLVERS="$work/bad" "$mfv" list methods
expect_exit 2 "command must be an array of strings" \
  env MFV_SOLVERS="$work/bad" "$mfv" run rod-pulse -m external:bad -n 25
expect_exit 0 "L2" env MFV_SOLVERS="$work/bad" "$mfv" run laplace-tanh -m fem -n 21

# 3. Broken solvers: a Python fake, broken as its argument says.
mkdir -p "$work/fakes"
cat > "$work/fakes/fake.py" <<'EOF'
import csv, json, os, sys, time
mode, case = sys.argv[1], sys.argv[2]
inp = json.load(open(os.path.join(case, "input.json")))
n = inp["particles"]["count"]
parts = list(csv.DictReader(open(os.path.join(case, "particles.csv"))))
# Frames of a frozen body: the initial velocity mfv sent, held at every output time (wrong
# physics, but consistent with mfv's masses and with the account below); or all zeros.
v0 = [(float(p["vx0"]), float(p.get("vy0", 0))) for p in parts]
k0 = sum(0.5 * float(p["mass"]) * (a * a + b * b) for p, (a, b) in zip(parts, v0))
if mode == "sleep": time.sleep(60)
if mode == "exit": sys.stderr.write("fake: diverged at step 7\n"); sys.exit(3)
if mode == "escape" and os.fork() == 0:
    # A descendant that leaves the solver's process group and outlives it.
    os.setsid()
    time.sleep(3)
    open(os.environ["FAKE_MARK"], "w").write("still running after mfv\n")
    os._exit(0)
os.makedirs(os.path.join(case, "frames"))
ix = open(os.path.join(case, "frames", "index.csv"), "w")
ix.write("mfv-external-1\nk,time,steps\n" if mode == "short" else "mfv-external-1\nk,time\n")
times = inp["output_times"]
for k, t in enumerate(times):
    if mode == "missing" and t == inp["checkpoints"][0]: continue
    grow = 1e15 if mode == "blowup" and k == len(times) - 1 else 1
    with open(os.path.join(case, "frames", f"frame-{k}.csv"), "w") as f:
        f.write("id,ux,uy,vx,vy\n")
        for i in range(n - (1 if mode == "count" else 0)):
            vx, vy = (0, 0) if mode == "zeros" else (grow * v0[i][0], grow * v0[i][1])
            f.write(f"{i},0,0,{'nan' if mode == 'nan' and i == 17 else repr(vx)},{vy!r}\n")
    ix.write(f"{k},{t!r},{min(k + 1, 5)}\n" if mode == "short" else f"{k},{t!r}\n")
if mode in ("energy-nan", "drift", "short", "account-zero", "account-wrong"):
    # An energy account: broken, not balancing, starting from nothing, or not the frames'.
    end = times[-1]
    start = 0.0 if mode == "account-zero" else k0
    mid = "nan" if mode == "energy-nan" else repr(3 * k0 if mode == "account-wrong" else k0)
    with open(os.path.join(case, "frames", "energy.csv"), "w") as f:
        f.write(f"mfv-external-1\ntime,kinetic,internal_work\n0,{start!r},0\n")
        f.write(f"{end / 2!r},{mid},{k0!r}\n{end!r},{k0!r},{2 * k0!r}\n")
EOF
for mode in sleep exit missing nan count energy-nan drift short blowup zeros account-zero account-wrong escape; do
  printf '[solver]\ncommand = ["python3", "{solver_dir}/fake.py", "%s"]\nproblems = ["rod-pulse"]\ntimeout = %s\n' \
    "$mode" "$([ "$mode" = sleep ] && echo 2 || echo 30)" > "$work/fakes/fake-$mode.toml"
done
# Frames of a body at rest, on the plate too: its period cannot be measured.
printf '[solver]\ncommand = ["python3", "{solver_dir}/fake.py", "frozen"]\nproblems = ["rod-pulse", "oscillating-plate"]\ntimeout = 20\n' \
  > "$work/fakes/fake-frozen.toml"
printf '[solver]\ncommand = ["mfv-no-such-solver"]\nproblems = ["rod-pulse"]\ninstall_hint = "apt install mfv-no-such-solver"\n' \
  > "$work/fakes/absent.toml"
export MFV_SOLVERS="$work/fakes"
expect_exit 1 "did not finish within its timeout of 2 s" "$mfv" run rod-pulse -m external:fake-sleep -n 25
expect_exit 1 "exited 3 after .*fake: diverged at step 7" "$mfv" run rod-pulse -m external:fake-exit -n 25
expect_exit 1 "checkpoint t = 0.0115635 (frame [0-9]*) missing" "$mfv" run rod-pulse -m external:fake-missing -n 25
expect_exit 1 "field vx is nan at particle 17" "$mfv" run rod-pulse -m external:fake-nan -n 25
expect_exit 1 "74 particles in frame-0.csv, expected 75" "$mfv" run rod-pulse -m external:fake-count -n 25
expect_exit 1 "frames/energy.csv line 4: field kinetic is nan" "$mfv" run rod-pulse -m external:fake-energy-nan -n 25
expect_exit 1 "energy balance (frames/energy.csv) drifted by 2 of the run's energy" \
  "$mfv" run rod-pulse -m external:fake-drift -n 25
# Issue 45: mfv judges the replayed frames by its own physics. A blow-up (velocities 1e15 ×
# the initial ones at the last frame: K 1e30 × E_in) is unstable; frames of zeros for a body
# set in motion, an account starting from nothing or one that is not the frames' fail naming
# it; a solver that states fewer steps than mfv's critical step allows has its drift judged.
expect_exit 1 "kinetic energy .* with mfv's masses, above 10000 × the energy put in" \
  "$mfv" run rod-pulse -m external:fake-blowup -n 25
expect_exit 1 "every one of the solver's [0-9]* frames is zero" "$mfv" run rod-pulse -m external:fake-zeros -n 25
expect_exit 1 "frames/energy.csv: the kinetic energy at t = 0 is 0, but the initial velocity mfv sent" \
  "$mfv" run rod-pulse -m external:fake-account-zero -n 25
expect_exit 1 "frames/energy.csv disagrees with the frames: at t = " \
  "$mfv" run rod-pulse -m external:fake-account-wrong -n 25
expect_exit 1 "energy balance (frames/energy.csv) drifted by 2 of the run's energy" \
  "$mfv" run rod-pulse -m external:fake-short -n 193
expect_exit 1 "not installed here: mfv-no-such-solver: no such program on PATH (install: apt install mfv-no-such-solver)" \
  "$mfv" run rod-pulse -m external:absent -n 25
# mfv killed while its solver runs: the solver's process group goes with it and the case
# directory is removed (the group is the solver's own: the signal alone would not reach it).
mkdir -p "$work/tmp"
TMPDIR="$work/tmp" "$mfv" run rod-pulse -m external:fake-sleep -n 25 > "$work/killed.out" 2>&1 &
victim=$!
for _ in $(seq 100); do pgrep -f "fake.py sleep $work/tmp/mfv-external" > /dev/null && break; sleep 0.05; done
pgrep -f "fake.py sleep $work/tmp/mfv-external" > /dev/null || fail "kill: the solver did not start"
kill -TERM $victim
wait $victim
for _ in $(seq 40); do pgrep -f "fake.py sleep $work/tmp/mfv-external" > /dev/null || break; sleep 0.05; done
pgrep -f "fake.py sleep $work/tmp/mfv-external" > /dev/null && fail "kill: the solver outlived mfv"
[ -z "$(ls -A "$work/tmp")" ] || { ls -la "$work/tmp"; fail "kill: the case directory outlived mfv"; }
ok
# Issue 45: mfv killed by SIGKILL (no handler of its runs): its watchdog, which holds a pipe
# only mfv writes to, kills the solver's group when mfv is gone (the solver ran on before).
mkdir -p "$work/tmp3"
TMPDIR="$work/tmp3" "$mfv" run rod-pulse -m external:fake-sleep -n 25 > "$work/killed9.out" 2>&1 &
victim=$!
for _ in $(seq 100); do pgrep -f "fake.py sleep $work/tmp3/mfv-external" > /dev/null && break; sleep 0.05; done
pgrep -f "fake.py sleep $work/tmp3/mfv-external" > /dev/null || fail "kill -9: the solver did not start"
kill -KILL $victim
wait $victim
for _ in $(seq 40); do pgrep -f "fake.py sleep $work/tmp3/mfv-external" > /dev/null || break; sleep 0.05; done
pgrep -f "fake.py sleep $work/tmp3/mfv-external" > /dev/null && fail "kill -9: the solver outlived mfv"
ok
# Issue 45: a solver's descendant that calls setsid() dies with the case (mfv is its
# subreaper); a dead run's case directory is swept by the next run, a kept one is not.
rm -f "$work/escaped"
FAKE_MARK="$work/escaped" "$mfv" run rod-pulse -m external:fake-escape -n 25 > "$work/esc.out" 2>&1 ||
  { cat "$work/esc.out"; fail "escape: exit $?"; }
sleep 4
[ ! -e "$work/escaped" ] || fail "escape: a descendant of the solver outlived mfv and wrote $(cat "$work/escaped")"
ok
mkdir -p "$work/tmp2/mfv-external-4194300-aaaaaa" "$work/tmp2/mfv-external-4194301-bbbbbb"
touch "$work/tmp2/mfv-external-4194301-bbbbbb/.mfv-keep"
touch -d '2 hours ago' "$work/tmp2/mfv-external-4194300-aaaaaa" "$work/tmp2/mfv-external-4194301-bbbbbb"
TMPDIR="$work/tmp2" "$mfv" run rod-pulse -m external:fem-rod -n 25 > "$work/sweep.out" 2>&1 ||
  { cat "$work/sweep.out"; fail "sweep: exit $?"; }
[ ! -e "$work/tmp2/mfv-external-4194300-aaaaaa" ] || fail "sweep: a dead run's case directory was left"
[ -e "$work/tmp2/mfv-external-4194301-bbbbbb" ] || fail "sweep: a kept case directory was removed"
ok
# The repository's LAMMPS adapter without LAMMPS (as in CI): not installed, with the way to get it.
if ! command -v lmp > /dev/null; then
  expect_exit 1 "external solver 'lammps-machdyn' is not installed here: .*LAMMPS not found.*scripts/bench_lammps.sh" \
    env -u MFV_LAMMPS MFV_SOLVERS="$src/solvers" "$mfv" run rod-pulse -m external:lammps-machdyn -n 25
fi
# A broken solver beside a good one: the good study reports, the broken one fails with its reason.
"$mfv" compare rod-pulse -m external:fem-rod -m external:fake-nan -n 25 > "$work/mix.out" 2>&1
grep -q "could not run: external:fake-nan: .*field vx is nan at particle 17" "$work/mix.out" ||
  { cat "$work/mix.out"; fail "compare with a broken solver: no reason"; }
grep -qE "^\|  *75 \| *2.500e\+00 \| *[0-9.]+e-0[0-9] \|" "$work/mix.out" || { cat "$work/mix.out"; fail "compare: the good study did not report"; }
ok
# In a manifest: the broken case fails the run, with its reason.
sed 's/external:fem-rod/external:fake-nan/; s/external-fem-rod/external-fake-nan/' "$work/suite.toml" > "$work/broken.toml"
"$mfv" verify "$work/broken.toml" > "$work/vb.out" 2>&1
rc=$?
[ $rc -ne 0 ] || { cat "$work/vb.out"; fail "verify of a broken solver: exit 0"; }
grep -q "field vx is nan at particle 17" "$work/vb.out" || { cat "$work/vb.out"; fail "verify: no reason"; }
ok
# A case whose run ended but whose measurement cannot be taken (no period from a plate at rest)
# fails with its reason; the suite goes on to the next case, which passes.
cat > "$work/measure.toml" <<'EOF'
[suite]
name = "measure"
[[case]]
id = "oscillating-plate/external-fake-frozen"
problem = "oscillating-plate"
method = "external:fake-frozen"
nodes = [5]
[[case]]
id = "rod-pulse/external-fem-rod"
problem = "rod-pulse"
method = "external:fem-rod"
nodes = [25]
EOF
"$mfv" verify "$work/measure.toml" > "$work/vm.out" 2>&1
rc=$?
[ $rc -eq 1 ] || { cat "$work/vm.out"; fail "verify with an unmeasurable case: exit $rc, expected 1"; }
grep -q "could not measure: oscillating-plate: the tip crossed zero 0 time(s)" "$work/vm.out" ||
  { cat "$work/vm.out"; fail "verify: no 'could not measure' with the reason"; }
grep -q "rod-pulse/external-fem-rod .*PASS" "$work/vm.out" ||
  { cat "$work/vm.out"; fail "verify: the case after the unmeasurable one did not run"; }
ok
echo "PASS: $checks checks"
