"""The 3D replay of a case in the report (docs/report.md#3d-replay).

Every ok run's trajectory, downsampled to at most `MAX_FRAMES` frames (and at most
`MAX_BODY_FRAMES` frames × dynamic bodies × runs per case, so a 100-link chain stays small), is
written with the bodies' shapes into `replay/CASE.js`, a classic script that sets
`window.PBDVAL_REPLAY` (a page opened from the disk may not fetch JSON, but may load scripts).
The viewer, `web/replay.js`, draws it with three.js (bundled from npm into the report's
`assets/`): one colour per engine/method, static bodies grey, play, pause, speed and a time
scrubber; between frames it interpolates positions linearly and rotations by slerp.

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


def replay_data(case: str, scene: Scene, runs: Sequence[tuple[str, str, Trajectory]]) -> dict[str, Any]:
    """The replay of `runs` (label, colour, trajectory) of one case."""
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
    dynamic_ids = [b["id"] for b in described if b["dynamic"]]
    usable = [(label, colour, t) for label, colour, t in runs if len(t) >= 1]
    duration = max((float(t.times[-1]) for _, _, t in usable), default=0.0)
    budget = MAX_BODY_FRAMES // max(1, len(dynamic_ids) * len(usable))
    samples = max((len(t) for _, _, t in usable), default=1)
    frames = max(2, min(MAX_FRAMES, samples, budget))
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
        last = int(np.argmin(finite)) if not finite.all() else frames  # a diverged run stops
        encoded.append({"label": label, "colour": colour, "frames": last,
                        "x": _b64(positions[:last], "<f4"), "q": _b64(quaternions[:last], "<f4")})
    return {"case": case, "times": _b64(times, "<f4"), "frameCount": frames, "duration": duration,
            "dynamicIds": dynamic_ids, "bodies": described, "meshes": meshes, "runs": encoded}


def replay_script(data: dict[str, Any]) -> str:
    """The data as a classic script (loadable from file://)."""
    return "window.PBDVAL_REPLAY = " + json.dumps(data, separators=(",", ":")) + ";\n"
