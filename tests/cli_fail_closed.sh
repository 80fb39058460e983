#!/usr/bin/env bash
# pbdval's command line on bad inputs and special output paths (issue 9, docs/cli.md): every
# case must end with the documented exit status and a message saying what is wrong; no special
# file may be replaced. Device nodes are made in the work folder (mknod), never /dev itself.
# Usage: cli_fail_closed.sh PBDVAL SOURCE_DIR WORK_DIR
set -uo pipefail
pbdval=$1 source=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
scene=$source/cases/contact_sphere_drop.json
failures=0 tried=0

fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
# expect STATUS TEXT -- COMMAND...: exit status STATUS and TEXT in stdout+stderr.
expect() {
  local want=$1 text=$2; shift 3
  tried=$((tried + 1))
  local out status
  out=$("$@" 2>&1); status=$?
  [[ $status -eq $want ]] || fail "exit $status (expected $want): $* :: $out"
  [[ "$out" == *"$text"* ]] || fail "'$text' not in the output of: $* :: $out"
}
sim=("$pbdval" simulate "$scene" --duration 0.05 --quiet)

# --- CLI basics
expect 0 "precision: pbd::Real = double" -- "$pbdval" --version
expect 0 "usage: pbdval run" -- "$pbdval" help run
expect 2 "unknown command 'nope'" -- "$pbdval" help nope
example=$("$pbdval" simulate --help | grep -o 'example: pbdval simulate [^ ]*' | awk '{print $4}')
[[ -f "$source/$example" ]] || fail "the example of 'simulate --help' ($example) does not exist"

# --- --out special files
mkfifo "$work/fifo"
# Both sides time out: a writer that never opens the FIFO (or opens it twice, so the reader
# sees an early end) must fail this test, not hang it.
timeout 60 cat "$work/fifo" >"$work/from_fifo.csv" &
reader=$!
expect 0 "" -- timeout 60 "${sim[@]}" --out "$work/fifo"
wait $reader || fail "the FIFO's reader ended with status $? (124: nothing was written to it)"
[[ -p "$work/fifo" ]] || fail "the FIFO was replaced"
head -1 "$work/from_fifo.csv" | grep -q '^t,id,x' || fail "nothing came through the FIFO"

echo old >"$work/target.csv" && ln -s target.csv "$work/link.csv"
expect 0 "" -- "${sim[@]}" --out "$work/link.csv"
[[ -L "$work/link.csv" ]] || fail "the symlink was replaced"
head -1 "$work/target.csv" | grep -q '^t,id,x' || fail "the symlink's target was not written"

# /dev/stdout into a pipe (it resolves to /proc/self/fd/1 -> "pipe:[N]").
header=$("${sim[@]}" --out /dev/stdout | head -1)
[[ "$header" == t,id,x* ]] || fail "--out /dev/stdout into a pipe: got '$header'"
"${sim[@]}" --out /dev/stdout >"$work/redirected.csv"
head -1 "$work/redirected.csv" | grep -q '^t,id,x' || fail "--out /dev/stdout into a file"

mkdir "$work/folder"
expect 2 "is a folder, not a file" -- "${sim[@]}" --out "$work/folder"
expect 2 "proc file system" -- "${sim[@]}" --out /proc/self/pbdval-out.csv
expect 2 "plain is a regular file, not a folder" -- \
  bash -c "touch '$work/plain' && $(printf '%q ' "${sim[@]}") --out '$work/plain/x.csv'"
if mknod "$work/null" c 1 3 2>/dev/null && mknod "$work/full" c 1 7 2>/dev/null; then
  expect 0 "" -- "${sim[@]}" --out "$work/null"
  [[ -c "$work/null" ]] || fail "the null device node was replaced"
  expect 2 "No space left on device" -- "${sim[@]}" --out "$work/full"
  [[ -c "$work/full" ]] || fail "the full device node was replaced"
  expect 2 "No space left on device" -- "$pbdval" distance --samples 2 --json "$work/full"
else
  echo "note: mknod not permitted here; device-node cases skipped" >&2
