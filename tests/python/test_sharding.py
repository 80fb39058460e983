"""`pbdval run --shard K/N` and `pbdval merge` (docs/cluster.md): the merged folder is the one a
single run of the whole plan writes, apart from timings and hosts; every way shards can fail to
make one plan is refused with a message naming it."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from pbdval.results import load_results, pbdval_binary

REPO = Path(__file__).resolve().parents[2]
CASES = [str(REPO / "cases" / f"{c}.json") for c in ("joint_hinge", "chain_10", "projectile", "contact_sphere_drop")]
ENGINES = "pbd,ode,bullet"
TIMING = {"wall_time_s", "real_time_factor"}  # differ from run to run by nature


def pbdval(*args: str, check: bool = True) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(pbdval_binary()), *args], capture_output=True, text=True, check=check)


def shard_folders(tmp_path: Path, count: int) -> list[str]:
    folders = []
    for k in range(1, count + 1):
        folder = tmp_path / f"shard-{k}"
        pbdval("run", *CASES, "--engines", ENGINES, "--shard", f"{k}/{count}", "--out", str(folder),
               "--jobs", "1", "--quiet")
        folders.append(str(folder))
    return folders


def comparable(folder: Path) -> list[tuple[object, ...]]:
    results = load_results(folder)
    return [(r.case, r.engine, r.method, r.status, r.facts.get("engineVersion"),
             {k: v for k, v in r.metrics.items() if k not in TIMING},
             r.trajectory().positions.tobytes() if r.ok else b"")
            for r in results]


def test_merged_shards_equal_one_run_of_the_plan(tmp_path: Path) -> None:
    folders = shard_folders(tmp_path, 3)
    merged = tmp_path / "merged"
    out = pbdval("merge", *folders, "--out", str(merged), "--quiet")
    assert "3 shards" in out.stdout
    pbdval("run", *CASES, "--engines", ENGINES, "--out", str(tmp_path / "whole"), "--jobs", "2", "--quiet")
    assert comparable(merged) == comparable(tmp_path / "whole")  # order, statuses, metrics, trajectories
    document = json.loads((merged / "results.json").read_text())
    whole = json.loads((tmp_path / "whole" / "results.json").read_text())
    assert "shard" not in document["metadata"]
    assert document["cases"] == whole["cases"]
    # PBD is bitwise deterministic: the state hashes agree run for run.
    hashes = [r.get("state_hash") for r in document["runs"]]
    assert hashes == [r.get("state_hash") for r in whole["runs"]] and any(hashes)


def test_shards_that_do_not_make_one_plan_are_refused(tmp_path: Path) -> None:
    folders = shard_folders(tmp_path, 3)
    gap = pbdval("merge", folders[0], folders[2], "--out", str(tmp_path / "m"), check=False)
    assert gap.returncode == 2 and "missing shard(s) 2 of 3" in gap.stderr
    overlap = pbdval("merge", folders[0], folders[0], folders[1], folders[2], "--out", str(tmp_path / "m"), check=False)
    assert overlap.returncode == 2 and "given twice" in overlap.stderr
    other = tmp_path / "other"
    pbdval("run", CASES[0], "--engines", ENGINES, "--shard", "2/3", "--out", str(other), "--quiet")
    mixed_plan = pbdval("merge", folders[0], str(other), folders[2], "--out", str(tmp_path / "m"), check=False)
    assert mixed_plan.returncode == 2 and "another plan" in mixed_plan.stderr
    # Another build: a shard whose results name another commit.
    rebuilt = Path(folders[1]) / "results.json"
    document = json.loads(rebuilt.read_text())
    document["metadata"]["pbdval"]["commit"] = "0" * 40
    rebuilt.write_text(json.dumps(document))
    mixed_build = pbdval("merge", *folders, "--out", str(tmp_path / "m"), check=False)
    assert mixed_build.returncode == 2 and "another build" in mixed_build.stderr
    whole = tmp_path / "whole"
    pbdval("run", CASES[0], "--engines", "pbd", "--out", str(whole), "--quiet")
    not_shard = pbdval("merge", str(whole), "--out", str(tmp_path / "m"), check=False)
    assert not_shard.returncode == 2 and "not a shard" in not_shard.stderr
    assert not (tmp_path / "m").exists()  # nothing written by a refused merge


@pytest.mark.parametrize("text", ["0/3", "4/3", "3", "a/b", "1/0", "-1/2", "1/2/3"])
def test_bad_shard_specifications_are_usage_errors(tmp_path: Path, text: str) -> None:
    out = pbdval("run", CASES[0], "--shard", text, "--out", str(tmp_path / "o"), check=False)
    assert out.returncode == 2 and "--shard: expected K/N" in out.stderr


def test_an_unreadable_case_keeps_results_readable_and_shards_mergeable(tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text('{"RigidBodies": 5}')
    cases = [str(bad), CASES[0], CASES[2]]
    whole = tmp_path / "whole"
    pbdval("run", *cases, "--engines", "pbd", "--out", str(whole), "--quiet")
    # The gate's readers accept the file: the unreadable case has its entry, without checks.
    pbdval("baseline", "--results", str(whole), "--out", str(tmp_path / "baseline.json"))
    results = load_results(whole)
    assert [r.status for r in results if r.case == "bad"] == ["error"]
    folders = []
    for k in (1, 2):
        folder = tmp_path / f"s{k}"
        pbdval("run", *cases, "--engines", "pbd", "--shard", f"{k}/2", "--out", str(folder), "--quiet")
        folders.append(str(folder))
    pbdval("merge", *folders, "--out", str(tmp_path / "merged"), "--quiet")
    assert comparable(tmp_path / "merged") == comparable(whole)
