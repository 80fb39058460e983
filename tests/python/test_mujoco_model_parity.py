"""One model description for both MuJoCo versions (docs/external-engines.md#one-model-description):
the built-in engine's MJCF (adapters/mujoco/mjcf_writer.cpp, through pbdval._core._mujoco_mjcf)
compiled by MuJoCo 2.2.2 (pbdval._core._mujoco_2_2_2_model: every size, option and numeric array
of its mjModel, by mjxmacro.h's names) and, with the rewrites of MJCF_2_2_2_TO_4, by MuJoCo 4.0.0
(the mujoco module), for every case of the library. The models are compared field by field:
every field of 2.2.2's model is compared with 4.0.0's field of the same name, unless this file
names why not (a field 4.0.0 removed, renamed or encodes differently); so a difference a future
version brings fails here.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

from conftest import REPO
from pbdval import _core
from pbdval import protocol as pp
from pbdval.external.mujoco import engine

CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))
#: Cases whose rigid part the writer cannot map, with the reason it names.
UNSUPPORTED = {
    "contact_sphere_pile": "hollow box (collisionObjectType 7)",
    "joint_rigid_body_particle_ball": "RigidBodyParticleBallJoints[0]",
    "stiff_rod_cantilever": "stiff-rod joints",
    "stiff_rod_helix": "stiff-rod joints",
}

# --- tolerances ----------------------------------------------------------------------------------
#: Reals the MJCF gives or the compiler gets from them in a few operations (quaternion and axis
#: normalisation, frame composition, subtree sums): relative to the field's largest magnitude
#: (at least 1). Measured at most 4.4e-16 (2 epsilon); 1e-14 covers sums of up to ~45 terms.
GIVEN = 1e-14
#: Reals derived from the inverse of the joint-space inertia at qpos0 (MuJoCo's constraint
#: scaling): relative. Their round-off grows with the condition number of M; measured 1.6e-10 on
#: chain_100 (100 links, cond(M) ~ 1e6), 1e-14 on the short chains.
DERIVED = 1e-9
DERIVED_FIELDS = {"body_invweight0", "dof_invweight0", "dof_M0", "tendon_invweight0",
                  "actuator_acc0"}
#: Fields of meshes (and the geoms placed on them), in m: the compiler moves a mesh to its centre
#: of mass, found by volume integration over its faces, summed in another order by each version.
#: Measured 4.3e-12 m on contact_pile's 2000-face pins; 1e-10 m is 1e-8 of their size.
MESH = 1e-10
MESH_FIELDS = {"mesh_vert", "geom_pos", "geom_quat", "geom_aabb"}
#: Compared by meaning when the model has meshes: a mesh's frame is its principal frame, which is
#: not unique when two principal moments are equal (a torus about its axis; seen once its float
#: coordinates, as the seed reads OBJ files, break the symmetry at 1e-8): each version may turn
#: it differently about that axis. What must agree is where the mesh's vertices are in their
#: body, R(geom_quat) mesh_vert + geom_pos (mesh_in_bodies), and every other geom's pose.
MESH_FRAME_FIELDS = {"mesh_vert", "geom_quat"}
#: A mesh geom's size (its half extents along its principal axes) and bounding radius follow from
#: its vertices in that frame, so they carry the frame's ambiguity: measured 1.6e-9 and 2.5e-10 m
#: on the minitaur's leg meshes (robot_minitaur_drop), whose vertices agree in their bodies. Those
#: rows are covered by mesh_in_bodies; the other geoms' rows are compared as given.
MESH_EXTENT_FIELDS = {"geom_size", "geom_rbound"}
MJ_GEOM_MESH = 7

# --- what is not compared by name, and why ----------------------------------------------------
#: Fields of MuJoCo 2.2.2 with no field of that name in 4.0.0.
REMOVED_OR_RENAMED = {
    "nmeshtexvert": "texture coordinates are indexed per face in MuJoCo 3 (nmeshtexcoord)",
    "nstack": "the stack is part of the arena in MuJoCo 3 (narena)",
    "opt.apirate": "the remote API's rate was removed in MuJoCo 3",
    "opt.collision": "removed in MuJoCo 3 (MJCF_2_2_2_TO_4)",
    "opt.mpr_tolerance": "libccd's MPR; MuJoCo 3's opt.ccd_tolerance, not written, has the same default 1e-6",
    "opt.mpr_iterations": "libccd's MPR (50); MuJoCo 3's opt.ccd_iterations, not written, belongs to its own "
                          "convex collision (default 35)",
    "light_directional": "a light type in MuJoCo 3 (light_type); no lights here",
    "tex_rgb": "tex_data in MuJoCo 3; no textures here",
    "eq_active": "eq_active0 in MuJoCo 3 (compared below)",
}
#: Fields compared by meaning below (their encoding changed).
BY_MEANING = {"opt.disableflags", "opt.enableflags", "eq_data", "tendon_lengthspring",
              "pair_signature"}
#: Fields that are not part of the model's physics and differ by design.
NOT_COMPARED = {
    "njmax": "2.2.2's constraint buffer; not written for 4.0.0 (MJCF_2_2_2_TO_4)",
    "nconmax": "2.2.2's contact buffer; not written for 4.0.0 (MJCF_2_2_2_TO_4)",
    "nbuffer": "the size of mjModel's own memory block",
    "body_sameframe": "compiler shortcut flags, with more kinds in MuJoCo 3 (the frames are compared)",
    "geom_sameframe": "compiler shortcut flags, with more kinds in MuJoCo 3 (the frames are compared)",
    "site_sameframe": "compiler shortcut flags, with more kinds in MuJoCo 3 (the frames are compared)",
    "body_simple": "compiler shortcut flags, with more kinds in MuJoCo 3 (the joints are compared)",
    "nmeshgraph": "MuJoCo 3 stores the convex hull it computes at compile time; 2.2.2 computed it when colliding",
    "mesh_graphadr": "as nmeshgraph",
    "mesh_graph": "as nmeshgraph",
    "mesh_normal": "vertex normals for rendering, averaged differently",
}
#: Disable flags of 2.2.2 and their MuJoCo 4 names (2.2.2's `passive` is 4's `spring` + `damper`).
DISABLE_2_2_2 = {"constraint": ["CONSTRAINT"], "equality": ["EQUALITY"],
                 "frictionloss": ["FRICTIONLOSS"], "limit": ["LIMIT"], "contact": ["CONTACT"],
                 "passive": ["SPRING", "DAMPER"], "gravity": ["GRAVITY"], "clampctrl": ["CLAMPCTRL"],
                 "warmstart": ["WARMSTART"], "filterparent": ["FILTERPARENT"],
                 "actuation": ["ACTUATION"], "refsafe": ["REFSAFE"], "sensor": ["SENSOR"]}
#: Enable flags of 2.2.2 (bit order of its mjmodel.h); multiccd became a disable flag in 4.
ENABLE_2_2_2 = ["OVERRIDE", "ENERGY", "FWDINV", "SENSORNOISE", "MULTICCD"]


def resolved(export_scene: Callable[..., Path], case: str) -> pp.ResolvedScene:
    return pp.read_resolved_scene(export_scene(case, method="mujoco-python.euler.newton"))


def writer_model(scene: pp.ResolvedScene) -> dict[str, Any]:
    settings = engine.writer_settings("euler", "newton", engine.parameter_reader(scene, "euler"),
                                       scene.time_step_size)
    return engine.rigid_model(scene, settings)


def flag_names(bits: int, names: list[list[str]]) -> set[str]:
    return {n for i, group in enumerate(names) if bits >> i & 1 for n in group}


def compare(old: dict[str, np.ndarray], new: Any) -> list[str]:
    """The differences between 2.2.2's fields `old` and the 4.0.0 model `new`, one line each."""
    problems: list[str] = []
    has_mesh = int(old["nmesh"][0, 0]) > 0
    for name, a in old.items():
        if name in NOT_COMPARED or name in BY_MEANING or (has_mesh and name in MESH_FRAME_FIELDS):
            continue
        holder, key = (new.opt, name[4:]) if name.startswith("opt.") else (new, name)
        if not hasattr(holder, key):
            if name not in REMOVED_OR_RENAMED:
                problems.append(f"{name}: not in MuJoCo {mujoco.__version__}")
            continue
        b = np.asarray(getattr(holder, key))
        if b.size != a.size:
            problems.append(f"{name}: {a.shape} numbers in 2.2.2, {b.shape} in {mujoco.__version__}")
            continue
        b = b.reshape(a.shape)
        if has_mesh and name in MESH_EXTENT_FIELDS:
            primitive = old["geom_type"].ravel() != MJ_GEOM_MESH
            a, b = a.reshape(len(primitive), -1)[primitive], b.reshape(len(primitive), -1)[primitive]
        if np.array_equal(a, b):
            continue
        if a.dtype.kind == "i":  # ids, addresses, counts, types, flags: exactly
            problems.append(f"{name}: {a.ravel().tolist()} in 2.2.2, {b.ravel().tolist()} in 4")
            continue
        if name in MESH_FIELDS and has_mesh:
            bound = MESH
        elif name in DERIVED_FIELDS:
            bound = DERIVED * float(np.max(np.abs(a)))
        else:
            bound = GIVEN * max(1.0, float(np.max(np.abs(a))))
        difference = float(np.max(np.abs(a - b)))
        if not difference <= bound:
            problems.append(f"{name}: differs by {difference:.3g} (bound {bound:.3g})")
    if has_mesh:
        problems += compare_mesh_placement(old, new)
    return problems + compare_by_meaning(old, new)


