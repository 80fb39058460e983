"""Writes pbdval's own versions of PositionBasedDynamics' demo scenes (issue 28).

The original's scene files and meshes are not part of this repository; these scenes are written
here from the demos' description (bodies, joints, parameters as docs/seed.md lists them), on the
project's own meshes (cases/models) and an own 50 x 50 cloth plane (models/plane_50x50.obj).
Both programs read the files written here; README.md says how each recording was made.

    .venv/bin/python tests/data/seed_reference/make_demo_scenes.py
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
CUBE = "../../../../cases/models/cube.obj"
SPHERE = "../../../../cases/models/sphere.obj"
CYLINDER = "../../../../cases/models/cylinder.obj"
TORUS = "../../../../cases/models/torus.obj"

Vec = list[float]
Json = dict[str, Any]


def write_atomically(path: Path, text: str) -> None:
    """Writes `text` to `path` through a temporary file renamed over it."""
    temporary = path.with_suffix(path.suffix + ".tmp")
    temporary.write_text(text, encoding="utf-8")
    os.replace(temporary, path)


def rigid_body(
    body_id: int,
    mesh: str,
    collision_type: int,
    scale: Vec,
    translation: Vec,
    *,
    dynamic: bool,
    density: float = 500,
    restitution: float = 0.6,
    friction: float = 0.3,
    collision_scale: Vec | None = None,
    rotation_axis: Vec | None = None,
    rotation_angle: float = 0.0,
    angular_velocity: Vec | None = None,
) -> Json:
    """One entry of `RigidBodies`."""
    body: Json = {
        "id": body_id,
        "geometryFile": mesh,
        "isDynamic": dynamic,
        "density": density,
        "translation": translation,
        "rotationAxis": rotation_axis or [1, 0, 0],
        "rotationAngle": rotation_angle,
        "scale": scale,
        "restitution": restitution,
        "friction": friction,
        "collisionObjectType": collision_type,
        "collisionObjectScale": collision_scale or scale,
    }
    if angular_velocity is not None:
        body["angularVelocity"] = angular_velocity
    return body


def plane_cloth(model_id: int, translation: list[float], *, restitution: float,
                static_particles: list[int] | None = None) -> Json:
    """The demos' cloth: the 10 m plane of 50 x 50 particles (models/plane_50x50.obj) in the xz
    plane, friction 0.1; `staticParticles` written only when given (ClothOnBunny has none)."""
    model: Json = {
        "id": model_id,
        "geometryFile": "../models/plane_50x50.obj",
        "translation": translation,
        "rotationAxis": [1, 0, 0],
        "rotationAngle": 0.0,
        "scale": [10, 10, 10],
    }
    if static_particles is not None:
        model["staticParticles"] = static_particles
    model["restitution"] = restitution
    model["friction"] = 0.1
    return model


def car_scene() -> Json:
    """The car demo: a chassis on four damper joints, steered by a target-angle motor hinge,
    driven by four target-velocity motor hinges on sphere wheels, on a box ground.

    Its generator sets `"gravity": [0, -2, 0]`, a key PositionBasedDynamics does not read, so the
    demo runs with the default gravitation; written here as that default.
    """
    car = [0.0, 2.0, 0.0]

    def at(offset: Vec) -> Vec:
        return [round(c + o, 12) for c, o in zip(car, offset, strict=True)]

    bodies = [
        rigid_body(1, CUBE, 2, [1000, 1, 1000], [0, -0.5, 0], dynamic=False, restitution=0.5),
        rigid_body(2, CUBE, 0, [2.5, 0.4, 1], at([0, -0.1, 0.1]), dynamic=True, density=200,
                   friction=0.0),
    ]
    damper_offsets = [[1.75, -0.7, 0.5], [1.75, -0.7, -0.5], [-1.75, -0.7, 0.5],
                      [-1.75, -0.7, -0.5]]
    for k, offset in enumerate(damper_offsets):
        bodies.append(rigid_body(3 + k, CUBE, 0, [0.2, 0.1, 0.2], at(offset), dynamic=True,
                                 density=50000))
    bodies.append(rigid_body(7, CUBE, 0, [0.2, 0.1, 1], at([-1.75, -0.15, 0]), dynamic=True,
                             density=10000))
    wheel_offsets = [[1.75, -0.7, 0.9], [1.75, -0.7, -0.9], [-1.75, -0.7, 0.9],
                     [-1.75, -0.7, -0.9]]
    for k, offset in enumerate(wheel_offsets):
        bodies.append(rigid_body(8 + k, SPHERE, 1, [0.3, 0.3, 0.3], at(offset), dynamic=True,
                                 density=600, friction=0.4))
    motor_offsets = [[1.75, -0.7, 0.7], [1.75, -0.7, -0.7], [-1.75, -0.7, 0.7],
                     [-1.75, -0.7, -0.7]]
    return {
        "Name": "car_scene",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 5,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.01,
            "gravitation": [0, -9.81, 0],
        },
        "RigidBodies": bodies,
        "TargetAngleMotorHingeJoints": [{
            "bodyID1": 2, "bodyID2": 7, "position": at([-1.75, -0.4, 0]), "axis": [0, 1, 0],
            "targetSequence": [0, 0, 2, 0.707, 8, 0.707, 12, -0.707, 18, -0.707, 20, 0],
            "repeatSequence": True,
        }],
        "TargetVelocityMotorHingeJoints": [
            {"bodyID1": 3 + k, "bodyID2": 8 + k, "position": at(offset), "axis": [0, 0, 1],
             "target": 10.0}
            for k, offset in enumerate(motor_offsets)
        ],
        "DamperJoints": [
            {"bodyID1": first, "bodyID2": damper, "axis": [0, 1, 0], "stiffness": 500000.0}
            for first, damper in [(2, 3), (2, 4), (7, 5), (7, 6)]
        ],
    }


def cloth_collision_scene() -> Json:
    """The cloth collision demo: a 10 m FEM cloth pinned at two corners over a sphere, a spinning
    cylinder and a torus falling onto a box ground, analytic collision objects throughout."""
    return {
        "Name": "cloth_collision_scene",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 2,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.05,
            "clothSimulationMethod": 2,
            "clothBendingMethod": 2,
            "contactStiffnessRigidBody": 1.0,
            "contactStiffnessParticleRigidBody": 100.0,
        },
        "TriangleModels": [plane_cloth(0, [5, 8, 0], restitution=0.1, static_particles=[0, 49])],
        "RigidBodies": [
            rigid_body(1, CUBE, 2, [100, 1, 100], [0, 0, 0], dynamic=False, friction=0.0),
            rigid_body(2, SPHERE, 1, [1.5, 1.5, 1.5], [5, 6, 0], dynamic=True, density=200,
                       friction=0.2),
            rigid_body(3, CYLINDER, 3, [0.25, 3, 0.25], [6, 11, 3], dynamic=True, density=200,
                       friction=0.2, rotation_axis=[0, 0, 1], rotation_angle=1.5,
                       angular_velocity=[1, 0, 0]),
            rigid_body(4, TORUS, 4, [1.5, 1.5, 1.5], [5, 3, 0], dynamic=True, density=200,
                       friction=0.2, collision_scale=[1.5, 0.75, 1.5], rotation_axis=[0, 0, 1],
                       rotation_angle=0.25),
        ],
    }


def cloth_scene() -> Json:
    """The cloth demo of ClothScene.py (the generator's only scene without a JSON file in the
    original's data/scenes): a free 10 m FEM cloth of 50 x 50 particles falling onto a static
    analytic torus (collision scale 2 x 1) over a box ground, with the generator's parameters:
    5 substeps of 5 iterations, cloth_bendingStiffness 0.005 and the cloth keys' defaults. Its
    `gravity` key, which PositionBasedDynamics does not read, is left out (the demo runs with the
    default gravitation), and so are the keys clothSimulationMethod 2 does not use
    (`cloth_stiffness`, `cloth_normalizeStretch`, `cloth_normalizeShear`: the defaults)."""
    return {
        "Name": "cloth_scene",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 5,
            "maxIterations": 5,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.05,
            "clothSimulationMethod": 2,
            "clothBendingMethod": 2,
            "contactStiffnessRigidBody": 1.0,
            "contactStiffnessParticleRigidBody": 100.0,
            "cloth_bendingStiffness": 0.005,
            "cloth_xxStiffness": 1.0,
            "cloth_yyStiffness": 1.0,
            "cloth_xyStiffness": 1.0,
            "cloth_xyPoissonRatio": 0.3,
            "cloth_yxPoissonRatio": 0.3,
        },
        "TriangleModels": [plane_cloth(2, [0, 10, 0], restitution=0.2, static_particles=[])],
        "RigidBodies": [
            rigid_body(0, CUBE, 2, [100, 1, 100], [0, 0, 0], dynamic=False),
            rigid_body(1, TORUS, 4, [2, 2, 2], [0, 5, 0], dynamic=False, restitution=0.2,
                       friction=0.1, collision_scale=[2, 1, 2]),
        ],
    }


def pile_scene() -> Json:
    """The pile demo: eight bodies dropped onto a 5 x 5 field of static pins (analytic cylinders)
    on a box ground. The demo's two bunnies (grid read from a Discregrid .csdf) are tori here,
    their grid sdf/torus_8.csdf written by the original's Discregrid (README.md); its six
    armadillos (grids built from the mesh at the default 10^3 cells) are spheres. Its generator
    sets `maxIter` and `maxIterVel`, keys PositionBasedDynamics does not read: the demo runs with
    the defaults, written here."""
    bodies = [rigid_body(1, CUBE, 2, [500, 1, 500], [0, -0.5, 0], dynamic=False, restitution=0.5)]
    for row in range(5):
        for column in range(5):
            bodies.append(rigid_body(2 + 5 * row + column, CYLINDER, 3, [0.25, 10, 0.25],
                                     [-10.0 + 5 * column, 5.0, -10.0 + 5 * row], dynamic=False))
    # The demo's drop poses (its generator's random rotations, as it wrote them).
    drops: list[tuple[Vec, Vec, float]] = [
        ([-5.25, 20.0, -3.5], [0.13436424411240122, 0.8474337369372327, 0.763774618976614],
         0.801322977421273),
        ([1.75, 20.0, -3.5], [0.4494910647887381, 0.651592972722763, 0.7887233511355132],
         0.29486858827891005),
        ([-1.75, 20.0, 3.5], [0.8357651039198697, 0.43276706790505337, 0.762280082457942],
         0.006616361735917517),
        ([5.25, 20.0, 3.5], [0.7215400323407826, 0.22876222127045265, 0.9452706955539223],
         2.8319178785763612),
        ([-5.25, 27.0, -3.5], [0.0254458609934608, 0.5414124727934966, 0.9391491627785106],
         1.1975884326385855),
        ([1.75, 27.0, -3.5], [0.4221165755827173, 0.029040787574867943, 0.22169166627303505],
         1.3756644473107498),
        ([-1.75, 27.0, 3.5], [0.23308445025757263, 0.2308665415409843, 0.2187810373376886],
         1.443886871526072),
        ([5.25, 27.0, 3.5], [0.021489705265908876, 0.8375779756625729, 0.5564543226524334],
         2.0178272520307075),
    ]
    for k, (translation, axis, angle) in enumerate(drops):
        grid_file = k in (0, 2)  # the demo's bunnies
        body = rigid_body(27 + k, TORUS if grid_file else SPHERE, 5, [1, 1, 1], translation,
                          dynamic=True, density=300, friction=0.1, rotation_axis=axis,
                          rotation_angle=angle)
        if grid_file:
            body["collisionObjectFileName"] = "../sdf/torus_8.csdf"
        bodies.append(body)
    return {
        "Name": "pile_scene",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 5,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.01,
        },
        "RigidBodies": bodies,
    }


def stiff_rod_cantilever() -> Json:
    """A steel cantilever of ten segments on stiff-rod joints (the direct solver), released
    straight under gravity; one static segment at the root. The seed's stiff-rods demo gives a
    tree segment the mass properties of a solid cylinder of its `scale` (diameter, length,
    diameter; length along local y); pbdval takes them from the mesh, so `mass` and `inertia`
    (pbdval's extension keys, which the seed does not read) give it the same numbers, computed
    here in the demo's operation order."""
    width, length, density = 0.02, 0.1, 7800.0
    mass = math.pi / 4 * width * width * length * density
    across = 1.0 / 12.0 * mass * (3.0 * (0.25 * width * width) + length * length)
    along = 0.25 * mass * (0.25 * (width * width + width * width))
    bodies = []
    for k in range(11):
        body = rigid_body(1 + k, CYLINDER, 0, [width, length, width], [round(-0.05 + 0.1 * k, 10), 0, 0],
                          dynamic=k > 0, density=density, restitution=0.0, friction=0.2,
                          rotation_axis=[0, 0, 1], rotation_angle=-math.pi / 2)
        body["mass"] = mass
        body["inertia"] = [across, along, across]
        bodies.append(body)
    return {
        "Name": "stiff_rod_cantilever",
        "Simulation": {
            "timeStepSize": 0.001,
            "subSteps": 1,
            "maxIterations": 3,
            "maxIterationsV": 0,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.0,
        },
        "RigidBodies": bodies,
        "CosseratJoints": [
            {"bodyID1": 1 + k, "bodyID2": 2 + k, "id": 101 + k, "position": [round(0.1 * k, 10), 0, 0]}
            for k in range(10)
        ],
        "TreeModels": [{
            "id": 1, "rbIds": list(range(1, 12)), "jIds": list(range(101, 111)),
            "staticSegments": [1], "youngsModulus": 209e9, "torsionModulus": 79e9,
            "solverType": 12,
        }],
    }


def seed_cylinder_segment(body_id: int, width: float, length: float, density: float,
                          center: Vec, axis: Vec, angle: float, *, dynamic: bool) -> Json:
    """A stiff-rod tree segment of the seed's stiff-rods demo: `scale` (diameter, length,
    diameter), the length along local y, the demo's solid-cylinder mass properties given to
    pbdval as `mass` and `inertia` (computed in the demo's operation order), no collision."""
    mass = math.pi / 4 * width * width * length * density
    across = 1.0 / 12.0 * mass * (3.0 * (0.25 * width * width) + length * length)
    along = 0.25 * mass * (0.25 * (width * width + width * width))
    body = rigid_body(body_id, CYLINDER, 0, [width, length, width], center, dynamic=dynamic,
                      density=density, restitution=0.0, friction=0.2, rotation_axis=axis,
                      rotation_angle=angle)
    body["mass"] = mass
    body["inertia"] = [across, along, across]
    return body


def wilberforce_spring() -> Json:
    """The Wilberforce demo (a helical steel spring of stiff-rod segments carrying a heavy bob,
    which exchanges energy between bouncing and twisting), smaller: 40 segments (4 turns of 10)
    of 2 cm wire on a coil of radius 0.15 m and pitch 0.05 m, and a 0.2 m x 0.1 m steel
    cylinder hanging from its end; no collisions (the demo's segment grids come from its
    cylinder_unit_box.obj, not in the repository). The coil starts at the origin and descends."""
    per_turn, turns, coil, pitch, wire, steel = 10, 4, 0.15, 0.05, 0.02, 7800.0
    count = per_turn * turns
    points = []
    for i in range(count + 1):
        phi = 2 * math.pi * i / per_turn
        points.append([coil * math.cos(phi) - coil, -pitch * i / per_turn, coil * math.sin(phi)])
    bodies = []
    joints = []
    for k in range(count):
        a, b = points[k], points[k + 1]
        d = [b[j] - a[j] for j in range(3)]
        length = math.sqrt(sum(c * c for c in d))
        direction = [c / length for c in d]
        # The rotation taking local y onto the segment: axis y x d, angle acos(y . d).
        axis = [direction[2], 0.0, -direction[0]]
        axis_norm = math.sqrt(axis[0] ** 2 + axis[2] ** 2)
        axis = [c / axis_norm for c in axis]
        angle = math.acos(direction[1])
        center = [(a[j] + b[j]) / 2 for j in range(3)]
        bodies.append(seed_cylinder_segment(1 + k, wire, length, steel, center, axis, angle,
                                            dynamic=k > 0))
        if k > 0:
            joints.append({"bodyID1": k, "bodyID2": 1 + k, "id": 1000 + k, "position": a})
    bob_width, bob_length = 0.2, 0.1
    end = points[-1]
    bodies.append(seed_cylinder_segment(1 + count, bob_width, bob_length, steel,
                                        [end[0], end[1] - bob_length / 2, end[2]], [1, 0, 0],
                                        0.0, dynamic=True))
    joints.append({"bodyID1": count, "bodyID2": 1 + count, "id": 1000 + count, "position": end})
    return {
        "Name": "wilberforce_spring",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 1,
            "maxIterations": 3,
            "maxIterationsV": 0,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.0,
        },
        "RigidBodies": bodies,
        "CosseratJoints": joints,
        "TreeModels": [{
            "id": 1, "rbIds": list(range(1, count + 2)),
            "jIds": [j["id"] for j in joints], "staticSegments": [1],
            "youngsModulus": 209e9, "torsionModulus": 79e9, "solverType": 12,
        }],
    }


def cosserat_helix() -> Json:
    """The Cosserat rods demo: a helix of 50 particles (radius 0.5 m, 5 turns over 5 m, axis
    turned to x) clamped at its first particle and segment, the seed's PBD rod with its default
    rod_* fractions, particles and quaternions of mass 1. The points are written out (the
    demo's parametrisation, which pbdval's `helix` generator does not share)."""
    count, radius, height, total_angle = 50, 0.5, -5.0, 10.0 * math.pi
    c, s = math.cos(-0.5 * math.pi), math.sin(-0.5 * math.pi)  # rotation about y
    points = []
    for i in range(count):
        angle = total_angle / count * i
        x, y, z = radius * math.cos(angle), radius * math.sin(angle), height / count * i
        points.append([c * x + s * z, y, -s * x + c * z])
    return {
        "Name": "cosserat_helix",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 5,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
        },
        "LineModels": [{"id": 0, "points": points, "staticParticles": [0],
                        "staticSegments": [0]}],
    }


