"""pbdval import (python/pbdval/import_model.py, docs/models.md): URDF and MJCF robots as scenes.

The mass properties are checked against the models' own numbers and closed forms; the round
trips run the imported scene in pybullet's reduced coordinates and in MuJoCo 4 and compare it
with the original file loaded by the same engine."""

from __future__ import annotations

import json
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pybullet as pb
import pybullet_data  # type: ignore[import-untyped]
import pytest
from test_engines import assert_ok, trajectory

from conftest import REPO, VENV_PYTHON, engine_environment
from pbdval.import_model import ImportModelError, import_model, principal_frame, rpy_matrix

EPSILON = float(np.finfo(float).eps)
PYBULLET_DATA = Path(pybullet_data.getDataPath())
SUITE = Path(mujoco.__file__).parents[1] / "dm_control" / "suite"


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def link(name: str, mass: float, inertia: str, origin: str = "", collision: str = "") -> str:
    return (f'<link name="{name}"><inertial>{origin}<mass value="{mass}"/><inertia {inertia}/></inertial>'
            f"{collision}</link>")


# --- mass properties --------------------------------------------------------------------------

def test_a_rotated_inertial_frame_gives_its_moments_and_axes_exactly(tmp_path: Path) -> None:
    """An inertial origin rotated by rpy with a diagonal tensor diag(1, 2, 3): the principal
    moments are 1, 2, 3 and the principal axes the rotated frame's (independent of the eigen
    solver: the frame is built here from the closed-form rpy matrix)."""
    rpy = [0.3, -0.7, 1.1]
    urdf = write(tmp_path, "r.urdf", '<robot name="r">' + link(
        "a", 2.0, 'ixx="1" iyy="2" izz="3" ixy="0" ixz="0" iyz="0"',
        f'<origin xyz="0.1 0.2 0.3" rpy="{rpy[0]} {rpy[1]} {rpy[2]}"/>') + "</robot>")
    result = import_model(urdf)
    body = result.bodies[0]
    assert body.mass == 2.0
    # eigh's eigenvalues carry a backward error of a few epsilon of the largest moment (3)
    assert np.allclose(sorted(body.moments), [1, 2, 3], rtol=0, atol=16 * EPSILON * 3)
    expected = rpy_matrix(rpy)
    for k, moment in enumerate(body.moments):
        column = expected[:, round(moment) - 1]
        # eigenvectors of well-separated eigenvalues (gap 1) to a few epsilon: 16 epsilon
        assert abs(abs(float(column @ body.rotation[:, k])) - 1) <= 16 * EPSILON
    assert np.allclose(body.com, [0.1, 0.2, 0.3], rtol=0, atol=4 * EPSILON)
    entry = result.scene["RigidBodies"][0]
    assert entry["mass"] == 2.0 and np.allclose(entry["inertia"], body.moments, rtol=0, atol=0)


def test_a_full_tensor_is_reconstructed_from_its_principal_frame() -> None:
    """R diag(moments) Rᵀ gives the tensor back to round-off, with R a proper rotation."""
    tensor = np.array([[0.5, 0.01, -0.02], [0.01, 0.4, 0.03], [-0.02, 0.03, 0.3]])
    moments, axes = principal_frame(tensor)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=8 * EPSILON)
    # the reconstruction is backward stable: a few epsilon of the tensor's norm
    assert np.max(np.abs(axes @ np.diag(moments) @ axes.T - tensor)) <= 16 * EPSILON * 0.5


