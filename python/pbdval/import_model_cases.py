"""The library's cases from real robot models (cases/robot_*.json, docs/models.md#cases): each is
`pbdval import` of a pybullet_data URDF or a dm_control suite MJCF, at a declared start, with a
Validation block declared here. The committed files are this module's output:

    .venv/bin/python -m pbdval.import_model_cases --write   # regenerate cases/robot_*.json
    .venv/bin/python -m pbdval.import_model_cases --check   # exit 1 if a committed file differs
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pbdval.import_model import import_model
from pbdval.import_model_sweep import pybullet_data_root, suite_root

REPO = Path(__file__).resolve().parents[2]
CASES = REPO / "cases"
#: Collision meshes of the robot cases, below cases/ (relative paths in the scenes).
MESHES = CASES / "models" / "robots"

ENERGY_NOT_CREATED = {
    "metric": "energy_drift_final", "max": 0.01, "engines": ["pbd", "bullet", "ode"],
    "description": "the passive robot has no energy source, and these engines' constraint projections only "
                   "dissipate: final drift at most +1 % of E_ref. Not required of the reduced-coordinate "
                   "engines: semi-implicit Euler in joint coordinates is not symplectic with a configuration-"
                   "dependent mass matrix and gains energy (measured on the iiwa at h = 1 ms: +16 % in 2 s in "
                   "MuJoCo and pybullet.multibody alike)"}
JOINTS_HOLD_IN_REDUCED_COORDINATES = {
    "metric": "joint_error_linear_max", "max": 2.2e-12, "engines": ["mujoco", "mujoco-python"],
    "description": "the joints are MuJoCo's coordinates: what separates their two sides is round-off in forward "
                   "kinematics on metre-sized coordinates, 1e4 epsilon with room (measured below 1.5e-15 m)"}
#: The minitaur's legs: its eight motor joints and lower legs (front/back, right/left, R/L half).
MINITAUR_LEGS = [f"{end}_{side}{half}" for end in ("front", "back") for side in ("right", "left") for half in "RL"]
#: The links of the drop that keep collision shapes: the chassis and the lower legs (the upper legs'
#: and motors' shapes overlap their neighbours at the joints, and jointed bodies collide).
MINITAUR_COLLIDING = {"base_chassis_link", "chassis_right", "chassis_left"} | {
    f"lower_leg_{leg}_link" for leg in MINITAUR_LEGS}


@dataclass
class RobotCase:
    name: str
    source: str  # "pybullet_data" or "dm_control"
    model: str  # path within the source
    description: str
    validation: dict[str, Any]
    fixed_base: bool = False
    collisions: bool = True
    positions: dict[str, float] = field(default_factory=dict)
    #: A static ground box added under the robot: [top height z, half extent in x and y] (m).
    ground: tuple[float, float] | None = None
    #: Raises every body by this much (m) before the ground is added.
    lift: float = 0.0
    #: The frame step (s); None: the model's (MJCF) or the importer's default (URDF).
    time_step: float | None = None
    #: Only these links keep their collision shapes (None: all).
    collision_links: set[str] | None = None
    #: URDF: the links' inertia from their collision shapes (pybullet's loadURDF default).
    inertia_from_collision: bool = False


#: 1 ms for the URDF chains: pybullet's default 1/240 s leaves the reduced-coordinate engines
#: diverging on the iiwa at 1.6 s (its light distal links), and at 5 ms pendulum5's energy error
#: reaches 14-40 % in every engine.
CHAIN_STEP = 0.001
CHAIN_CHECKS = [ENERGY_NOT_CREATED, JOINTS_HOLD_IN_REDUCED_COORDINATES]

ROBOT_CASES = [
    RobotCase(
        "robot_kuka_iiwa_swing", "pybullet_data", "kuka_iiwa/model.urdf",
        "KUKA LBR iiwa (pybullet_data), base fixed, started bent (joint 2 at 0.8 rad, joint 4 at -1 rad) and "
        "swinging passively under gravity on its 7 hinges; no collision shapes (its link meshes overlap at the "
        "joints, and jointed bodies collide)",
        {"duration": 2.0, "sampleInterval": 0.01, "conserved": ["energy"], "checks": CHAIN_CHECKS},
        fixed_base=True, collisions=False, positions={"lbr_iiwa_joint_2": 0.8, "lbr_iiwa_joint_4": -1.0},
        time_step=CHAIN_STEP),
    RobotCase(
        "robot_pendulum5", "pybullet_data", "pendulum5.urdf",
        "pybullet_data's pendulum5.urdf: five 0.5 m links (point-like spheres) on continuous joints about x, "
        "released horizontally; chaotic, energy conserved by the exact dynamics",
        {"duration": 3.0, "sampleInterval": 0.01, "conserved": ["energy"], "checks": CHAIN_CHECKS},
        time_step=CHAIN_STEP),
    RobotCase(
        "robot_minitaur_drop", "pybullet_data", "quadruped/minitaur.urdf",
        "Ghost Robotics Minitaur (pybullet_data), a free quadruped of 17 bodies (fixed links merged), legs "
        "turned down (motor joints at pi), dropped with its feet 0.19 m above a static ground box with "
        "its legs passive; inertias from the collision shapes, as pybullet loads it (the file's are "
        "placeholders: 1 kg m^2 on a 50 g leg); the chassis (one mesh of its three boxes) and the lower legs "
        "(boxes) collide",
        {"duration": 1.5, "sampleInterval": 0.01, "checks": [
            {"metric": "penetration_max", "max": 0.1,
             "description": "no foot passes through the ground: penetration below half a lower leg (0.2 m); "
                            "measured 1.1 cm (pybullet.si) to 7.7 cm (pbd.xpbd) on the 1 cm thick legs; the "
                            "seed's pbd lets a leg through (0.2 m, status suspect)"},
            {"metric": "energy_drift_final", "max": 0.01,
             "description": "a passive robot falling onto the ground has no energy source: final drift at most "
                            "+1 % of E_ref"}]},
        ground=(0.0, 2.0), lift=0.5, collision_links=MINITAUR_COLLIDING, inertia_from_collision=True,
        positions={f"motor_{leg}_joint": math.pi for leg in MINITAUR_LEGS}),
    RobotCase(
        "robot_dm_cartpole", "dm_control", "cartpole.xml",
        "dm_control's cart-pole: the cart on a slider, the pole on a hinge started 0.3 rad from upright; "
        "the suite disables contacts, so no shapes; energy conserved by the exact dynamics",
        {"duration": 3.0, "sampleInterval": 0.01, "conserved": ["energy"], "checks": CHAIN_CHECKS},
        positions={"hinge_1": 0.3}),
    RobotCase(
        "robot_dm_acrobot", "dm_control", "acrobot.xml",
        "dm_control's acrobot: two 1 m capsule links on hinges, started at 0.4 and 0.3 rad from upright; "
        "the suite disables constraints, so no shapes; chaotic, energy conserved by the exact dynamics",
        {"duration": 3.0, "sampleInterval": 0.01, "conserved": ["energy"], "checks": CHAIN_CHECKS},
        positions={"shoulder": 0.4, "elbow": 0.3}),
]


def model_path(case: RobotCase) -> Path:
    return (pybullet_data_root() if case.source == "pybullet_data" else suite_root()) / case.model


def scene_text(case: RobotCase, scene_path: Path, mesh_folder: Path) -> str:
    """The case file's text: the import, the start, the ground and the Validation block."""
    result = import_model(model_path(case), scene_path, fixed_base=case.fixed_base, collisions=case.collisions,
                          positions=case.positions, mesh_folder=mesh_folder, collision_links=case.collision_links,
                          inertia_from_collision=case.inertia_from_collision)
    scene = result.scene
    scene["Name"] = case.name
    if case.time_step is not None:
        scene["Simulation"]["timeStepSize"] = case.time_step
    if case.lift:
        for body in scene["RigidBodies"]:
            body["translation"][2] += case.lift
        for block in ("BallJoints", "HingeJoints", "UniversalJoints"):
            for joint in scene.get(block, []):
                joint["position"][2] += case.lift
    notes = list(scene["Validation"]["notes"])
    if case.ground:
        top, half = case.ground
        ground_id = len(scene["RigidBodies"])
        scene["RigidBodies"].append({
            "id": ground_id, "isDynamic": False, "collisionObjectType": 2,
            "collisionObjectScale": [2 * half, 2 * half, 0.2], "translation": [0.0, 0.0, top - 0.1]})
        notes.append(f"body {ground_id}: the ground, a static box {2 * half} x {2 * half} x 0.2 m with its top at "
                     f"z = {top} (added by the case, not in the model)")
    if case.lift:
        notes.append(f"every body raised by {case.lift} m (the drop)")
    source = ("pybullet_data (pybullet 3.2.7, zlib licence)" if case.source == "pybullet_data"
              else "the dm_control suite (dm-control 1.0.50, Apache-2.0 licence)")
    origin = (f"imported by `pbdval import` from {case.model} of {source}; "
              "regenerate with python -m pbdval.import_model_cases --write")
    scene["Validation"] = {"schema": 1, "description": case.description, **case.validation,
                           "notes": [origin, *notes]}
    return json.dumps(scene, indent=2) + "\n"


def generate(folder: Path) -> dict[Path, str]:
    """Every case file and collision mesh as `folder` (standing for cases/) would hold them."""
    files: dict[Path, str] = {}
    for case in ROBOT_CASES:
        scene_path = folder / f"{case.name}.json"
        mesh_folder = folder / "models" / "robots" / case.name
        files[scene_path] = scene_text(case, scene_path, mesh_folder)
        if mesh_folder.is_dir():
            for mesh in sorted(mesh_folder.iterdir()):
                files[mesh] = mesh.read_text(encoding="utf-8")
    return files


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pbdval.import_model_cases", description=__doc__)
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", action="store_true", help="write cases/robot_*.json and their meshes")
    group.add_argument("--check", action="store_true", help="exit 1 unless the committed files are current")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        generated = generate(Path(scratch))
        stale = []
        for path, text in generated.items():
            committed = CASES / path.relative_to(scratch)
            if args.write:
                committed.parent.mkdir(parents=True, exist_ok=True)
                committed.write_text(text, encoding="utf-8")
            elif not committed.is_file() or committed.read_text(encoding="utf-8") != text:
                stale.append(committed)
    for path in stale:
        print(f"{path}: differs from its generation: run python -m pbdval.import_model_cases --write",
              file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