def rotate(quaternion: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Each row of `vectors` turned by the unit quaternion (w, x, y, z)."""
    w, u = float(quaternion[0]), np.asarray(quaternion[1:], dtype=float)
    t = 2.0 * np.cross(u, vectors)
    return vectors + w * t + np.cross(u, t)


def mesh_in_bodies(geom_type: np.ndarray, dataid: np.ndarray, quat: np.ndarray, pos: np.ndarray,
                   vertadr: np.ndarray, vertnum: np.ndarray, vert: np.ndarray) -> list[np.ndarray]:
    """Per geom: a mesh geom's vertices in its body's frame; any other geom's quaternion."""
    placed = []
    for g in range(len(geom_type)):
        if int(geom_type[g]) == MJ_GEOM_MESH:
            m = int(dataid[g])
            vertices = vert[int(vertadr[m]):int(vertadr[m]) + int(vertnum[m])]
            placed.append(rotate(quat[g], vertices) + pos[g])
        else:
            placed.append(quat[g])
    return placed


def compare_mesh_placement(old: dict[str, np.ndarray], new: Any) -> list[str]:
    """MESH_FRAME_FIELDS by meaning: every mesh's vertices where its body holds them, every other
    geom's orientation, both to MESH."""
    def arrays(m: Any, get: Callable[[str], np.ndarray]) -> list[np.ndarray]:
        return mesh_in_bodies(get("geom_type").ravel(), get("geom_dataid").ravel(),
                              get("geom_quat").reshape(-1, 4), get("geom_pos").reshape(-1, 3),
                              get("mesh_vertadr").ravel(), get("mesh_vertnum").ravel(),
                              get("mesh_vert").reshape(-1, 3))
    before = arrays(old, lambda name: np.asarray(old[name]))
    after = arrays(new, lambda name: np.asarray(getattr(new, name)))
    problems = []
    for g, (a, b) in enumerate(zip(before, after, strict=True)):
        difference = float(np.max(np.abs(a - b))) if a.shape == b.shape else math.inf
        if not difference <= MESH:
            problems.append(f"geom {g}: mesh vertices in the body (or orientation) differ by "
                            f"{difference:.3g} (bound {MESH:.3g})")
    return problems


def compare_by_meaning(old: dict[str, np.ndarray], new: Any) -> list[str]:
    """BY_MEANING and the renamed fields: flags by name, the data of equality constraints in
    2.2.2's columns (4.0.0 added one, which must be 0 here), a tendon's spring length as 4.0.0's
    dead band [l, l], each pair's bodies, eq_active as eq_active0."""
    problems: list[str] = []
    known = {n for group in DISABLE_2_2_2.values() for n in group}
    disable_old = flag_names(int(old["opt.disableflags"][0, 0]), list(DISABLE_2_2_2.values()))
    disable_new = {n for n in known if new.opt.disableflags & int(getattr(mujoco.mjtDisableBit, f"mjDSBL_{n}"))}
    if disable_old != disable_new:
        problems.append(f"opt.disableflags: {sorted(disable_old)} in 2.2.2, {sorted(disable_new)} in 4")
    enable_old = flag_names(int(old["opt.enableflags"][0, 0]), [[n] for n in ENABLE_2_2_2])
    enable_new = {n for n in ("OVERRIDE", "ENERGY", "FWDINV")
                  if new.opt.enableflags & int(getattr(mujoco.mjtEnableBit, f"mjENBL_{n}"))}
    if not new.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_MULTICCD):
        enable_new.add("MULTICCD")
    if enable_old != enable_new:
        problems.append(f"opt.enableflags: {sorted(enable_old)} in 2.2.2, {sorted(enable_new)} in 4")
    data_old = old["eq_data"]
    data_new = np.asarray(new.eq_data).reshape(len(data_old), mujoco.mjNEQDATA)
    common = data_old.shape[1]
    bound = GIVEN * max(1.0, float(np.abs(data_old).max(initial=0.0)))
    if np.any(np.abs(data_old - data_new[:, :common]) > bound) or np.any(data_new[:, common:]):
        problems.append(f"eq_data: {data_old.tolist()} in 2.2.2, {data_new.tolist()} in 4")
    spring_old = old["tendon_lengthspring"][:, 0]
    spring_new = np.asarray(new.tendon_lengthspring).reshape(-1, 2)
    if not (np.array_equal(spring_new[:, 0], spring_old) and np.array_equal(spring_new[:, 1], spring_old)):
        problems.append(f"tendon_lengthspring: {spring_old.tolist()} in 2.2.2, {spring_new.tolist()} in 4")
    # A pair's signature packs its two bodies: (b1 + 1) << 16 | (b2 + 1) in 2.2.2, b1 << 16 | b2 in 4.
    bodies = old["geom_bodyid"][:, 0]
    for i, (g1, g2) in enumerate(zip(old["pair_geom1"][:, 0], old["pair_geom2"][:, 0])):
        signature_old, signature_new = int(old["pair_signature"][i, 0]), int(new.pair_signature[i])
        pair_old = {(signature_old >> 16) - 1, (signature_old & 0xFFFF) - 1}
        pair_new = {signature_new >> 16, signature_new & 0xFFFF}
        if not pair_old == pair_new == {int(bodies[g1]), int(bodies[g2])}:
            problems.append(f"pair {i}: signatures name bodies {pair_old} in 2.2.2, {pair_new} in 4")
    if not np.array_equal(old["eq_active"][:, 0], np.asarray(new.eq_active0, dtype=np.int64)):
        problems.append("eq_active differs from eq_active0")
    return problems


