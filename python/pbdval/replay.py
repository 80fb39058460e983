"""The 3D replay of a case in the report (docs/report.md#3d-replay).

Every ok run's trajectory, downsampled to at most `MAX_FRAMES` frames (and at most
`MAX_BODY_FRAMES` frames × dynamic bodies × runs per case, so a 100-link chain stays small), is
written with the bodies' shapes into `replay/CASE.js`, a classic script that sets
`window.PBDVAL_REPLAY` (a page opened from the disk may not fetch JSON, but may load scripts).
The viewer, `web/replay.js`, draws it with three.js (bundled from npm into the report's
`assets/`): one colour per engine/method, static bodies grey, play, pause, speed and a time
scrubber; between frames it interpolates positions linearly and rotations by slerp.

Deformables are replayed from the particles each run read back (ENGINE-METHOD.particles.*):
cloth (triangle models) and solids (the boundary faces of tet models) as surfaces, rods (line
models) as polylines through their particles, fluids as points, every run in its colour, with
the same slider; at most `MAX_PARTICLE_FRAMES` frames × particles × runs. A run that cannot be
replayed (it did not complete, or read no particles back in a scene of particles) is named in
`notes` with the reason, and so is a case where no run can be.

Arrays are little-endian float32 (positions, quaternions, times, mesh vertices) and uint32
(triangles), base64-encoded. A body is drawn from its geometry file (the OBJ, times its
`scale`) when it has one, else from its collision shape (box, sphere, cylinder; others as a
small sphere); vertex v of the scene frame is at x_com + R (v − c) in the world, with x_com
and R the trajectory's centre of mass and scene-frame rotation and c the centre of mass in the
scene frame (`principalFrame.centerOfMass` of the resolved scene).
"""

from __future__ import annotations

import base64
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pbdval.api import Scene, Trajectory

#: Frames of a replay at most (a 5 s case at 48 frames per second).
MAX_FRAMES = 240
#: frames × dynamic bodies × runs per case at most: about 1.1 MB of data per case.
MAX_BODY_FRAMES = 30_000
#: frames × particles × runs per case at most: about 2.4 MB of particle data per case.
MAX_PARTICLE_FRAMES = 150_000
#: Triangles of one mesh at most (the case library's largest, sphere.obj, has 1280).
MAX_TRIANGLES = 20_000