def deformable_solid_collision_scene() -> Json:
    """The deformable solid collision demo: a PBD FEM solid (the demo's armadillo, a tet mesh
    not in the repository, is cases/models' 3 x 3 x 3-cell tet cube of side 2 m here (copied
    without its comment lines, which the seed's TetGen reader does not skip), its
    visual mesh the cube) falling onto a box ground, hit by a sphere and a spinning cylinder,
    over a torus. Its tet model is a type-5 collision object as in the demo (the grid only marks
    it as a distance-field object; particle-tet contacts use the tet mesh). The demo's keys the
    seed does not read (`tetModelSimulationMethod`, `maxIter`, `maxIterVel`) are left out: it
    runs with the defaults."""
    return {
        "Name": "deformable_solid_collision_scene",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 5,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.05,
            "solidSimulationMethod": 2,
            "solid_poissonRatio": 0.2,
            "contactStiffnessRigidBody": 1.0,
            "contactStiffnessParticleRigidBody": 100.0,
        },
        "TetModels": [{
            "id": 0,
            "nodeFile": "../models/tet_cube.node",
            "eleFile": "../models/tet_cube.ele",
            "visFile": CUBE,
            "translation": [0, 8, 0],
            "rotationAxis": [1, 0, 0],
            "rotationAngle": 1.57,
            "scale": [2, 2, 2],
            "restitution": 0.1,
            "friction": 0.1,
            "collisionObjectType": 5,
            "testMesh": True,
        }],
        "RigidBodies": [
            rigid_body(1, CUBE, 2, [100, 1, 100], [0, 0, 0], dynamic=False, friction=0.0),
            rigid_body(2, SPHERE, 1, [1.5, 1.5, 1.5], [0.5, 12.8, 0], dynamic=True, density=200,
                       friction=0.2),
            rigid_body(3, CYLINDER, 3, [0.5, 3, 0.5], [-0.5, 15, 3], dynamic=True, density=200,
                       friction=0.2, rotation_axis=[0, 0, 1], rotation_angle=1.5,
                       angular_velocity=[1, 0, 0]),
            rigid_body(4, TORUS, 4, [2.5, 2.5, 2.5], [0.0, 4.5, 1.0], dynamic=True, density=200,
                       friction=0.2, collision_scale=[2.5, 1.25, 2.5]),
        ],
    }