@pytest.mark.parametrize("case", CASES)
def test_mujoco_2_2_2_and_4_compile_the_same_model_of_every_case(
        export_scene: Callable[..., Path], case: str) -> None:
    scene = resolved(export_scene, case)
    model = writer_model(scene)
    if case in UNSUPPORTED:
        assert any(UNSUPPORTED[case] in reason for reason in model["unsupported"]), model["unsupported"]
        return
    assert model["unsupported"] == []
    old = _core._mujoco_2_2_2_model(model["xml"])
    new = mujoco.MjSpec.from_string(engine.mjcf_for_mujoco_4(model["xml"])).compile()
    assert compare(old, new) == []
    # The scene's bodies are the models' (beyond the world): nothing was dropped on either side.
    assert int(old["nbody"][0, 0]) == new.nbody == len(scene.bodies) + 1


def test_every_rewrite_of_the_mjcf_is_needed_by_mujoco_4(export_scene: Callable[..., Path]) -> None:
    # MuJoCo 4.0.0's schema rejects the attributes the first two rewrites take out; the size
    # block it accepts, but it would cap the constraint rows at 2.2.2's buffer.
    xml = writer_model(resolved(export_scene, "joint_distance"))["xml"]
    rewrites = engine.MJCF_2_2_2_TO_4
    for left_out in range(2):
        text = xml
        for k, (pattern, replacement, _) in enumerate(rewrites):
            if k != left_out:
                text = re.sub(pattern, replacement, text)
        with pytest.raises(ValueError, match="unrecognized attribute"):
            mujoco.MjSpec.from_string(text)
    text = xml
    for pattern, replacement, _ in rewrites[:2]:
        text = re.sub(pattern, replacement, text)
    assert mujoco.MjSpec.from_string(text).compile().njmax > 0
    assert mujoco.MjSpec.from_string(engine.mjcf_for_mujoco_4(xml)).compile().njmax == -1