fi
# Standard output on a full device (a shell redirection: /dev/full itself is not touched).
if [[ -w /dev/full ]]; then
  expect 2 "standard output failed" -- bash -c "$(printf '%q ' "${sim[@]}") >/dev/full"
fi

# Commands that compute before writing check their output path first.
expect 2 "proc file system" -- timeout 20 "$pbdval" run "$scene" --engines pbd --out /proc/self/pbdval-run
expect 2 "is a folder, not a file" -- timeout 20 "$pbdval" distance --json "$work/folder"
expect 2 "is a character device, not a folder" -- timeout 20 "$pbdval" sweep "$scene" --out /dev/null --param subSteps=1,2

# --- scenes that are not regular files, or hostile
expect 2 "the scene is a character device, not a regular file" -- "$pbdval" simulate /dev/null
expect 2 "the scene is a folder, not a file" -- "$pbdval" simulate "$work/folder"
expect 2 "the scene is a FIFO, not a regular file" -- "$pbdval" simulate "$work/fifo"
python3 -c "import sys; sys.stdout.write('{\"Name\": ' + '[' * 100000)" >"$work/deep.json"
expect 2 "deep.json: Name" -- timeout 20 "$pbdval" simulate "$work/deep.json"
expect 2 "nested deeper than 64 levels" -- timeout 20 "$pbdval" simulate "$work/deep.json"
printf '{"Na\xffme": 1}' >"$work/utf8.json"
expect 2 'invalid JSON at line 1' -- "$pbdval" simulate "$work/utf8.json"
expect 2 '\xFF' -- "$pbdval" simulate "$work/utf8.json"

# --- the gate fails closed
"$pbdval" run "$scene" --engines pbd --out "$work/run" --no-trajectories --quiet >/dev/null ||
  fail "pbdval run failed"
"$pbdval" baseline --results "$work/run" --out "$work/baseline.json" >/dev/null ||
  fail "pbdval baseline failed"
expect 0 "pbdval gate: passed" -- "$pbdval" gate --baseline "$work/baseline.json" --results "$work/run"
expect 2 'no case "no_such_case" in the baseline or the results' -- \
  "$pbdval" gate --baseline "$work/baseline.json" --results "$work/run" --cases no_such_case
# --engines restricts both sides: a baseline of pbd and ode judges pbd's runs alone only when told.
"$pbdval" run "$scene" --engines pbd,ode --out "$work/run_two" --no-trajectories --quiet >/dev/null ||
  fail "pbdval run (two engines) failed"
"$pbdval" baseline --results "$work/run_two" --out "$work/baseline_two.json" >/dev/null ||
  fail "pbdval baseline (two engines) failed"
expect 1 "run missing from the results" -- \
  "$pbdval" gate --baseline "$work/baseline_two.json" --results "$work/run"
expect 0 "pbdval gate: passed" -- \
  "$pbdval" gate --baseline "$work/baseline_two.json" --results "$work/run" --engines pbd
expect 2 "--engines: expected a comma-separated list of engine names" -- \
  "$pbdval" gate --baseline "$work/baseline_two.json" --results "$work/run" --engines ,
expect 2 "--engines: " -- \
  "$pbdval" gate --baseline "$work/baseline_two.json" --results "$work/run" --engines no_such_engine
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
base = json.load(open(f"{work}/baseline.json"))
base["runs"] = []
json.dump(base, open(f"{work}/empty_baseline.json", "w"))
results = json.load(open(f"{work}/run/results.json"))
no_cases = dict(results); del no_cases["cases"]
json.dump(no_cases, open(f"{work}/no_cases.json", "w"))
dup = dict(results); dup["runs"] = results["runs"] + results["runs"]
json.dump(dup, open(f"{work}/duplicate.json", "w"))
null = json.loads(json.dumps(results))
null["runs"][0]["metrics"]["energy_drift_max"] = None
json.dump(null, open(f"{work}/null_metric.json", "w"))
# Issue 25: a metric 100x worse with a tolerance of 1e9 written into the results.
tampered = json.loads(json.dumps(results))
tampered["runs"][0]["metrics"]["energy_drift_max"] *= 100
for case in tampered["cases"].values():
    case["tolerances"] = {"energy_drift_max": 1e9}
