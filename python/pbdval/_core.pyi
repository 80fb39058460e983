# Type stubs of the C++ extension pbdval._core (python/bindings/core.cpp). Users call the typed
# wrappers of pbdval.api; these names are the contract between the two.
from typing import Any

import numpy as np
from numpy.typing import NDArray

version: str
default_wall_time_limit: float  # s, kDefaultWallTimeLimit (validation/simulation.h)
max_steps_per_run: float  # kMaxStepsPerRun

class _Scene: ...

class _Registry:
    def __init__(self) -> None: ...

class _Stepper:
    def __init__(self, registry: _Registry, scene: _Scene, method: str, parameters: dict[str, Any]) -> None: ...
    def step(self, count: int) -> None: ...
    def time(self) -> float: ...
    def body_count(self) -> int: ...
    def read_into(self, packed: NDArray[np.float64]) -> float: ...
    def facts(self) -> dict[str, Any]: ...

def _load_scene(path: str, strict: bool) -> _Scene: ...
def _scene_summary(scene: _Scene) -> dict[str, Any]: ...
def _run_length(registry: _Registry, scene: _Scene) -> tuple[float, float]: ...
def _resolved_scene(
    registry: _Registry, scene: _Scene, method: str, parameters: dict[str, Any], duration: float, interval: float
) -> dict[str, Any]: ...
def _engines(registry: _Registry) -> list[dict[str, Any]]: ...
def _scene_features() -> list[dict[str, Any]]: ...
def _feature_support(registry: _Registry, scene: _Scene, method: str) -> dict[str, Any]: ...
def _did_you_mean(name: str, candidates: list[str]) -> str: ...
def _simulate(
    registry: _Registry,
    scene: _Scene,
    method: str,
    parameters: dict[str, Any],
    duration: float,
    interval: float,
    wall_time_limit: float,
) -> tuple[dict[str, Any], dict[str, Any]]: ...
def _measure(
    registry: _Registry,
    scene: _Scene,
    times: NDArray[np.float64],
    positions: NDArray[np.float64],
    quaternions: NDArray[np.float64],
    velocities: NDArray[np.float64],
    angular_velocities: NDArray[np.float64],
    particle_positions: NDArray[np.float64] | None,
    particle_velocities: NDArray[np.float64] | None,
    segment_rotations: NDArray[np.float64] | None,
    segment_angular_velocities: NDArray[np.float64] | None,
    reference: Any,
    contact_margin: float,
    integration_step: float,
) -> dict[str, Any]: ...
def _energy(
    registry: _Registry,
    scene: _Scene,
    times: NDArray[np.float64],
    positions: NDArray[np.float64],
    quaternions: NDArray[np.float64],
    velocities: NDArray[np.float64],
    angular_velocities: NDArray[np.float64],
    particle_positions: NDArray[np.float64] | None,
    particle_velocities: NDArray[np.float64] | None,
    segment_rotations: NDArray[np.float64] | None,
    segment_angular_velocities: NDArray[np.float64] | None,
) -> dict[str, Any]: ...
def _read_trajectory(path: str) -> dict[str, Any]: ...
