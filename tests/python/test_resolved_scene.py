"""`pbdval export-scene`: every case exports to a resolved scene that validates against
docs/schemas/resolved-scene.schema.json, and whose derived numbers agree with an independent
computation from the same document and the raw case file."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import pytest

from conftest import REPO
from pbdval import protocol as pp

CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))
SCHEMA = json.loads((REPO / "docs" / "schemas" / "resolved-scene.schema.json").read_text())
#: Every derived number is a few double operations from the scene's: round-off only.
ROUND_OFF = 1e-12


def export(binary: Path, case: str, *extra: str) -> dict[str, Any]:
    result = subprocess.run([str(binary), "export-scene", str(REPO / "cases" / f"{case}.json"),
                             "--quiet", *extra], capture_output=True, text=True, cwd=REPO, check=False)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def test_there_are_cases() -> None:
    assert len(CASES) >= 20


def test_the_schema_is_a_valid_draft_2020_12_schema() -> None:
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("case", CASES)
def test_case_exports_to_a_valid_resolved_scene(pbdval_binary: Path, case: str) -> None:
    document = export(pbdval_binary, case)
    jsonschema.Draft202012Validator(SCHEMA).validate(document)
    scene = pp.parse_resolved_scene(document, case)  # and the engines' reader accepts it
    raw = json.loads((REPO / "cases" / f"{case}.json").read_text())
    assert [b.id for b in scene.bodies] == [b["id"] for b in raw.get("RigidBodies", [])]
    assert scene.steps == max(1, round(scene.duration / scene.time_step_size))
    check_frames(scene)
    check_joint_coordinates(scene)
    check_contact_pairs(scene, raw)


def rot(q: Any) -> np.ndarray:
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def check_frames(scene: pp.ResolvedScene) -> None:
    for b in scene.bodies:
        scale = 1 + np.linalg.norm(b.scene_origin)
        # the centre of mass is the scene frame's origin plus the rotated offset
        com = np.array(b.scene_origin) + rot(b.rotation) @ np.array(b.principal_com)
        assert np.allclose(com, b.position, atol=ROUND_OFF * scale), b.json_path
        # principal → world is scene → world after principal → scene
        assert np.allclose(rot(b.rotation) @ rot(b.principal_rotation), rot(b.world_principal_rotation),
                           atol=ROUND_OFF * 10), b.json_path
        for q in (b.rotation, b.principal_rotation, b.world_principal_rotation):
            assert abs(np.linalg.norm(q) - 1) < ROUND_OFF and q[0] >= 0


def check_joint_coordinates(scene: pp.ResolvedScene) -> None:
    for j in scene.joints:
        for side, body_id in (("body1", j.body1), ("body2", j.body2)):
            if body_id is None:
                continue
            b = scene.body_by_id(body_id)
            for name, point in j.points.items():
                c = getattr(point, side)
                assert c is not None, f"{j.json_path}.{name}.{side}"
                world = np.array(b.scene_origin) + rot(b.rotation) @ np.array(c.scene)
                assert np.allclose(world, point.world, atol=ROUND_OFF * 10), f"{j.json_path}.{name}"
                world = np.array(b.position) + rot(b.world_principal_rotation) @ np.array(c.principal)
                assert np.allclose(world, point.world, atol=ROUND_OFF * 10), f"{j.json_path}.{name}"
            for name, axis in j.axes.items():
                c = getattr(axis, side)
                assert np.allclose(rot(b.rotation) @ np.array(c.scene), axis.world, atol=ROUND_OFF * 10)
                assert np.allclose(rot(b.world_principal_rotation) @ np.array(c.principal), axis.world,
                                   atol=ROUND_OFF * 10)


def check_contact_pairs(scene: pp.ResolvedScene, raw: dict[str, Any]) -> None:
    explicit = {}
    for entry in raw.get("ContactPairs", []):
        explicit[frozenset((entry["bodyID1"], entry["bodyID2"]))] = entry
    rule = scene.contact_combine_rule
    shaped = [b for b in scene.bodies if b.shape.type != "none"]
    expected_pairs = {frozenset((a.id, b.id)) for i, a in enumerate(shaped) for b in shaped[i + 1:]
                      if a.dynamic or b.dynamic}
    assert {frozenset(p.bodies) for p in scene.contact_pairs} == expected_pairs
    for p in scene.contact_pairs:
        a, b = (scene.body_by_id(i).material for i in p.bodies)
        combined = {  # pbd/model/scene.h: the seed's rule is e_a e_b and mu_a + mu_b
            "seed": (a.friction + b.friction, a.restitution * b.restitution),
            "product": (a.friction * b.friction, a.restitution * b.restitution),
            "average": ((a.friction + b.friction) / 2, (a.restitution + b.restitution) / 2),
            "min": (min(a.friction, b.friction), min(a.restitution, b.restitution)),
            "max": (max(a.friction, b.friction), max(a.restitution, b.restitution)),
        }[rule]
        entry = explicit.get(frozenset(p.bodies))
        friction = entry["friction"] if entry and "friction" in entry else combined[0]
        restitution = entry["restitution"] if entry and "restitution" in entry else combined[1]
        assert p.explicit == (entry is not None)
        assert p.friction == pytest.approx(friction, rel=ROUND_OFF, abs=ROUND_OFF)
        assert p.restitution == pytest.approx(restitution, rel=ROUND_OFF, abs=ROUND_OFF)


def test_export_to_a_file_equals_standard_output(pbdval_binary: Path, tmp_path: Path) -> None:
    out = tmp_path / "hinge.resolved.json"
    result = subprocess.run([str(pbdval_binary), "export-scene", "cases/joint_hinge.json", "--out", str(out),
                             "--method", "pybullet.si", "--duration", "0.5", "--quiet"],
                            capture_output=True, text=True, cwd=REPO, check=False)
    assert result.returncode == 0, result.stderr
    document = json.loads(out.read_text())
    # --method fills in the method's parameters at their defaults, typed, as the runner passes
    # them: the catalogue's declarations.
    catalogue = json.loads((REPO / "engines" / "pybullet.json").read_text())
    declared = next(m for m in catalogue["methods"] if m["name"] == "pybullet.si")["parameters"]
    assert document["method"] == {"name": "pybullet.si",
                                  "parameters": {p["name"]: p["default"] for p in declared}}
    assert document["duration"] == 0.5 and document["steps"] == 100  # 0.5 s / 5 ms
    assert document == {**export(pbdval_binary, "joint_hinge", "--method", "pybullet.si",
                                 "--duration", "0.5"), "method": document["method"]}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hinge.resolved.json"]


def test_export_of_a_missing_file_names_it(pbdval_binary: Path) -> None:
    result = subprocess.run([str(pbdval_binary), "export-scene", "cases/no_such_case.json"],
                            capture_output=True, text=True, cwd=REPO, check=False)
    assert result.returncode == 2
    assert "no_such_case.json" in result.stderr and result.stdout == ""


def test_export_rejects_a_bad_duration(pbdval_binary: Path) -> None:
    result = subprocess.run([str(pbdval_binary), "export-scene", "cases/projectile.json",
                             "--duration", "-1"], capture_output=True, text=True, cwd=REPO, check=False)
    assert result.returncode == 2 and "duration" in result.stderr