def armadillo_collision_scene() -> Json:
    """The armadillo collision demo: three PBD FEM solids dropped onto each other and a box
    ground (particle-tet contacts between the solids). The demo's armadillo tet mesh is not in
    the repository: the tet cube of deformable_solid_collision_scene stands in for it. The
    demo's resolutionSDF 20^3 of the grid of the visual mesh is left at the default (the grid
    marks the model as a distance-field object; recorded with 20^3, the original's particles
    are the same bit for bit up to 1.1 s and then differ by 10^-15 m, past the scene's
    horizon)."""
    poses: list[tuple[Vec, Vec, float, float]] = [
        ([0, 10, 0], [0, 1, 0], 1.57, 0.1),
        ([0, 4, 0], [0, 0, 1], 0.1, 0.0),
        ([0, 18, 0], [0, 0, 1], 0.5, 0.0),
    ]
    models = []
    for k, (translation, axis, angle, restitution) in enumerate(poses):
        models.append({
            "id": min(k, 1),  # as the demo, whose last two models share id 1
            "nodeFile": "../models/tet_cube.node",
            "eleFile": "../models/tet_cube.ele",
            "visFile": CUBE,
            "translation": translation,
            "rotationAxis": axis,
            "rotationAngle": angle,
            "scale": [2, 2, 2],
            "restitution": restitution,
            "friction": 0.3,
            "collisionObjectType": 5,
            "testMesh": True,
        })
    return {
        "Name": "armadillo_collision_scene",
        "Simulation": {
            "timeStepSize": 0.01,
            "subSteps": 5,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.0,
            "solid_poissonRatio": 0.2,
            "contactStiffnessRigidBody": 1.0,
            "contactStiffnessParticleRigidBody": 100.0,
        },
        "TetModels": models,
        "RigidBodies": [
            rigid_body(2, CUBE, 2, [100, 1, 100], [0, 0, 0], dynamic=False, friction=0.0),
        ],
    }