def test_a_changed_writer_that_the_rewrites_no_longer_match_is_an_error() -> None:
    with pytest.raises(RuntimeError, match="MJCF_2_2_2_TO_4"):
        engine.mjcf_for_mujoco_4("<mujoco/>")


def test_the_model_is_the_documents_even_when_it_is_not_its_source_files(
        export_scene: Callable[..., Path]) -> None:
    # The writer reads the resolved scene, not the scene file it came from: a document edited
    # after export (as tests and users do) is modelled as edited.
    path = export_scene("joint_hinge", method="mujoco-python.euler.newton")
    document = json.loads(path.read_text())
    moving = next(i for i, b in enumerate(document["bodies"]) if b["mass"] > 0)
    document["bodies"][moving]["mass"] *= 2
    edited = mujoco.MjSpec.from_string(engine.mjcf_for_mujoco_4(
        writer_model(pp.parse_resolved_scene(document))["xml"])).compile()
    original = mujoco.MjSpec.from_string(engine.mjcf_for_mujoco_4(
        writer_model(pp.read_resolved_scene(path))["xml"])).compile()
    body = mujoco.mj_name2id(original, mujoco.mjtObj.mjOBJ_BODY, f"b{moving}")  # the writer's name
    assert edited.body_mass[body] == 2 * original.body_mass[body]


def test_a_core_module_of_another_build_is_named_not_a_bare_attribute_error(
        export_scene: Callable[..., Path], monkeypatch: pytest.MonkeyPatch) -> None:
    # The engine needs this build's pbdval._core; one from another checkout (the venv's path
    # file may name one) lacks the writer's entry point: the run's error says so.
    scene = resolved(export_scene, "joint_hinge")
    monkeypatch.delattr(_core, "_mujoco_mjcf")
    with pytest.raises(RuntimeError, match="another build's pbdval._core"):
        writer_model(scene)