def test_two_boxes_welded_by_a_fixed_joint_have_the_inertia_of_the_box_they_form(tmp_path: Path) -> None:
    """Two 1 kg boxes 0.2 x 0.1 x 0.1 m side by side along x form one 2 kg box 0.4 x 0.1 x 0.1
    m: I = m/12 (b² + c²) etc. (closed form), reached only through the parallel axis theorem."""
    def box_inertia(m: float, a: float, b: float, c: float) -> str:
        return (f'ixx="{m / 12 * (b * b + c * c)!r}" iyy="{m / 12 * (a * a + c * c)!r}" '
                f'izz="{m / 12 * (a * a + b * b)!r}" ixy="0" ixz="0" iyz="0"')

    text = ('<robot name="w">' + link("a", 1.0, box_inertia(1, 0.2, 0.1, 0.1))
            + link("b", 1.0, box_inertia(1, 0.2, 0.1, 0.1))
            + '<joint name="weld" type="fixed"><parent link="a"/><child link="b"/>'
            '<origin xyz="0.2 0 0"/></joint></robot>')
    result = import_model(write(tmp_path, "w.urdf", text))
    assert len(result.bodies) == 1 and result.bodies[0].links == ["a", "b"]
    body = result.bodies[0]
    expected = sorted([2 / 12 * 0.02, 2 / 12 * (0.16 + 0.01), 2 / 12 * (0.16 + 0.01)])
    # sums of a few products of numbers of order 0.03: a few epsilon of the largest
    assert np.allclose(sorted(body.moments), expected, rtol=0, atol=32 * EPSILON * 0.03)
    assert np.allclose(body.com, [0.1, 0, 0], rtol=0, atol=4 * EPSILON)
    assert any("merged" in note for note in result.notes)


def test_mjcf_bodies_keep_the_compiled_models_masses_and_principal_moments() -> None:
    """acrobot.xml compiled by MuJoCo: each imported body has the model's body_mass and its
    body_inertia (principal moments, diagonalised by MuJoCo) to the eigen solver's round-off."""
    model = mujoco.MjModel.from_xml_path(str(SUITE / "acrobot.xml"))
    result = import_model(SUITE / "acrobot.xml")
    for name in ("upper_arm", "lower_arm"):
        b = model.body(name).id
        body = result.bodies[result.body_of_link[name]]
        assert body.mass == pytest.approx(float(model.body_mass[b]), rel=4 * EPSILON)
        scale = float(np.max(model.body_inertia[b]))
        assert np.allclose(sorted(body.moments), sorted(model.body_inertia[b]), rtol=0, atol=64 * EPSILON * scale)


def test_inertia_from_collision_gives_a_boxs_centre_and_closed_form_inertia(tmp_path: Path) -> None:
    """A 2 kg link whose file says 1 kg m² everywhere, with a 0.4 x 0.2 x 0.1 m collision box centred
    at (0, 0, 0.1): with --inertia-from-collision its centre of mass is the box's centre and its
    moments m/12 (b² + c²), ... (closed form), and it becomes the seed's box."""
    urdf = write(tmp_path, "b.urdf", '<robot name="b">' + link(
        "a", 2.0, 'ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"',
        collision='<collision><origin xyz="0 0 0.1"/><geometry><box size="0.4 0.2 0.1"/></geometry></collision>')
        + "</robot>")
    result = import_model(urdf, inertia_from_collision=True)
    body = result.bodies[0]
    assert np.allclose(body.com, [0, 0, 0.1], rtol=0, atol=1e-15)  # the mean of 8 corners: round-off
    expected = sorted([2 / 12 * (0.04 + 0.01), 2 / 12 * (0.16 + 0.01), 2 / 12 * (0.16 + 0.04)])
    # trimesh integrates the 12 triangles: a few epsilon of the largest moment
    assert np.allclose(sorted(body.moments), expected, rtol=0, atol=64 * EPSILON * 0.04)
    assert result.scene["RigidBodies"][0]["collisionObjectType"] == 2
    assert result.scene["RigidBodies"][0]["collisionObjectScale"] == [0.4, 0.2, 0.1]