def cloth_on_bunny() -> Json:
    """The cloth-on-bunny demo (ClothOnBunny.json): a free 10 m FEM cloth of 50 x 50 particles
    falling onto a dynamic body with a grid collision object on a box ground. The demo's bunny
    (bunny_10k.obj, not in the repository) is cases/models' torus here, scale 4, its grid built
    from the mesh at 20^3 cells (the demo's 40^3 on the bunny; 20^3 keeps the original's grid
    build short), lying 0.1 m above the ground. The demo's keys PositionBasedDynamics does not
    read (`triangleModelSimulationMethod`, `triangleModelBendingMethod`, `maxIterVel`) are left
    out: it runs with the defaults (methods 2 and 2, 5 velocity iterations); the keys it reads
    and that differ from the defaults are written (`cloth_bendingStiffness` 0.1)."""
    cloth_on_torus = rigid_body(2, TORUS, 5, [4, 4, 4], [5, 2.2, 0], dynamic=True, density=500,
                                friction=0.2)
    cloth_on_torus["resolutionSDF"] = [20, 20, 20]
    return {
        "Name": "cloth_on_bunny",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 2,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "contactTolerance": 0.1,
            "clothSimulationMethod": 2,
            "clothBendingMethod": 2,
            "cloth_bendingStiffness": 0.1,
            "contactStiffnessRigidBody": 1.0,
            "contactStiffnessParticleRigidBody": 100.0,
        },
        "TriangleModels": [plane_cloth(0, [5, 8, 0], restitution=0.1)],
        "RigidBodies": [
            rigid_body(1, CUBE, 2, [100, 1, 100], [0, 0, 0], dynamic=False, friction=0.0),
            cloth_on_torus,
        ],
    }


