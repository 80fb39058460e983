"""Trajectory files as NPY (`pbdval run --trajectory-format npy`, `pbdval simulate --out F.npy`):
the same rows and columns as the CSV, bit for bit (the CSV's shortest round-trip text reads back
to the same doubles), the same metrics, read by numpy.load and by the suite's reader; a bad
format is refused with a message naming the option."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np

import pbdval
from pbdval.results import load_results, pbdval_binary

REPO = Path(__file__).resolve().parents[2]
CASES = [str(REPO / "cases" / f"{c}.json") for c in ("chain_10", "contact_sphere_drop")]
TIMING = {"wall_time_s", "real_time_factor"}  # differ from run to run by nature


def pbdval_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(pbdval_binary()), *args], capture_output=True, text=True, check=check)


def test_run_writes_npy_trajectories_equal_to_the_csv_ones(tmp_path: Path) -> None:
    for fmt in ("csv", "npy"):
        pbdval_cli("run", *CASES, "--engines", "pbd,ode", "--out", str(tmp_path / fmt), "--jobs", "2",
                   "--trajectory-format", fmt, "--quiet")
    csv_runs, npy_runs = load_results(tmp_path / "csv").runs, load_results(tmp_path / "npy").runs
    assert len(csv_runs) == len(npy_runs) >= 4  # the cases name their methods
    for c, n in zip(csv_runs, npy_runs):
        assert n.trajectory_path is not None and n.trajectory_path.suffix == ".npy"
        assert c.trajectory_path is not None
        # numpy reads the file as the CSV's table, exactly (shortest round-trip text on one side,
        # the doubles' bits on the other).
        table = np.load(n.trajectory_path)
        assert table.dtype == np.float64 and table.shape[1] == 15
        assert np.array_equal(table, np.loadtxt(c.trajectory_path, delimiter=",", skiprows=1))
        a, b = c.trajectory(), n.trajectory()
        assert np.array_equal(a.times, b.times) and np.array_equal(a.positions, b.positions)
        assert np.array_equal(a.quaternions, b.quaternions)
        # The metrics come from the samples, not from the file: identical.
        assert {k: v for k, v in c.metrics.items() if k not in TIMING} == \
            {k: v for k, v in n.metrics.items() if k not in TIMING}


def test_simulate_writes_npy_by_extension(tmp_path: Path) -> None:
    for name in ("t.csv", "t.npy"):
        pbdval_cli("simulate", CASES[0], "--duration", "0.3", "--sample-interval", "0.01", "--out",
                   str(tmp_path / name), "--quiet")
    table = np.load(tmp_path / "t.npy")
    assert np.array_equal(table, np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1))
    assert table.shape == (31 * 11, 15)  # 31 samples (0 to 0.3 s) × 11 bodies
    assert np.array_equal(pbdval.Trajectory.read(tmp_path / "t.npy").positions,
                          pbdval.Trajectory.read(tmp_path / "t.csv").positions)


def test_a_bad_trajectory_format_is_refused(tmp_path: Path) -> None:
    result = pbdval_cli("run", CASES[0], "--engines", "pbd", "--out", str(tmp_path / "x"),
                        "--trajectory-format", "parquet", check=False)
    assert result.returncode == 2
    assert "--trajectory-format: expected csv or npy, got 'parquet'" in result.stderr
    assert not (tmp_path / "x" / "results.json").exists()
