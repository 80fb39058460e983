"""pbdval from Python: scenes, engines, stepping, metrics and results (docs/python.md).

    import pbdval
    scene = pbdval.load_scene("cases/joint_hinge.json")
    sim = pbdval.Simulation(scene, "pbd.xpbd", {"substeps": 40})
    sim.step(100)
    states = sim.state()                 # positions (N,3), quaternions (N,4) w,x,y,z, ...
    info, trajectory = pbdval.simulate(scene, "mujoco.rk4")
    print(pbdval.measure(scene, trajectory)["energy_drift_max"])

The C++ core (pbdval._core) is built by CMake into <build>/python/pbdval/; scripts/install-deps
puts that folder and <source>/python on the venv's path, and the two are one package here.
The external-engine protocol (pbdval.protocol) needs only the pure-Python part.
"""

from __future__ import annotations

from pkgutil import extend_path
from typing import TYPE_CHECKING

# The extension lives in the build folder's pbdval/ (no __init__.py there): join it.
__path__ = extend_path(__path__, __name__)

if TYPE_CHECKING:  # what the lazy __getattr__ below returns, for type checkers
    from pbdval.api import (
        BodyStates,
        Energy,
        EngineInfo,
        Engines,
        MethodInfo,
        Metrics,
        Parameter,
        RunInfo,
        Scene,
        Simulation,
        Trajectory,
        energy,
        engines,
        load_scene,
        measure,
        read_particles,
        read_segments,
        simulate,
    )
    from pbdval.errors import (
        ArgumentError,
        BuildMissingError,
        CommandError,
        DivergenceError,
        EngineError,
        PbdvalError,
        ResultsError,
        SceneError,
        UnsupportedError,
    )
    from pbdval.results import Results, RunResult, load_results, run

__all__ = [
    "ArgumentError",
    "BodyStates",
    "BuildMissingError",
    "CommandError",
    "DivergenceError",
    "Energy",
    "EngineError",
    "EngineInfo",
    "Engines",
    "MethodInfo",
    "Metrics",
    "Parameter",
    "PbdvalError",
    "Results",
    "ResultsError",
    "RunInfo",
    "RunResult",
    "Scene",
    "SceneError",
    "Simulation",
    "Trajectory",
    "UnsupportedError",
    "energy",
    "engines",
    "load_results",
    "load_scene",
    "measure",
    "read_particles",
    "read_segments",
    "run",
    "simulate",
]

_API = {"BodyStates", "Energy", "EngineInfo", "Engines", "MethodInfo", "Metrics", "Parameter",
        "RunInfo", "Scene", "Simulation", "Trajectory", "energy", "engines", "load_scene",
        "measure", "read_particles", "read_segments", "simulate"}
_RESULTS = {"Results", "RunResult", "load_results", "run"}
_ERRORS = {"ArgumentError", "BuildMissingError", "CommandError", "DivergenceError", "EngineError",
           "PbdvalError", "ResultsError", "SceneError", "UnsupportedError"}


def __getattr__(name: str) -> object:
    # Loaded on first use, so that external engines importing pbdval.protocol never need the
    # C++ core or numpy's import time, and an engine server's start does not pay for the errors'
    # module (it imports subprocess: 3-4 ms of CPU; docs/benchmarks.md, seventh pass).
    if name in _ERRORS:
        from pbdval import errors

        return getattr(errors, name)
    if name in _API:
        from pbdval import api

        return getattr(api, name)
    if name in _RESULTS:
        from pbdval import results

        return getattr(results, name)
    raise AttributeError(f"module 'pbdval' has no attribute {name!r}")