def fluid_dam_break_seed() -> Json:
    """The fluid demo's breaking dam, smaller: a block of 6 x 10 x 4 particles (x, y, z) in the
    demo's container for that block (width (6 + 1) 10 r, depth (4 + 1) 2 r), 1 m high instead
    of the demo's 4 m. Particles and walls are computed with the demo's own expressions
    (createBreakingDam, initBoundaryData: Python floats are IEEE doubles evaluated in the same
    order), so both programs start from the same numbers; the walls are given as the demo's
    addWall boxes (`boundaryWalls`), the particles listed. The seed formulation of pbdval's
    fluid (`formulation` "seed"), one substep of the demo's 5 ms (its CFL cap; the driver checks
    that the demo's CFL rule keeps it)."""
    width, height, depth, container_height = 6, 10, 4, 1.0
    radius = 0.025
    container_width = (width + 1) * radius * (2.0 * 5.0)
    container_depth = (depth + 1) * radius * 2.0
    diam = 2.0 * radius
    start = [-0.5 * container_width + diam, diam, -0.5 * container_depth + diam]
    particles = [[diam * i + start[0], diam * j + start[1], diam * k + start[2]]
                 for i in range(width) for j in range(height) for k in range(depth)]
    x1, x2 = -container_width / 2.0, container_width / 2.0
    y1, y2 = 0.0, container_height
    z1, z2 = -container_depth / 2.0, container_depth / 2.0
    walls = [([x1, y1, z1], [x2, y1, z2]),  # floor
             ([x1, y2, z1], [x2, y2, z2]),  # top
             ([x1, y1, z1], [x1, y2, z2]),  # left
             ([x2, y1, z1], [x2, y2, z2]),  # right
             ([x1, y1, z1], [x2, y2, z1]),  # back
             ([x1, y1, z2], [x2, y2, z2])]  # front
    return {
        "Name": "fluid_dam_break_seed",
        "Simulation": {
            "timeStepSize": 0.005,
            "subSteps": 1,
            "maxIterations": 1,
            "maxIterationsV": 5,
            "velocityUpdateMethod": 0,
            "gravitation": [0, -9.81, 0],
        },
        "FluidModels": [{
            "formulation": "seed",
            "particleRadius": radius,
            "density0": 1000,
            "viscosity": 0.02,
            "iterations": 5,
            "particles": particles,
            "boundaryWalls": [{"min": low, "max": high} for low, high in walls],
        }],
    }


