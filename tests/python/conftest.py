"""Shared fixtures of the Python tests (scripts/test runs them with .venv/bin/python).

Nothing is skipped silently: a skipped test is turned into a failure carrying the skip reason
(pytest_runtest_makereport below), and a missing pbdval binary fails the tests that need it.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any, Callable

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
VENV_PYTHON = REPO / ".venv" / "bin" / "python"


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[Any]):  # type: ignore[no-untyped-def]
    outcome = yield
    report = outcome.get_result()
    if report.skipped and not hasattr(report, "wasxfail"):
        report.outcome = "failed"
        report.longrepr = f"skipped tests fail here (tests/python/conftest.py): {report.longrepr}"


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def pbdval_binary() -> Path:
    build = Path(os.environ.get("PBDVAL_BUILD_DIR", REPO / "build" / "release"))
    binary = build / "bin" / "pbdval"
    if not binary.is_file():
        pytest.fail(f"{binary} is missing: build it (cmake --build --preset release --target pbdval) "
                    "or set PBDVAL_BUILD_DIR")
    return binary


@pytest.fixture(scope="session")
def export_scene(pbdval_binary: Path, tmp_path_factory: pytest.TempPathFactory) -> Callable[..., Path]:
    """export_scene("joint_hinge", method=..., parameters={...}, duration=...) → the path of the
    case's resolved scene, with the method block as the runner would fill it."""
    folder = tmp_path_factory.mktemp("resolved")

    def export(case: str, method: str = "", parameters: dict[str, Any] | None = None,
               duration: float | None = None, sample_interval: float | None = None) -> Path:
        command = [str(pbdval_binary), "export-scene", str(REPO / "cases" / f"{case}.json"), "--quiet"]
        if duration is not None:
            command += ["--duration", repr(duration)]
        if sample_interval is not None:
            command += ["--sample-interval", repr(sample_interval)]
        result = subprocess.run(command, capture_output=True, text=True, cwd=REPO, check=False)
        assert result.returncode == 0, f"{' '.join(command)}: {result.stderr}"
        document = json.loads(result.stdout)
        document["method"] = {"name": method, "parameters": parameters or {}}
        path = folder / f"{case}-{len(list(folder.iterdir()))}.json"
        path.write_text(json.dumps(document))
        return path

    return export


@pytest.fixture
def run_engine(tmp_path: Path) -> Callable[[str, Path], tuple[dict[str, Any], Path]]:
    """run_engine("adapters/pybullet/engine.py", scene) → (status.json, OUTDIR), run as the
    runner does: venv interpreter by path, repository root as working directory, PBDVAL_PROTOCOL=1."""
    counter = [0]

    def run(script: str, scene: Path) -> tuple[dict[str, Any], Path]:
        counter[0] += 1
        out = tmp_path / f"out{counter[0]}"
        out.mkdir()
        env = dict(os.environ, PBDVAL_PROTOCOL="1")
        result = subprocess.run([str(VENV_PYTHON), str(REPO / script), "--scene", str(scene),
                                 "--out", str(out)], capture_output=True, text=True, cwd=REPO,
                                env=env, check=False, timeout=600)
        assert result.returncode == 0, f"{script} exited {result.returncode}: {result.stderr}"
        assert result.stdout == "", f"{script} wrote to standard output: {result.stdout[:200]}"
        status = json.loads((out / "status.json").read_text())
        return status, out

    return run