json.dump(tampered, open(f"{work}/tampered.json", "w"))
empty = dict(results); empty["runs"] = []
json.dump(empty, open(f"{work}/empty_results.json", "w"))
other = json.loads(json.dumps(results)); other["metadata"]["planDigest"] = "0123456789abcdef"
json.dump(other, open(f"{work}/other_plan.json", "w"))
old = dict(base); old["schemaVersion"] = 1; del old["cases"]
json.dump(old, open(f"{work}/v1_baseline.json", "w"))
PY
expect 2 "runs: expected a non-empty array" -- \
  "$pbdval" gate --baseline "$work/empty_baseline.json" --results "$work/run"
expect 2 'missing required key "cases"' -- \
  "$pbdval" gate --baseline "$work/baseline.json" --results "$work/no_cases.json"
expect 2 "runs were lost, added, reordered or edited" -- \
  "$pbdval" gate --baseline "$work/baseline.json" --results "$work/duplicate.json"
expect 1 "pbdval gate: FAILED" -- \
  "$pbdval" gate --baseline "$work/baseline.json" --results "$work/tampered.json"
expect 2 "pbdval baseline --results out --out $work/v1_baseline.json" -- \
  "$pbdval" gate --baseline "$work/v1_baseline.json" --results "$work/run"
# pbdval baseline refuses what the gate would refuse, and results that would pass broken.
expect 2 "runs: no runs" -- \
  "$pbdval" baseline --results "$work/empty_results.json" --out "$work/refused.json"
expect 2 "runs were lost, added, reordered or edited" -- \
  "$pbdval" baseline --results "$work/duplicate.json" --out "$work/refused.json"
expect 2 "the runs listed are not those of the plan" -- \
  "$pbdval" baseline --results "$work/other_plan.json" --out "$work/refused.json"
"$pbdval" run "$scene" --engines pbd --shard 1/1 --fail-with lost --out "$work/lost" --quiet >/dev/null
expect 2 "no run is ok (2 error)" -- \
  "$pbdval" baseline --results "$work/lost" --out "$work/refused.json"
[[ ! -e "$work/refused.json" ]] || fail "a refused baseline was written"
# A baseline of another plan (here: only pbd.xpbd) does not silently replace one.
cp "$work/baseline.json" "$work/replaced.json"
"$pbdval" run "$scene" --methods pbd.xpbd --out "$work/xpbd" --no-trajectories --quiet >/dev/null
expect 2 "replaced.json was made from another plan" -- \
  "$pbdval" baseline --results "$work/xpbd" --out "$work/replaced.json"
expect 0 "pbdval baseline: 1 runs of 1 cases" -- \
  "$pbdval" baseline --results "$work/xpbd" --out "$work/replaced.json" --new-plan
# A case file edited since the baseline: refused by name, unless re-pinned.
cp "$scene" "$work/pinned_case.json"
"$pbdval" run "$work/pinned_case.json" --engines pbd --out "$work/pinned" --no-trajectories --quiet >/dev/null
"$pbdval" baseline --results "$work/pinned" --out "$work/pinned_baseline.json" >/dev/null ||
  fail "pbdval baseline failed"
echo " " >>"$work/pinned_case.json"
expect 2 "case pinned_case: $work/pinned_case.json on disk has sha256" -- \
  "$pbdval" gate --baseline "$work/pinned_baseline.json" --results "$work/pinned"
expect 2 "the results were run from sha256" -- \
  "$pbdval" gate --baseline "$work/pinned_baseline.json" --results "$work/pinned" --repin-cases
"$pbdval" run "$work/pinned_case.json" --engines pbd --out "$work/repinned" --no-trajectories --quiet >/dev/null
expect 2 "case pinned_case: the results were run from $work/pinned_case.json with sha256" -- \
  "$pbdval" gate --baseline "$work/pinned_baseline.json" --results "$work/repinned"
