"""Fits the scaling exponent of every method on every scaling family (bench/bench_step.cpp,
`scaling/<family>/<method>/<N>`) from a Google Benchmark JSON written by scripts/bench.

    .venv/bin/python bench/fit_scaling.py bench/results/<host>/step-<stamp>.json [--json FILE] [--markdown]

For each family and method: the median wall time per step at every body count N (wall, not
CPU: `pbd@threads=2` runs part of its step on a second thread, which the calling thread's CPU
time would not count; single-threaded, the two agree), the exponent p
of t ≈ c·Nᵖ fitted by least squares on log t against log N over N ≥ --from (default 100: below
it the fixed cost per step, the same for every N, flattens the curve and would flatter the
fit), and the local exponent of each successive pair of sizes (where a cost turns super-linear).
A method that failed at some N (the benchmark's error message) is reported with it.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
from pathlib import Path


def load(path: Path) -> tuple[dict[tuple[str, str], dict[int, float]], dict[tuple[str, str], str], dict]:
    data = json.loads(path.read_text())
    times: dict[tuple[str, str], dict[int, float]] = {}
    errors: dict[tuple[str, str], str] = {}
    for b in data["benchmarks"]:
        name = b.get("run_name", b["name"])
        if not name.startswith("scaling/"):
            continue
        # scaling/FAMILY/METHOD/N, with "/iterations:20" appended by Google Benchmark
        _, family, method, count = name.split("/")[:4]
        key = (family, method)
        if b.get("error_occurred"):
            errors.setdefault(key, f"N = {count}: {b.get('error_message', '')}")
            continue
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        times.setdefault(key, {})[int(count)] = float(b["real_time"])
    return times, errors, data.get("context", {})


def fit(points: dict[int, float], smallest: int) -> float | None:
    xs = [math.log(n) for n in sorted(points) if n >= smallest]
    ys = [math.log(points[n]) for n in sorted(points) if n >= smallest]
    if len(xs) < 2:
        return None
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def local_exponents(points: dict[int, float]) -> list[tuple[int, int, float]]:
    sizes = sorted(points)
    return [(a, b, math.log(points[b] / points[a]) / math.log(b / a)) for a, b in itertools.pairwise(sizes)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path)
    parser.add_argument("--from", dest="smallest", type=int, default=100, help="smallest N of the fit")
    parser.add_argument("--json", type=Path, help="write the fits here")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args()
    times, errors, context = load(args.results)
    if not times and not errors:
        print(f"{args.results}: no scaling/ benchmarks in this file", file=sys.stderr)
        return 1
    rows = []
    for (family, method), points in sorted(times.items()):
        rows.append({"family": family, "method": method, "wall_time_us": {str(n): t for n, t in sorted(points.items())},
                     "exponent": fit(points, args.smallest), "fit_from": args.smallest,
                     "local_exponents": [{"from": a, "to": b, "exponent": e} for a, b, e in local_exponents(points)],
                     "error": errors.get((family, method))})
    for (family, method), message in sorted(errors.items()):
        if (family, method) not in times:
            rows.append({"family": family, "method": method, "wall_time_us": {}, "exponent": None,
                         "fit_from": args.smallest, "local_exponents": [], "error": message})
    sizes = sorted({int(n) for r in rows for n in r["wall_time_us"]})
    if args.markdown:
        print("| family | method | " + " | ".join(f"N = {n}" for n in sizes)
              + f" | exponent (N ≥ {args.smallest}) | local exponents |")
        print("|---|---|" + "---|" * len(sizes) + "---|---|")
        for r in rows:
            cells = [f"{r['wall_time_us'][str(n)]:.4g}" if str(n) in r["wall_time_us"] else "—" for n in sizes]
            exponent = f"{r['exponent']:.3f}" if r["exponent"] is not None else "—"
            local = ", ".join(f"{e['exponent']:.2f}" for e in r["local_exponents"])
            print(f"| {r['family']} | {r['method']} | " + " | ".join(cells) + f" | {exponent} | {local} |")
    else:
        for r in rows:
            exponent = f"{r['exponent']:.3f}" if r["exponent"] is not None else "—"
            local = " ".join(f"{e['exponent']:.2f}" for e in r["local_exponents"])
            print(f"{r['family']:8} {r['method']:14} exponent {exponent}  local {local}"
                  + (f"  ({r['error']})" if r["error"] else ""))
    if args.json:
        document = {"source": str(args.results), "context": context, "fits": rows}
        args.json.write_text(json.dumps(document, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
