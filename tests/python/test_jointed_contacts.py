"""Jointed bodies collide with each other in the external engines too, as in the seed (its
collision detection tests every pair of collision objects). The scene is the one the built-in
engines are held to (tests/adapters/test_jointed_contacts.cpp): cases/contact_jointed_bodies.json,
a 0.5 x 0.05 x 0.05 m link hinged 5 cm above the 1.2 x 0.1 x 0.1 m beam it is jointed to,
falling from horizontal onto it; once a static beam, once a dynamic beam hinged at its centre
(a parent-child pair in MuJoCo's tree). Measured: how deep the link's corners go below the
beam's top face, in the beam's frame. A box-box contact pushes a corner out through the nearer
face, so a working contact keeps every corner above the beam's mid-plane; without the contact
the link swings through the beam (the control, with the shapes removed)."""

from __future__ import annotations

import itertools
import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_engines import MUJOCO, PYBULLET, assert_ok, trajectory

from pbdval import protocol as pp

CASE = "contact_jointed_bodies"
ENGINES = [(PYBULLET, "pybullet.si"), (PYBULLET, "pybullet.pgs"), (PYBULLET, "pybullet.dantzig"),
           (MUJOCO, "mujoco-python.euler.newton"), (MUJOCO, "mujoco-python.implicit.newton"),
           (MUJOCO, "mujoco-python.rk4.newton"),
           # reduced coordinates: the dynamic beam is the link's parent in one multibody
           (PYBULLET, "pybullet.multibody.si"), (PYBULLET, "pybullet.multibody.dantzig")]

Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]


@dataclass(frozen=True)
class LinkOnBeam:
    beam: pp.Body
    link: pp.Body


def half_extents(body: pp.Body) -> pp.Vec3:
    """The half extents of a box body (the links and beams of these cases are boxes)."""
    assert body.shape.half_extents is not None, f"{body.json_path}: not a box"
    return body.shape.half_extents


def links_on_beams(scene: pp.ResolvedScene) -> list[LinkOnBeam]:
    """Each hinge of the case between two bodies with collision shapes."""
    return [LinkOnBeam(scene.body_by_id(j.body1), scene.body_by_id(j.body2))  # type: ignore[arg-type]
            for j in scene.joints if scene.body_by_id(j.body1).shape.type != "none"]  # type: ignore[arg-type]


def rotation_matrices(rows: np.ndarray) -> np.ndarray:
    """Each row's quaternion (columns 4-7: w, x, y, z) as a 3 x 3 rotation matrix."""
    w, x, y, z = rows[:, 4], rows[:, 5], rows[:, 6], rows[:, 7]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)],
        axis=-2)


def scene_frames(body: pp.Body, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per sample: the body's scene-frame origin and rotation (rows give the centre of mass)."""
    rotation = rotation_matrices(rows)
    origin = rows[:, 1:4] - rotation @ np.array(body.principal_com)
    return origin, rotation


def deepest_corner(l: LinkOnBeam, rows: dict[int, np.ndarray]) -> float:
    """How far the link's deepest corner went below the beam's top face (negative: above it),
    over the corners above the beam's footprint, in the beam's frame."""
    beam_origin, beam_rotation = scene_frames(l.beam, rows[l.beam.id])
    link_origin, link_rotation = scene_frames(l.link, rows[l.link.id])
    half = np.array(half_extents(l.beam))
    deepest = -np.inf
    for signs in itertools.product((-1.0, 1.0), repeat=3):
        corner = link_origin + link_rotation @ (np.array(signs) * half_extents(l.link))
        local = np.einsum("nji,nj->ni", beam_rotation, corner - beam_origin)
        above = (np.abs(local[:, 0]) <= half[0]) & (np.abs(local[:, 2]) <= half[2])
        if above.any():
            deepest = max(deepest, float(np.max(half[1] - local[above, 1])))
    return deepest


def deepest_corners(scene_path: Path, run_engine: Run, engine: str,
                    links: list[LinkOnBeam]) -> list[float]:
    status, out = run_engine(engine, scene_path)
    assert_ok(status)
    rows = trajectory(out)
    return [deepest_corner(l, rows) for l in links]


def initial_gap(l: LinkOnBeam) -> float:
    """The gap between the link's bottom face and the beam's top face at t = 0."""
    return ((l.link.position[1] - half_extents(l.link)[1])
            - (l.beam.position[1] + half_extents(l.beam)[1]))


@pytest.mark.parametrize("engine,method", ENGINES)
def test_a_link_falling_onto_the_beam_it_is_jointed_to_is_stopped_by_their_contact(
        export_scene: Export, run_engine: Run, engine: str, method: str) -> None:
    scene_path = export_scene(CASE, method=method)
    links = links_on_beams(pp.read_resolved_scene(scene_path))
    assert len(links) == 2  # a static and a dynamic beam
    for depth, l in zip(deepest_corners(scene_path, run_engine, engine, links), links):
        # The contact keeps every corner above the beam's mid-plane (the module's bound)...
        assert depth < half_extents(l.beam)[1], (l.link.json_path, depth)
        # ...and the link did reach the beam: closer than half the initial 2.5 cm gap.
        assert depth > -initial_gap(l) / 2, (l.link.json_path, depth)


@pytest.mark.parametrize("engine,method", [ENGINES[0], ENGINES[3], ENGINES[6]])
def test_without_collision_shapes_the_link_swings_through_the_beam(
        export_scene: Export, run_engine: Run, engine: str, method: str) -> None:
    """The control: the bound above fails for an engine that drops the jointed pairs' contacts."""
    scene_path = export_scene(CASE, method=method)
    links = links_on_beams(pp.read_resolved_scene(scene_path))
    document = json.loads(scene_path.read_text())
    document["contactPairs"] = []
    for body in document["bodies"]:
        body["shape"] = {"collisionObjectType": 0, "type": "none"}
    scene_path.write_text(json.dumps(document))
    for depth, l in zip(deepest_corners(scene_path, run_engine, engine, links), links):
        assert depth > 2 * half_extents(l.beam)[1], (l.link.json_path, depth)


@pytest.mark.parametrize("engine,method", [ENGINES[0], ENGINES[3], ENGINES[6]])
def test_the_run_records_that_jointed_bodies_collide(export_scene: Export, run_engine: Run,
                                                      engine: str, method: str) -> None:
    status, _ = run_engine(engine, export_scene(CASE, method=method, duration=0.01))
    assert_ok(status)
    assert str(status["effectiveSettings"]["jointedBodiesCollide"]).startswith("yes (as in the seed): 2 ")
