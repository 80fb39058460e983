#!/usr/bin/env bash
# Issue 25, "fail closed, round two": pbdval leaves no process, scratch folder or temporary file
# behind, and never hangs, whatever an external engine does and whatever signal the command
# gets; extreme scenes are refused with a clear error, never a crash. Every command here runs
# under `timeout`, in its own TMPDIR (so leftovers are counted exactly); every process the
# test's engine starts is recorded and killed at the end whatever happened.
# Usage: cli_no_leftovers.sh PBDVAL SOURCE_DIR WORK_DIR
set -uo pipefail
pbdval=$1 source=$2 work=$3
rm -rf "$work" && mkdir -p "$work/tmp" "$work/engines"
export TMPDIR=$work/tmp
scene=$source/cases/contact_sphere_drop.json
failures=0 tried=0

fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
# A process that still runs (a zombie waiting for its parent to reap it does not).
alive() { [[ -r /proc/$1/stat ]] && ! grep -q '^[0-9]* (.*) Z ' "/proc/$1/stat"; }
# Waits up to 5 s for every process recorded in FILE... to be gone.
expect_gone() {
  local what=$1 file pid; shift
  for file in "$@"; do
    [[ -s $file ]] || { fail "$what: the engine did not record its child ($file)"; continue; }
    pid=$(cat "$file")
    for _ in $(seq 50); do alive "$pid" || break; sleep 0.1; done
    alive "$pid" && fail "$what: the engine's child $pid still runs"
  done
}
expect_no_scratch() {
  local left
  left=$(find "$TMPDIR" -maxdepth 1 -name 'pbdval-*' | head -5)
  [[ -z $left ]] || fail "$1: left behind: $left"
  rm -rf "${TMPDIR:?}"/pbdval-*
}
cleanup() {
  local pid
  for pid in $(cat "$ENGINE_ALL" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null; done
}
trap cleanup EXIT

# The engine: a shell script that starts a child of its own (recorded in $ENGINE_PIDS), then
# per $ENGINE_MODE hangs or finishes normally (status "unsupported", exit 0). With
# $ENGINE_SETSID (a file name) it also starts a process that leaves its process group with
# setsid() and records its pid there.
cat >"$work/engine.sh" <<'SH'
echo $$ >>"$ENGINE_PIDS.engines"
if [ -n "${ENGINE_SETSID:-}" ]; then
  setsid sh -c 'echo $$ >>"$1"; echo $$ >"$0"; exec sleep 300' "$ENGINE_SETSID" "$ENGINE_ALL" &
  while [ ! -s "$ENGINE_SETSID" ]; do sleep 0.01; done
fi
sleep 300 &
child=$!
if [ "$ENGINE_MODE" = hang ]; then sleep 300 & hang=$!; fi
# Every process, for the test's own cleanup whatever pbdval does; before $ENGINE_PIDS, which the
# test waits for before it signals.
echo $$ $child ${hang:-} >>"$ENGINE_ALL"
echo $child >"$ENGINE_PIDS"
if [ "$ENGINE_MODE" = hang ]; then wait $hang; exit 0; fi
printf '{"protocol": 1, "status": "unsupported", "reason": "r", "divergedAt": null, "engineVersion": "e 1", "effectiveSettings": {}, "integratorStepsPerSceneStep": 1, "contactMargin": null, "unsupported": ["everything"]}' \
  >"$4/status.json"
SH
cat >"$work/engines/probe.json" <<JSON
{"protocol": 1, "name": "probe", "defaultMethod": "probe.x",
 "command": ["sh", "$work/engine.sh"],
 "methods": [{"name": "probe.x", "description": "a test engine"}]}
JSON
export PBDVAL_ENGINE_CATALOGUE=$work/engines
export ENGINE_ALL=$work/all-engine-processes  # every process an engine started, never removed

# --- an engine's child is ended after a normal finish
tried=$((tried + 1))
ENGINE_MODE=done ENGINE_PIDS=$work/done.pid timeout 60 "$pbdval" simulate "$scene" --engine probe \
  --duration 0.05 --quiet >/dev/null 2>&1
expect_gone "simulate, normal finish" "$work/done.pid"
expect_no_scratch "simulate, normal finish"

# --- a process that left the engine's process group (setsid) ends with the run too
tried=$((tried + 1))
rm -f "$work/setsid_simulate.pid"
ENGINE_MODE=done ENGINE_PIDS=$work/setsid_simulate.child ENGINE_SETSID=$work/setsid_simulate.pid \
  timeout 60 "$pbdval" simulate "$scene" --engine probe --duration 0.05 --quiet >/dev/null 2>&1
expect_gone "simulate, a setsid() child after a normal finish" "$work/setsid_simulate.pid"
expect_no_scratch "simulate, setsid child"
tried=$((tried + 1))
rm -f "$work/setsid_run.pid"
ENGINE_MODE=done ENGINE_PIDS=$work/setsid_run.child ENGINE_SETSID=$work/setsid_run.pid \
  timeout 60 "$pbdval" run "$scene" --engines probe --out "$work/setsid_run" --no-trajectories \
  --quiet >/dev/null 2>&1
expect_gone "run, a setsid() child after a normal finish" "$work/setsid_run.pid"
expect_no_scratch "run, setsid child"

# --- run: the worker that runs the engine killed outright (SIGKILL, as the OOM killer does):
# the scheduler records the run as an error, ends the engine's processes (those that left its
# process group too) and removes the scratch folder the worker could not
tried=$((tried + 1))
rm -f "$work/worker_kill.pid" "$work/worker_kill.pid.engines" "$work/worker_kill.setsid"
ENGINE_MODE=hang ENGINE_PIDS=$work/worker_kill.pid ENGINE_SETSID=$work/worker_kill.setsid \
  timeout 60 "$pbdval" run "$scene" --engines probe --out "$work/worker_kill" --no-trajectories \
  --quiet >/dev/null 2>&1 &
runner=$!
for _ in $(seq 100); do [[ -s $work/worker_kill.pid ]] && break; sleep 0.1; done
worker=$(ps -o ppid= -p "$(head -1 "$work/worker_kill.pid.engines")" | tr -d ' ')
[[ -n $(find "$TMPDIR" -maxdepth 1 -name 'pbdval-engine-*') ]] ||
  fail "run, worker SIGKILL: no scratch folder while the engine runs (the probe is void)"
kill -KILL "$worker"
wait "$runner"
grep -q 'engine process crashed with signal 9' "$work/worker_kill/results.json" 2>/dev/null ||
  fail "run, worker SIGKILL: the run is not recorded as crashed"
expect_gone "run, worker SIGKILL (the engine's child)" "$work/worker_kill.pid"
expect_gone "run, worker SIGKILL (the setsid() child)" "$work/worker_kill.setsid"
expect_no_scratch "run, worker SIGKILL"

# --- simulate has run's wall-time limit, and a timeout leaves nothing
tried=$((tried + 1))
out=$(ENGINE_MODE=hang ENGINE_PIDS=$work/timeout.pid timeout 60 "$pbdval" simulate "$scene" \
  --engine probe --duration 0.05 --timeout 1 --out "$work/o.csv" 2>&1)
status=$?
[[ $status -eq 1 && $out == *"exceeded the wall-time limit of 1 s"* ]] ||
  fail "simulate --timeout 1 on a hanging engine: exit $status: $out"
expect_gone "simulate, timeout" "$work/timeout.pid"
expect_no_scratch "simulate, timeout"
# (a failed run writes what it sampled, as a diverged one does; no temporary file is left)
[[ -z $(find "$work" -maxdepth 1 -name 'o.csv.tmp-*') ]] || fail "simulate, timeout: o.csv.tmp-* left"
tried=$((tried + 1))
out=$("$pbdval" simulate "$scene" --timeout nan 2>&1)
[[ $? -eq 2 && $out == *"--timeout"* ]] || fail "simulate --timeout nan accepted: $out"
"$pbdval" simulate --help | grep -q -- "--timeout S" || fail "simulate --help has no --timeout"

# --- run: a run over its limit is killed with its engine; the runner removes what it cannot
tried=$((tried + 1))
ENGINE_MODE=hang ENGINE_PIDS=$work/run.pid timeout 60 "$pbdval" run "$scene" --engines probe \
  --timeout 1 --out "$work/run" --no-trajectories --quiet >/dev/null 2>&1
grep -q '"status": "timeout"' "$work/run/results.json" 2>/dev/null ||
  fail "run --timeout 1: no timeout status in results.json"
expect_gone "run, timeout" "$work/run.pid"
expect_no_scratch "run, timeout"
tried=$((tried + 1))
ENGINE_MODE=done ENGINE_PIDS=$work/run_done.pid timeout 60 "$pbdval" run "$scene" --engines probe \
  --out "$work/run_done" --no-trajectories --quiet >/dev/null 2>&1
expect_gone "run, normal finish" "$work/run_done.pid"
expect_no_scratch "run, normal finish"

# --- run stopped by SIGTERM while the engine runs: the runner ends the engine and its child
tried=$((tried + 1))
rm -f "$work/run_signal.pid"
ENGINE_MODE=hang ENGINE_PIDS=$work/run_signal.pid timeout 60 "$pbdval" run "$scene" --engines probe \
  --out "$work/run_signal" --no-trajectories --quiet >/dev/null 2>&1 &
runner=$!
for _ in $(seq 100); do [[ -s $work/run_signal.pid ]] && break; sleep 0.1; done
kill -TERM "$(pgrep -P "$runner" -x pbdval || echo "$runner")"
wait "$runner"
status=$?
[[ $status -eq 143 ]] || fail "run on SIGTERM: exit $status, expected 143"
expect_gone "run, SIGTERM" "$work/run_signal.pid"
expect_no_scratch "run, SIGTERM"

# --- run killed outright (SIGKILL): its runs and their engines die with it (PR_SET_PDEATHSIG);
# only the engine's scratch folder and what the engine itself started can stay
tried=$((tried + 1))
rm -f "$work/run_kill.pid" "$work/run_kill.pid.engines"
ENGINE_MODE=hang ENGINE_PIDS=$work/run_kill.pid "$pbdval" run "$scene" --engines probe \
  --out "$work/run_kill" --no-trajectories --quiet >/dev/null 2>&1 &
runner=$!
for _ in $(seq 100); do [[ -s $work/run_kill.pid ]] && break; sleep 0.1; done
kill -KILL "$runner"
wait "$runner" 2>/dev/null
expect_gone "run, SIGKILL (the engine)" "$work/run_kill.pid.engines"
cleanup
rm -rf "${TMPDIR:?}"/pbdval-*

# --- simulate stopped by SIGTERM, SIGINT or SIGHUP while the engine runs: engine ended,
# scratch and temporary output removed, exit status 128 + signal
for signal in TERM INT HUP; do
  tried=$((tried + 1))
  rm -f "$work/signal.pid"
  ENGINE_MODE=hang ENGINE_PIDS=$work/signal.pid timeout 60 "$pbdval" simulate "$scene" \
    --engine probe --duration 0.05 --out "$work/s.csv" 2>"$work/signal.err" &
  runner=$!
  for _ in $(seq 100); do [[ -s $work/signal.pid ]] && break; sleep 0.1; done
  # `timeout` runs pbdval as its child: signal pbdval itself.
  kill -"$signal" "$(pgrep -P "$runner" -x pbdval || echo "$runner")"
  wait "$runner"
  status=$?
  want=$((128 + $(kill -l "$signal")))
  [[ $status -eq $want ]] || fail "simulate on SIG$signal: exit $status, expected $want: $(cat "$work/signal.err")"
  grep -q "interrupted by SIG$signal" "$work/signal.err" ||
    fail "simulate on SIG$signal: no message: $(cat "$work/signal.err")"
  expect_gone "simulate, SIG$signal" "$work/signal.pid"
  expect_no_scratch "simulate, SIG$signal"
  [[ -z $(find "$work" -maxdepth 1 -name 's.csv*') ]] || fail "simulate, SIG$signal: s.csv left"
done
# The same for a built-in engine stepping in-process (pbd): the temporary output is removed.
tried=$((tried + 1))
timeout 60 "$pbdval" simulate "$scene" --duration 1e4 --out "$work/long.csv" --quiet &
runner=$!
for _ in $(seq 100); do [[ -n $(find "$work" -maxdepth 1 -name 'long.csv.tmp-*') ]] && break; sleep 0.1; done
kill -TERM "$(pgrep -P "$runner" -x pbdval || echo "$runner")"
wait "$runner"
status=$?
[[ $status -eq 143 ]] || fail "simulate (pbd) on SIGTERM: exit $status, expected 143"
[[ -z $(find "$work" -maxdepth 1 -name 'long.csv*') ]] || fail "simulate (pbd), SIGTERM: long.csv left"

# --- a FIFO nobody reads is refused after a bounded wait, not waited for for ever
tried=$((tried + 1))
mkfifo "$work/fifo"
start=$SECONDS
out=$(timeout 60 "$pbdval" simulate "$scene" --duration 0.05 --quiet --out "$work/fifo" 2>&1)
status=$?
[[ $status -eq 2 && $out == *"is a FIFO that no process reads"* ]] ||
  fail "simulate --out FIFO without a reader: exit $status: $out"
((SECONDS - start < 30)) || fail "simulate --out FIFO without a reader took $((SECONDS - start)) s"
[[ -p $work/fifo ]] || fail "the FIFO was replaced"

# --- extreme initial states are refused when the scene is loaded, for every engine
for field in "angularVelocity 1e300" "translation 1e308" "velocity -1e300"; do
  tried=$((tried + 1))
  read -r key value <<<"$field"
  python3 - "$source/cases/free_tumbling_box.json" "$work/extreme.json" "$key" "$value" "$source/cases" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["RigidBodies"][0][sys.argv[3]] = [float(sys.argv[4]), 0, 0]
scene["RigidBodies"][0]["geometryFile"] = sys.argv[5] + "/" + scene["RigidBodies"][0]["geometryFile"]
json.dump(scene, open(sys.argv[2], "w"))
PY
  for engine in ode pbd bullet mujoco; do
    out=$(timeout 60 "$pbdval" simulate "$work/extreme.json" --engine "$engine" --duration 0.1 2>&1)
    status=$?
    [[ $status -eq 2 && $out == *"RigidBodies[0].$key: expected an array of 3 finite numbers in"* ]] ||
      fail "simulate --engine $engine with $key $value: exit $status: ${out:0:300}"
  done
done

echo "cli_no_leftovers: $tried probes, $failures failures"
[[ $failures -eq 0 ]]