def test_a_mesh_is_the_geometry_only_when_its_centroid_is_the_centre_of_mass(tmp_path: Path) -> None:
    """Two boxes symmetric about the centre of mass: one mesh, the body's geometryFile. One box off
    the centre of mass: its SDF only, noted (the format puts the centre of mass at the geometry's
    centroid)."""
    inertia = 'ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"'
    box = '<collision><origin xyz="{} 0 0"/><geometry><box size="0.1 0.1 0.1"/></geometry></collision>'
    pair = write(tmp_path, "pair.urdf", '<robot name="p">' + link(
        "a", 1.0, inertia, collision=box.format(0.3) + box.format(-0.3)) + "</robot>")
    entry = import_model(pair, tmp_path / "pair.json").scene["RigidBodies"][0]
    assert entry["collisionObjectType"] == 5 and "geometryFile" in entry
    off = write(tmp_path, "off.urdf", '<robot name="o">' + link("a", 1.0, inertia, collision=box.format(0.3))
                + "</robot>")
    result = import_model(off, tmp_path / "off.json")
    entry = result.scene["RigidBodies"][0]
    assert entry["collisionObjectType"] == 5 and "geometryFile" not in entry and "collisionObjectFileName" in entry
    assert any("is not its centre of mass" in note for note in result.notes)


def test_an_unknown_collision_link_or_start_joint_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ImportModelError, match=r"pendulum5.urdf: --collision-links: no link named 'nope'"):
        import_model(PYBULLET_DATA / "pendulum5.urdf", collision_links={"nope"})
    with pytest.raises(ImportModelError, match=r"acrobot.xml: --joint nope: no hinge or slider joint"):
        import_model(SUITE / "acrobot.xml", positions={"nope": 1.0})


# --- joints and notes -------------------------------------------------------------------------

def test_pendulum5_maps_its_continuous_joints_to_hinges_and_lists_what_it_drops() -> None:
    result = import_model(PYBULLET_DATA / "pendulum5.urdf")
    scene = result.scene
    assert len(scene["HingeJoints"]) == 5
    assert [b["isDynamic"] for b in scene["RigidBodies"]] == [False] + [True] * 5
    # the spheres sit at their links' centres of mass: the seed's sphere, not a mesh
    assert all(b["collisionObjectType"] == 1 for b in scene["RigidBodies"][1:])
    notes = scene["Validation"]["notes"]
    assert sum("damping 1.0 dropped" in n for n in notes) == 5
    assert sum("friction 1.0 dropped" in n for n in notes) == 5


def test_the_cartpoles_limits_damping_and_actuator_are_listed_not_dropped_silently() -> None:
    notes = import_model(SUITE / "cartpole.xml").notes
    assert any("slider" in n and "range" in n for n in notes)
    assert any("damping" in n and "hinge_1" in n for n in notes)
    assert any("actuator 'slide'" in n for n in notes)


# --- bad input --------------------------------------------------------------------------------

@pytest.mark.parametrize(("text", "expected"), [
    ("<robot name='x'><link name='a'/>", "not well-formed XML"),
    ("<model/>", "expected a <robot> root element"),
    (("<robot name='x'><link name='a'/><joint name='j' type='revolute'><parent link='a'/>"
     "<child link='nope'/></joint></robot>"), "joint 'j'/child: no link named 'nope'"),
    (("<robot name='x'><link name='a'/><link name='b'/><joint name='j' type='planar'><parent link='a'/>"
     "<child link='b'/></joint></robot>"), "joint 'j': type 'planar'"),
    ("<robot name='x'><link name='a'><inertial><mass value='abc'/></inertial></link></robot>",
     "link 'a'/inertial/mass: attribute value=\"abc\""),
    (("<robot name='x'><link name='a'><collision><geometry><mesh filename='m.dae'/></geometry></collision>"
     "</link></robot>"), "m.dae: cannot be read"),
    (("<robot name='x'><link name='a'/><link name='b'/><joint name='j' type='revolute'><parent link='a'/>"
     "<child link='b'/></joint></robot>"), "'b': mass 0.0 kg is outside"),
])
def test_bad_urdf_is_refused_naming_the_file_and_the_element(tmp_path: Path, text: str, expected: str) -> None:
    (tmp_path / "m.dae").write_text("<COLLADA/>")
    path = write(tmp_path, "bad.urdf", text)
    with pytest.raises(ImportModelError) as error:
        import_model(path)
    assert str(path) in str(error.value) and expected in str(error.value), str(error.value)