def plane_obj(count: int) -> str:
    """A count x count grid of vertices over [-0.5, 0.5]² in the xz plane, two triangles per
    cell (vertex index i + count j is at x = i/(count-1) - 0.5, z = j/(count-1) - 0.5)."""
    lines = [
        f"# {count} x {count} vertices over [-0.5, 0.5]^2, xz plane"
        + " (pbdval seed_reference test data, make_demo_scenes.py)"
    ]
    for j in range(count):
        for i in range(count):
            lines.append(f"v {i / (count - 1) - 0.5:.17g} 0 {j / (count - 1) - 0.5:.17g}")
    for j in range(count - 1):
        for i in range(count - 1):
            a = 1 + i + count * j  # OBJ indices start at 1
            lines.append(f"f {a} {a + count} {a + 1}")
            lines.append(f"f {a + 1} {a + count} {a + count + 1}")
    return "\n".join(lines) + "\n"


def without_comments(path: Path) -> str:
    """The file's text without its `#` comment lines (the seed's TetGen reader reads none)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    return "\n".join(line for line in lines if not line.startswith("#")) + "\n"


def main() -> None:
    write_atomically(HERE / "models" / "plane_50x50.obj", plane_obj(50))
    for suffix in ("node", "ele"):
        source = HERE.parents[2] / "cases" / "models" / f"tet_cube.{suffix}"
        write_atomically(HERE / "models" / f"tet_cube.{suffix}", without_comments(source))
    for name, scene in [("car_scene", car_scene()),
                        ("cloth_collision_scene", cloth_collision_scene()),
                        ("cloth_scene", cloth_scene()),
                        ("pile_scene", pile_scene()),
                        ("stiff_rod_cantilever", stiff_rod_cantilever()),
                        ("cosserat_helix", cosserat_helix()),
                        ("deformable_solid_collision_scene", deformable_solid_collision_scene()),
                        ("armadillo_collision_scene", armadillo_collision_scene()),
                        ("wilberforce_spring", wilberforce_spring()),
                        ("cloth_on_bunny", cloth_on_bunny()),
                        ("fluid_dam_break_seed", fluid_dam_break_seed())]:
        write_atomically(HERE / "scenes" / f"{name}.json", json.dumps(scene, indent=2) + "\n")


if __name__ == "__main__":
    main()
