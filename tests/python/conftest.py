"""Shared fixtures of the Python tests (scripts/test runs them with .venv/bin/python).

Nothing is skipped silently: a skipped test is turned into a failure carrying the skip reason
(pytest_runtest_makereport below), and a missing pbdval binary fails the tests that need it.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Callable, Generator
from pathlib import Path
from typing import Any

import pytest

REPO = Path(__file__).resolve().parents[2]
#: The build under test: its pbdval._core (the folder python/) comes before any other checkout's
#: the venv's .pth may name, as the runner sets it for its Python engines.
BUILD = Path(os.environ.get("PBDVAL_BUILD_DIR", REPO / "build" / "release"))
sys.path.insert(0, str(REPO / "python"))
sys.path.insert(1, str(BUILD / "python"))
VENV_PYTHON = REPO / ".venv" / "bin" / "python"


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[Any]) -> Generator[None, Any, None]:
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
    binary = BUILD / "bin" / "pbdval"
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


def engine_command(name: str) -> list[str]:
    """The command of catalogue entry engines/<name>.json as the runner runs it: "{python}"
    replaced by the venv's interpreter (validation/external/engine_catalogue.cpp)."""
    command = json.loads((REPO / "engines" / f"{name}.json").read_text())["command"]
    return [str(VENV_PYTHON) if word == "{python}" else word for word in command]


def engine_environment() -> dict[str, str]:
    """The environment the runner gives a "{python}" engine: PBDVAL_PROTOCOL=1 and this source
    tree's python/ and the build's first on PYTHONPATH (validation/external/standard_engines.cpp)."""
    inherited = os.environ.get("PYTHONPATH", "")
    path = os.pathsep.join([str(REPO / "python"), str(BUILD / "python")]) + (
        os.pathsep + inherited if inherited else "")
    return dict(os.environ, PBDVAL_PROTOCOL="1", PYTHONPATH=path)


@pytest.fixture
def run_engine(tmp_path: Path) -> Callable[[str, Path], tuple[dict[str, Any], Path]]:
    """run_engine("pybullet", scene) → (status.json, OUTDIR): the catalogue entry's command run as
    the runner does (engine_command, engine_environment), in the catalogue's folder (engines/),
    where its relative paths lead."""
    counter = [0]

    def run(engine: str, scene: Path) -> tuple[dict[str, Any], Path]:
        counter[0] += 1
        out = tmp_path / f"out{counter[0]}"
        out.mkdir()
        result = subprocess.run(engine_command(engine) + ["--scene", str(scene), "--out", str(out)],
                                capture_output=True, text=True, cwd=REPO / "engines",
                                env=engine_environment(), check=False, timeout=600)
        assert result.returncode == 0, f"{engine} exited {result.returncode}: {result.stderr}"
        assert result.stdout == "", f"{engine} wrote to standard output: {result.stdout[:200]}"
        status = json.loads((out / "status.json").read_text())
        return status, out

    return run