def test_a_collada_mesh_reads_the_vertices_and_triangles_it_was_written_with(tmp_path: Path) -> None:
    # A box written as COLLADA by trimesh's exporter (through pycollada), read back by the
    # importer's mesh reader: the same 8 corners, scaled, and 12 triangles. Tolerance: the
    # exporter writes coordinates as decimal text of float32 values, exact for these halves.
    import trimesh

    from pbdval.import_model import read_mesh

    box = trimesh.creation.box(extents=[1.0, 2.0, 3.0])
    (tmp_path / "box.dae").write_bytes(trimesh.exchange.dae.export_collada(box))
    scale = np.array([2.0, 1.0, 0.5])
    vertices, faces = read_mesh(tmp_path / "box.dae", scale, "link 'a'/collision[0]")
    assert faces.shape == (12, 3)
    expected = np.asarray(box.vertices) * scale
    assert np.array_equal(np.unique(vertices, axis=0), np.unique(expected, axis=0))


def test_a_body_with_three_joints_is_refused_naming_them() -> None:
    with pytest.raises(ImportModelError, match=r"body 'torso': 3 joints \('rootz' \(slider\)"):
        import_model(SUITE / "walker.xml")


def test_a_bad_mjcf_is_refused_with_mujocos_message(tmp_path: Path) -> None:
    path = write(tmp_path, "bad.xml", "<mujoco><worldbody><body><geom type='sphere'/></body></worldbody>"
                 "<bogus/></mujoco>")
    with pytest.raises(ImportModelError, match=r"bad.xml: MuJoCo cannot compile it: .*bogus"):
        import_model(path)


# --- the command ------------------------------------------------------------------------------

def test_pbdval_import_writes_a_scene_the_library_loads(pbdval_binary: Path, tmp_path: Path) -> None:
    out = tmp_path / "kuka.json"
    done = subprocess.run([str(pbdval_binary), "import", str(PYBULLET_DATA / "kuka_iiwa/model.urdf"),
                           "--out", str(out), "--fixed-base"], capture_output=True, text=True, check=False,
                          env=engine_environment())
    assert done.returncode == 0, done.stderr
    assert "note:" in done.stdout
    loaded = subprocess.run([str(pbdval_binary), "export-scene", str(out), "--quiet"], capture_output=True,
                            text=True, check=False)
    assert loaded.returncode == 0, loaded.stderr
    resolved = json.loads(loaded.stdout)
    assert len(resolved["bodies"]) == 8 and len(resolved["joints"]) == 7


def test_pbdval_import_names_the_file_of_a_bad_model(pbdval_binary: Path, tmp_path: Path) -> None:
    path = write(tmp_path, "m.txt", "")
    done = subprocess.run([str(pbdval_binary), "import", str(path)], capture_output=True, text=True, check=False,
                          env=engine_environment())
    assert done.returncode == 1 and f"{path}: expected a URDF (.urdf) or MJCF (.xml) file" in done.stderr


# --- round trips --------------------------------------------------------------------------------

