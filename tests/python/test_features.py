"""The engines' feature tables (docs/engines.md#features) against the catalogue schema, the
generated parity pages, the case-library plan and the committed baseline: what an engine declares
is what its runs do."""

from __future__ import annotations

import json
import subprocess
from functools import cache
from pathlib import Path
from typing import Any

import jsonschema
import pytest

from pbdval import protocol as pp
from pbdval.api import _core
from pbdval.parity import REGENERATE, stale_pages

REPO = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((REPO / "docs" / "schemas" / "catalogue.schema.json").read_text(encoding="utf-8"))
BASELINE = REPO / "reports" / "baselines" / "main.json"
#: The engines that run in another process and whose own support check can be called here
#: (engine → the module with unsupported_features(ResolvedScene)).
EXTERNAL_CHECKS = {"pybullet": "pbdval.external.pybullet.engine", "mujoco-python": "pbdval.external.mujoco.engine",
                   "dart": "pbdval.external.dart.engine",
                   "drake": "pbdval.external.drake.engine"}


def test_the_catalogue_schema_is_a_valid_draft_2020_12_schema() -> None:
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("path", sorted((REPO / "engines").glob("*.json")), ids=lambda p: p.name)
def test_every_shipped_catalogue_entry_matches_the_schema_and_declares_its_features(path: Path) -> None:
    document = json.loads(path.read_text(encoding="utf-8"))
    errors = sorted(jsonschema.Draft202012Validator(SCHEMA).iter_errors(document), key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{path.name}: {'/'.join(map(str, e.path))}: {e.message}" for e in errors)
    assert document.get("features"), f"{path.name}: no feature table"


def test_the_schema_refuses_an_unsupported_entry_without_its_reason_and_an_unknown_key() -> None:
    document = json.loads((REPO / "engines" / "example-euler.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(SCHEMA)
    without_reason = {**document, "features": [{"feature": "joint", "support": "unsupported"}]}
    assert any("text" in e.message for e in validator.iter_errors(without_reason))
    unknown = {**document, "feature": []}
    assert any("feature" in e.message for e in validator.iter_errors(unknown))


def test_the_reader_refuses_a_catalogue_feature_table_naming_the_file_and_json_path(
        tmp_path: Path, pbdval_binary: Path) -> None:
    document = json.loads((REPO / "engines" / "example-euler.json").read_text(encoding="utf-8"))
    document["name"] = "probe"
    document["defaultMethod"] = "probe.x"
    document["methods"] = [{"name": "probe.x", "description": "d"}]
    document["features"] = [*document["features"], {"feature": "joint.hinges", "support": "native"}]
    (tmp_path / "probe.json").write_text(json.dumps(document), encoding="utf-8")
    result = subprocess.run([str(pbdval_binary), "methods"], capture_output=True, text=True, check=False,
                            env={"PBDVAL_ENGINE_CATALOGUE": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert result.returncode != 0
    assert "probe.json" in result.stderr and "features[9].feature" in result.stderr, result.stderr
    assert "joint.hinges" in result.stderr


def test_the_generated_parity_pages_are_current() -> None:
    stale = stale_pages()
    assert not stale, (f"generated parity pages are stale: {', '.join(f'docs/{f}' for f in stale)}; "
                       f"regenerate them with {REGENERATE}")


def test_the_cross_engine_table_compares_every_engine_with_a_page_opt_in_ones_included() -> None:
    from pbdval.parity import ENGINE_PAGES

    text = (REPO / "docs" / "parity.md").read_text(encoding="utf-8")
    header = next(line for line in text.splitlines() if line.startswith("| feature |"))
    columns = [c.strip() for c in header.strip("|").split("|")][1:]
    # The reference engines (DART, Drake, and Newton, which runs only when named) are columns.
    for engine in ENGINE_PAGES:
        assert engine in columns, (engine, columns)
    assert "example-euler" not in columns  # the catalogue's example is no engine to compare


def test_the_mujoco_python_catalogue_carries_the_generators_feature_table() -> None:
    from pbdval.external.mujoco.features import FEATURES

    shipped = json.loads((REPO / "engines" / "mujoco-python.json").read_text(encoding="utf-8"))
    assert shipped["features"] == FEATURES


# ---- the case-library plan ---------------------------------------------------------------------


@cache
def plan_runs(binary: str) -> tuple[tuple[str, str, str], ...]:
    """(case file, engine, method) of every run `pbdval run` makes by default (the full suite)."""
    result = subprocess.run([binary, "run", "--list-plan"], capture_output=True, text=True, cwd=REPO, check=False)
    assert result.returncode == 0, result.stderr
    plan = json.loads(result.stdout)
    runs = []
    for run in plan["runs"]:
        assert not run.get("assignments"), f"a plan run with --set assignments: {run}"
        runs.append((run["caseFile"], run["engine"], run["method"]))
    return tuple(runs)


@cache
def support(case_file: str, method: str) -> dict[str, Any]:
    core = _core()
    registry = registry_handle()
    scene = core._load_scene(str(REPO / case_file), False)
    result: dict[str, Any] = core._feature_support(registry, scene, method)
    return result


@cache
def registry_handle() -> Any:
    return _core()._Registry()


def baseline_statuses() -> dict[tuple[str, str], str]:
    document = json.loads(BASELINE.read_text(encoding="utf-8"))
    return {(r["case"], r["method"]): r["status"] for r in document["runs"] if not r.get("assignments")}


def test_every_unsupported_use_of_a_plan_run_is_declared_unsupported_by_its_engine(pbdval_binary: Path) -> None:
    runs = plan_runs(str(pbdval_binary))
    assert len(runs) > 300  # the full suite: every case in every engine run by default
    for case_file, engine, method in runs:
        s = support(case_file, method)
        assert s["declares_features"], f"{engine}: no feature table"
        decided = {(u["feature"], u["json_path"]): u["support"] for u in s["uses"]}
        for use in s["uses"]:
            assert use["support"] != "undeclared", f"{case_file} {method}: {use}"
        for item in s["table_unsupported"]:
            assert decided[(item["feature"], item["json_path"])] == "unsupported", (case_file, method, item)
        if not s["table_unsupported"]:
            assert all(u["support"] != "unsupported" for u in s["uses"]), (case_file, method)


def test_a_plan_run_is_unsupported_before_it_starts_exactly_when_its_table_says_so(pbdval_binary: Path) -> None:
    """The engines' unsupported() (what the runner asks before a run) is the table's verdict; the
    only uses a table alone cannot see are the loop closures of a reduced-coordinate engine's
    spanning tree, which the engine adds (they name joint.closingLoop features)."""
    for case_file, engine, method in plan_runs(str(pbdval_binary)):
        s = support(case_file, method)
        table = [u["message"] for u in s["table_unsupported"]]
        extra = [m for m in s["engine_unsupported"] if m not in table]
        assert all(m in s["engine_unsupported"] for m in table), (case_file, method)
        assert all("closes a kinematic loop" in m for m in extra), (case_file, method, extra)


def test_the_baselines_statuses_agree_with_the_tables(pbdval_binary: Path) -> None:
    """reports/baselines/main.json holds the full suite's statuses as the engines gave them (the
    external engines by their own checks, in their own process): a run is `unsupported` there
    exactly when its engine's table (with the engine's own uses) declares a feature of it
    unsupported."""
    statuses = baseline_statuses()
    compared = 0
    disagreements = []
    for case_file, engine, method in plan_runs(str(pbdval_binary)):
        case = Path(case_file).stem
        if (case, method) not in statuses:
            continue
        compared += 1
        unsupported = bool(support(case_file, method)["engine_unsupported"])
        if unsupported != (statuses[(case, method)] == "unsupported"):
            disagreements.append(f"{case} {method}: baseline {statuses[(case, method)]}, "
                                 f"table {'unsupported' if unsupported else 'runs'}")
    assert compared >= 300, compared  # the baseline covers the default plan
    assert not disagreements, "\n".join(disagreements)


@pytest.mark.parametrize("engine", sorted(EXTERNAL_CHECKS))
def test_an_external_engines_own_check_agrees_with_its_catalogue_table_on_every_plan_run(
        engine: str, pbdval_binary: Path) -> None:
    """The Python engines check the resolved scene themselves when they run; on every case of the
    plan, and every one of the engine's methods, they refuse a run exactly when the catalogue's
    table does."""
    import importlib

    module = importlib.import_module(EXTERNAL_CHECKS[engine])
    core = _core()
    registry = registry_handle()
    cases = sorted({case_file for case_file, e, _ in plan_runs(str(pbdval_binary)) if e == engine})
    methods = [m for e in core._engines(registry) if e["name"] == engine for m in (x["name"] for x in e["methods"])]
    disagreements = []
    for case_file in cases:
        scene = core._load_scene(str(REPO / case_file), False)
        for method in methods:
            resolved = pp.parse_resolved_scene(core._resolved_scene(registry, scene, method, {}, 0.1, -1.0), case_file)
            own = module.unsupported_features(resolved)
            table = [u["message"] for u in support(case_file, method)["table_unsupported"]]
            if bool(own) != bool(table):
                disagreements.append(f"{case_file} {method}: engine {own or 'runs'}; table {table or 'runs'}")
    assert not disagreements, "\n".join(disagreements)