expect 0 "note: case pinned_case re-pinned (--repin-cases)" -- \
  "$pbdval" gate --baseline "$work/pinned_baseline.json" --results "$work/repinned" --repin-cases
expect 2 "metric energy_drift_max is nan" -- \
  "$pbdval" baseline --results "$work/null_metric.json" --out "$work/null_baseline.json"
[[ ! -e "$work/null_baseline.json" ]] || fail "a baseline was written from a null metric"
expect 2 "is a folder, not a file" -- \
  "$pbdval" gate --baseline "$work/baseline.json" --results "$work/run" --junit "$work/folder"

# --- merge touches only what its shards own (issue 25): a shard whose results.json was edited to
# point outside it, or to relabel or reorder its runs, is refused before anything is moved
"$pbdval" run "$scene" --engines pbd,ode --shard 1/1 --out "$work/shard" --quiet >/dev/null ||
  fail "the shard run failed"
cp "$work/shard/results.json" "$work/shard.json"
echo "not the shard's" >"$work/outside.csv"
tamper() {  # tamper PYTHON-EXPRESSION-ON-runs: writes the shard's results.json edited
  python3 - "$work/shard.json" "$work/shard/results.json" "$1" "$work" <<'PY'
import json, sys
results = json.load(open(sys.argv[1]))
runs, work = results["runs"], sys.argv[4]
exec(sys.argv[3])
json.dump(results, open(sys.argv[2], "w"))
PY
}
tamper 'runs[0]["trajectory"] = work + "/outside.csv"'
expect 2 "expected OUT/trajectories/contact_sphere_drop/pbd-pbd.csv or .npy" -- \
  "$pbdval" merge "$work/shard" --out "$work/merged" --move
[[ -f $work/outside.csv && ! -e $work/merged ]] || fail "merge --move touched a file outside the shard"
tamper 'runs[0]["trajectory"] = runs[0]["trajectory"].replace("pbd-pbd.csv", "../../../outside.csv")'
expect 2 "or .npy, the path 'pbdval run' writes" -- "$pbdval" merge "$work/shard" --out "$work/merged" --move
mv "$work/shard/trajectories/contact_sphere_drop/pbd-pbd.csv" "$work/moved-away.csv"
ln -s "$work/outside.csv" "$work/shard/trajectories/contact_sphere_drop/pbd-pbd.csv"
tamper 'pass'
expect 2 "pbd-pbd.csv is a symbolic link" -- "$pbdval" merge "$work/shard" --out "$work/merged" --move
[[ -f $work/outside.csv && ! -e $work/merged ]] || fail "merge --move followed a link out of the shard"
rm "$work/shard/trajectories/contact_sphere_drop/pbd-pbd.csv"
expect 2 "pbd-pbd.csv does not exist; a run with status ok has its trajectory" -- \
  "$pbdval" merge "$work/shard" --out "$work/merged"
mv "$work/moved-away.csv" "$work/shard/trajectories/contact_sphere_drop/pbd-pbd.csv"
tamper 'runs[1]["engine"] = "mujoco"'
expect 2 "not the plan they were run from" -- "$pbdval" merge "$work/shard" --out "$work/merged"
tamper 'runs.reverse()'
expect 2 "not the plan they were run from" -- "$pbdval" merge "$work/shard" --out "$work/merged"
tamper 'del results["metadata"]["planDigest"]'
expect 2 "metadata.planDigest: missing" -- "$pbdval" merge "$work/shard" --out "$work/merged"
tamper 'pass'
expect 0 "3 runs: 3 ok, 3 trajectories" -- "$pbdval" merge "$work/shard" --out "$work/merged" --move --quiet
[[ -f $work/merged/trajectories/contact_sphere_drop/pbd-pbd.csv ]] || fail "the untampered shard was not merged"

echo "cli_fail_closed: $tried bad or special inputs tried, $failures failures"
[[ $failures -eq 0 ]]