def _b64(array: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def read_obj(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) and triangles (F, 3) of an OBJ file (polygons fanned into triangles;
    texture and normal indices ignored; negative indices counted from the end)."""
    vertices: list[list[float]] = []
    triangles: list[list[int]] = []
    with open(path, encoding="utf-8", errors="replace") as file:
        for line in file:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "v" and len(fields) >= 4:
                vertices.append([float(fields[1]), float(fields[2]), float(fields[3])])
            elif fields[0] == "f" and len(fields) >= 4:
                indices = []
                for field in fields[1:]:
                    index = int(field.split("/")[0])
                    indices.append(index - 1 if index > 0 else len(vertices) + index)
                for k in range(1, len(indices) - 1):
                    triangles.append([indices[0], indices[k], indices[k + 1]])
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"{path}: a face refers to a vertex that does not exist")
    return v, f


def _shape(body: dict[str, Any], meshes: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """How the viewer draws a body: {"mesh": key} or a primitive in the scene frame."""
    geometry = body.get("geometry") or {}
    file = geometry.get("file")
    if file:
        key = f"{file}|{geometry.get('scale')}"
        if key not in meshes:
            try:
                v, f = read_obj(file)
            except (OSError, ValueError):
                v, f = np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
            if 0 < len(f) <= MAX_TRIANGLES:
                scale = np.asarray(geometry.get("scale", [1, 1, 1]), dtype=np.float64)
                meshes[key] = {"v": _b64(v * scale, "<f4"), "f": _b64(f, "<u4")}
        if key in meshes:
            return {"mesh": key}
    shape = body.get("shape") or {}
    kind = shape.get("type")
    if kind == "box":
        return {"box": [2 * h for h in shape["halfExtents"]]}
    if kind == "sphere":
        return {"sphere": shape["radius"]}
    if kind == "cylinder":
        return {"cylinder": [shape["radius"], shape["height"]]}
    return {"sphere": 0.02}  # a marker for the centre of mass


def particle_topology(resolved: dict[str, Any]) -> dict[str, Any]:
    """How the viewer draws the scene's particles (global particle indices): "surfaces" (the
    triangles of cloth and the boundary faces of solids), "lines" (the rods' particles, in
    order) and "points" (the rest: fluids)."""
    count = len(resolved.get("particles") or [])
    surfaces: list[list[int]] = []
    covered = np.zeros(count, dtype=bool)
    for key, faces in (("triangleModels", "triangles"), ("tetModels", "boundaryFaces")):
        for model in resolved.get(key) or []:
            first = int(model.get("firstParticle", 0))
            local = np.asarray(model.get(faces) or [], dtype=np.int64).reshape(-1, 3)
            if len(local):
                surfaces.append((local + first).reshape(-1).tolist())
            covered[first:first + int(model.get("particleCount", 0))] = True
    rest = [i for i in range(count) if not covered[i]]
    has_rods = int((resolved.get("deformables") or {}).get("lineModels", 0)) > 0
    return {"surfaces": [_b64(np.asarray(s), "<u4") for s in surfaces],
            "lines": [_b64(np.asarray(rest), "<u4")] if has_rods and len(rest) > 1 else [],
            "points": _b64(np.asarray(rest), "<u4") if rest and not has_rods else "",
            "particleCount": count}


def replay_data(case: str, scene: Scene, runs: Sequence[tuple[str, str, Trajectory]],
                notes: Sequence[str] = ()) -> dict[str, Any]:
    """The replay of `runs` (label, colour, trajectory) of one case; `notes` say which runs of
    the case are not replayed, and why (more are added here)."""
    resolved = scene.resolved()
    bodies = resolved["bodies"]
    meshes: dict[str, dict[str, Any]] = {}
    described = []
    for body in bodies:
        pose = body.get("pose", {})
        described.append({
            "id": body["id"], "dynamic": bool(body.get("dynamic")), "draw": _shape(body, meshes),
            "com": body.get("principalFrame", {}).get("centerOfMass", [0, 0, 0]),
            "position": pose.get("position", [0, 0, 0]), "rotation": pose.get("rotation", [1, 0, 0, 0]),
        })
    topology = particle_topology(resolved)
    particle_count = int(topology["particleCount"])
    said = list(notes)
    dynamic_ids = [b["id"] for b in described if b["dynamic"]]
    usable = []
    for label, colour, t in runs:
        if len(t) < 1:
            said.append(f"{label}: its trajectory holds no sample")
            continue
        has_particles = t.particle_positions is not None and t.particle_positions.shape[1] == particle_count
        if particle_count and not has_particles:
            said.append(f"{label}: read no particles back ({particle_count} in the scene), so only its rigid "
                        "bodies are replayed" if dynamic_ids else f"{label}: read no particles back "
                        f"({particle_count} in the scene): nothing of it to replay")
            if not dynamic_ids:
                continue
        usable.append((label, colour, t))
    duration = max((float(t.times[-1]) for _, _, t in usable), default=0.0)
    budget = MAX_BODY_FRAMES // max(1, len(dynamic_ids) * len(usable))
    particle_budget = MAX_PARTICLE_FRAMES // max(1, particle_count * len(usable)) if particle_count else budget
    samples = max((len(t) for _, _, t in usable), default=1)
    frames = max(2, min(MAX_FRAMES, samples, budget, particle_budget))
    times = np.linspace(0.0, duration, frames)
    encoded = []
    for label, colour, trajectory in usable:
        column = {int(i): k for k, i in enumerate(trajectory.ids)}
        columns = [column.get(i, -1) for i in dynamic_ids]
        rows = np.clip(np.searchsorted(trajectory.times, times - 1e-12), 0, len(trajectory) - 1)
        positions = np.zeros((frames, len(dynamic_ids), 3))
        quaternions = np.tile([1.0, 0.0, 0.0, 0.0], (frames, len(dynamic_ids), 1))
        for j, c in enumerate(columns):
            if c >= 0:
                positions[:, j] = trajectory.positions[rows, c]
                quaternions[:, j] = trajectory.quaternions[rows, c]
        finite = np.isfinite(positions).all(axis=(1, 2)) & np.isfinite(quaternions).all(axis=(1, 2))
        particles = None
        if particle_count and trajectory.particle_positions is not None \
                and trajectory.particle_positions.shape[1] == particle_count:
            particles = trajectory.particle_positions[rows]
            finite &= np.isfinite(particles).all(axis=(1, 2))
        last = int(np.argmin(finite)) if not finite.all() else frames  # a diverged run stops
        entry = {"label": label, "colour": colour, "frames": last,
                 "x": _b64(positions[:last], "<f4"), "q": _b64(quaternions[:last], "<f4")}
        if particles is not None:
            entry["p"] = _b64(particles[:last], "<f4")
        encoded.append(entry)
    if not encoded:
        said.append("no run of this case can be replayed")
    return {"case": case, "times": _b64(times, "<f4"), "frameCount": frames, "duration": duration,
            "dynamicIds": dynamic_ids, "bodies": described, "meshes": meshes, "runs": encoded,
            "particles": topology, "notes": said}


def replay_script(data: dict[str, Any]) -> str:
    """The data as a classic script (loadable from file://)."""
    return "window.PBDVAL_REPLAY = " + json.dumps(data, separators=(",", ":")) + ";\n"
