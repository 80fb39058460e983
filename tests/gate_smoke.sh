#!/usr/bin/env bash
# CI's regression gate on a few non-chaotic cases (smooth dynamics, so the last-bit differences
# of libm across CPUs stay far inside the gate's tolerances): run them in every engine and gate
# them against the project baseline.  Usage: gate_smoke.sh PBDVAL SOURCE_DIR WORK_DIR
set -euo pipefail
pbdval=$1 source=$2 work=$3
cases=(projectile joint_hinge joint_rigid_body_spring joint_slider contact_sphere_drop contact_incline_slide)
files=()
for c in "${cases[@]}"; do files+=("$source/cases/$c.json"); done
rm -rf "$work"
"$pbdval" run "${files[@]}" --out "$work" --no-trajectories --quiet >/dev/null
list=$(IFS=,; echo "${cases[*]}")
# The baseline also holds engines run by name only (scripts/validate names them); the runs above
# are those of the default engines.
"$pbdval" gate --baseline "$source/reports/baselines/main.json" --results "$work" --cases "$list" --engines default