def resolved(pbdval_binary: Path, scene: Path, method: str, duration: float, folder: Path) -> Path:
    done = subprocess.run([str(pbdval_binary), "export-scene", str(scene), "--quiet", "--duration", repr(duration),
                           "--sample-interval", "0.01"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    document: dict[str, Any] = json.loads(done.stdout)
    document["method"] = {"name": method, "parameters": {}}
    path = folder / f"{scene.stem}.resolved.json"
    path.write_text(json.dumps(document))
    return path


def without_joint_dynamics(urdf: Path, folder: Path) -> Path:
    """A copy of the URDF without what the scene drops and loadURDF would apply: the joints'
    `<dynamics>` (damping, friction; the damping acts even after changeDynamics(jointDamping=0):
    pendulum5's five damping="1.0" move a link by 4.9 cm in 0.5 s) and their limits (loadURDF
    makes limit constraints of a revolute joint's lower and upper: the copy's are continuous).
    Mesh paths are made absolute."""
    tree = ET.parse(urdf)
    for joint in tree.getroot().iter("joint"):
        for dynamics in joint.findall("dynamics"):
            joint.remove(dynamics)
        if joint.get("type") == "revolute":
            joint.set("type", "continuous")
    for mesh in tree.getroot().iter("mesh"):
        mesh.set("filename", str(urdf.parent / mesh.get("filename", "")))
    copy = folder / urdf.name
    tree.write(copy)
    return copy


def pybullet_reference(urdf: Path, steps: int, h: float, sample_every: int,
                       positions: dict[str, float]) -> list[np.ndarray]:
    """The URDF in pybullet (loadURDF, fixed base, the file's inertia), stepped as
    pybullet.multibody.si steps: no damping, joint motors off, no speed clamp; the joints
    `positions` moved from zero. Rows per sample: every link's centre of mass."""
    c = pb.connect(pb.DIRECT)
    try:
        pb.setGravity(0, 0, -9.81, physicsClientId=c)
        pb.setPhysicsEngineParameter(fixedTimeStep=h, numSubSteps=0, physicsClientId=c)
        body = pb.loadURDF(str(urdf), useFixedBase=True, flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=c)
        count = pb.getNumJoints(body, physicsClientId=c)
        for k in range(count):
            pb.changeDynamics(body, k, linearDamping=0.0, angularDamping=0.0, jointDamping=0.0,
                              maxJointVelocity=1e30, physicsClientId=c)
            pb.setJointMotorControl2(body, k, pb.VELOCITY_CONTROL, force=0, physicsClientId=c)
            name = pb.getJointInfo(body, k, physicsClientId=c)[1].decode()
            if name in positions:
                pb.resetJointState(body, k, positions[name], 0.0, physicsClientId=c)
        samples = []
        for step in range(steps + 1):
            if step % sample_every == 0:
                samples.append(np.array([pb.getLinkState(body, k, computeForwardKinematics=1,
                                                         physicsClientId=c)[0] for k in range(count)]))
            if step < steps:
                pb.stepSimulation(physicsClientId=c)
        return samples
    finally:
        pb.disconnect(c)


#: Start positions: pendulum5 starts horizontal at zero; the arm stands upright there, so it starts bent.
URDF_STARTS: dict[str, dict[str, float]] = {
    "pendulum5.urdf": {}, "kuka_iiwa/model.urdf": {"lbr_iiwa_joint_2": 0.8, "lbr_iiwa_joint_4": -1.0}}


@pytest.mark.parametrize("model", sorted(URDF_STARTS))
def test_a_urdf_imported_runs_in_pybullet_as_its_original_file(model: str, pbdval_binary: Path, tmp_path: Path,
                                                              run_engine: Any) -> None:
    urdf = PYBULLET_DATA / model
    scene = tmp_path / "scene.json"
    result = import_model(urdf, scene, fixed_base=True, collisions=False, positions=URDF_STARTS[model])
    h, duration = result.scene["Simulation"]["timeStepSize"], 0.5
    status, out = run_engine("pybullet", resolved(pbdval_binary, scene, "pybullet.multibody.si", duration, tmp_path))
    assert_ok(status)
    rows = trajectory(out)
    steps, every = round(duration / h), round(0.01 / h)
    reference = pybullet_reference(without_joint_dynamics(urdf, tmp_path), steps, h, every, URDF_STARTS[model])
    c = pb.connect(pb.DIRECT)
    names = [pb.getJointInfo(pb.loadURDF(str(urdf), physicsClientId=c), k, physicsClientId=c)[12].decode()
             for k in range(len(reference[0]))]
    pb.disconnect(c)
    worst, travel = 0.0, 0.0
    for k, name in enumerate(names):
        body = result.body_of_link[name]
        ours = rows[body][:, 1:4]
        theirs = np.array([sample[k] for sample in reference])
        assert len(ours) == len(theirs)
        worst = max(worst, float(np.max(np.abs(ours - theirs))))
        travel = max(travel, float(np.max(np.abs(theirs - theirs[0]))))
    assert travel > 0.01  # the links move: the comparison is not of two resting models
    # Both runs integrate the same multibody (Featherstone, semi-implicit Euler) from inertias and
    # frames that differ only by the importer's eigen decomposition and frame composition (≈ 1e-16
    # relative): measured 1.3e-15 m after 100 steps; 1e-12 m leaves a thousandfold room for
    # round-off growth and none for a modelling difference (the dropped joint damping of
    # pendulum5 alone moves a link by 4.9 cm).
    assert worst <= 1e-12, worst


def mujoco_reference(xml: Path, h: float, steps: int, sample_every: int, names: list[str],
                     positions: dict[str, float]) -> list[np.ndarray]:
    """The original MJCF in MuJoCo 4 with what the scene drops switched off (damping, armature,
    friction loss, stiffness, actuators idle), semi-implicit Euler at step h, started with the
    joints `positions` moved from qpos0."""
    m = mujoco.MjModel.from_xml_path(str(xml))
    m.dof_damping[:] = 0
    m.dof_armature[:] = 0
    m.dof_frictionloss[:] = 0
    m.jnt_stiffness[:] = 0
    m.opt.timestep = h
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    d = mujoco.MjData(m)
    for name, value in positions.items():
        d.qpos[m.jnt_qposadr[m.joint(name).id]] += value
    ids = [m.body(n).id for n in names]
    samples = []
    for step in range(steps + 1):
        if step % sample_every == 0:
            mujoco.mj_forward(m, d)
            samples.append(np.array([d.xipos[i] for i in ids]))
        if step < steps:
            mujoco.mj_step(m, d)
    return samples


#: A body on two perpendicular hinges through one point, base fixed: the seed's universal joint.
UNIVERSAL = """<mujoco model="universal"><worldbody>
  <body name="a" pos="0 0 1"><joint name="u1" axis="1 0 0"/><joint name="u2" axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 -0.4" size="0.05"/></body></worldbody></mujoco>"""
#: A body on three mutually perpendicular hinges through one point: the seed's ball joint.
THREE_HINGES = """<mujoco model="three_hinges"><worldbody>
  <body name="a" pos="0 0 1"><joint name="b1" axis="1 0 0"/><joint name="b2" axis="0 1 0"/>
    <joint name="b3" axis="0 0 1"/><geom type="box" size="0.1 0.05 0.2" pos="0.05 0.02 -0.2"/></body>
  </worldbody></mujoco>"""
def mujoco_round_trip(xml: Path, positions: dict[str, float], h: float, duration: float, pbdval_binary: Path,
                      folder: Path, run_engine: Any) -> tuple[float, float]:
    """The imported scene in mujoco-python.euler.newton against the original file in MuJoCo 4, both at
    step h: the largest distance between a body's centres of mass, and the largest travel."""
    scene = folder / f"{xml.stem}-{h}.json"
    result = import_model(xml, scene, positions=positions)
    scene_document = json.loads(scene.read_text())
    scene_document["Simulation"]["timeStepSize"] = h
    scene.write_text(json.dumps(scene_document))
    status, out = run_engine("mujoco-python",
                             resolved(pbdval_binary, scene, "mujoco-python.euler.newton", duration, folder))
    assert_ok(status)
    rows = trajectory(out)
    names = list(result.body_of_link)
    reference = mujoco_reference(xml, h, round(duration / h), round(0.01 / h), names, positions)
    worst, travel = 0.0, 0.0
    for k, name in enumerate(names):
        ours = rows[result.body_of_link[name]][:, 1:4]
        theirs = np.array([sample[k] for sample in reference])
        worst = max(worst, float(np.max(np.abs(ours - theirs))))
        travel = max(travel, float(np.max(np.abs(theirs - theirs[0]))))
    return worst, travel


#: Start positions away from the models' equilibria (acrobot and cartpole stand upright at qpos0).
MJCF_STARTS = {"acrobot.xml": {"shoulder": 0.4, "elbow": 0.3}, "cartpole.xml": {"hinge_1": 0.3},
               "universal.xml": {"u1": 0.3, "u2": 0.2}}


@pytest.mark.parametrize("model", sorted(MJCF_STARTS))
def test_an_mjcf_imported_runs_in_mujoco_as_its_original_file(model: str, pbdval_binary: Path, tmp_path: Path,
                                                             run_engine: Any) -> None:
    xml = SUITE / model if model != "universal.xml" else write(tmp_path, model, UNIVERSAL)
    worst, travel = mujoco_round_trip(xml, MJCF_STARTS[model], 0.002, 0.5, pbdval_binary, tmp_path, run_engine)
    assert travel > 0.01  # the bodies move: the comparison is not of two resting models
    # The same tree in the same integrator, from body frames that differ by the principal-frame
    # conversion (≈ 1e-16 relative): measured 1.3e-15 m after 250 steps; 1e-12 m leaves a
    # thousandfold room for round-off growth and no room for any modelling difference (a 1e-6
    # relative error in one inertia moves these links by ≈ 1e-7 m in 0.5 s).
    assert worst <= 1e-12, worst


def test_three_hinges_imported_as_a_ball_joint_move_as_in_mujoco_to_first_order(pbdval_binary: Path,
                                                                               tmp_path: Path,
                                                                               run_engine: Any) -> None:
    """A ball joint (a quaternion) and three hinges (Euler angles) are the same continuous motion
    integrated in different coordinates: semi-implicit Euler separates them by O(h), not
    round-off. Halving h halves the difference (measured 8.8e-6 and 4.3e-6 m at 2 and 1 ms over
    0.1 s, a ratio of 2.03); a modelling difference would not shrink with h."""
    xml = write(tmp_path, "three_hinges.xml", THREE_HINGES)
    positions = {"b1": 0.4, "b3": 0.5}
    coarse, travel = mujoco_round_trip(xml, positions, 0.002, 0.1, pbdval_binary, tmp_path, run_engine)
    fine, _ = mujoco_round_trip(xml, positions, 0.001, 0.1, pbdval_binary, tmp_path, run_engine)
    assert travel > 0.01, travel
    # first order: the ratio is 2 up to the O(h) term's own variation with h (measured 2.03)
    assert 1.7 <= coarse / fine <= 2.3, (coarse, fine)


# --- every model ------------------------------------------------------------------------------

def test_every_pybullet_urdf_and_suite_model_imports_or_is_refused_by_name() -> None:
    """The sweep docs/models.md tabulates: each model gives a scene or an ImportModelError naming
    the model's file; nothing else escapes."""
    done = subprocess.run([str(VENV_PYTHON), "-m", "pbdval.import_model_sweep", "--check",
                           str(REPO / "docs/models.md")], capture_output=True, text=True, check=False,
                          cwd=REPO, env={"PYTHONPATH": str(REPO / "python"), "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_robot_cases_are_the_import_of_their_models() -> None:
    """cases/robot_*.json and their meshes are what python -m pbdval.import_model_cases generates."""
    done = subprocess.run([str(VENV_PYTHON), "-m", "pbdval.import_model_cases", "--check"], capture_output=True,
                          text=True, check=False, cwd=REPO, env={"PYTHONPATH": str(REPO / "python"),
                                                                 "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr


def test_pbdval_import_refuses_to_overwrite_its_model(pbdval_binary: Path, tmp_path: Path) -> None:
    model = tmp_path / "r.urdf"
    model.write_text('<robot name="r">' + link("a", 1.0, 'ixx="1" iyy="1" izz="1"') + "</robot>")
    (tmp_path / "link.urdf").symlink_to(model)
    for out in (model, tmp_path / "link.urdf"):
        done = subprocess.run([str(pbdval_binary), "import", str(model), "--out", str(out)], capture_output=True,
                              text=True, check=False, env=engine_environment())
        assert done.returncode == 2 and "is the model" in done.stderr, done.stderr
    assert model.read_text().startswith('<robot name="r">')
