"""`pbdval import` over every URDF of pybullet_data and every MJCF of the dm_control suite: each
gives a scene or a refusal naming what it cannot represent. Writes or checks the outcome table of
docs/models.md (between the markers below).

    .venv/bin/python -m pbdval.import_model_sweep --write docs/models.md
    .venv/bin/python -m pbdval.import_model_sweep --check docs/models.md
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from pbdval.import_model import ImportModelError, import_model

BEGIN = "<!-- import sweep: begin (python -m pbdval.import_model_sweep --write docs/models.md) -->"
END = "<!-- import sweep: end -->"


@dataclass
class Outcome:
    source: str
    model: str  # the path within its source
    bodies: int
    joints: int
    notes: int
    refusal: str  # "" when imported


def pybullet_data_root() -> Path:
    import pybullet_data  # type: ignore[import-untyped]

    return Path(pybullet_data.getDataPath())


def suite_root() -> Path:
    import mujoco

    return Path(mujoco.__file__).parents[1] / "dm_control" / "suite"


def sweep() -> list[Outcome]:
    """Every model, in path order. Anything but a scene or an ImportModelError propagates: a
    crash fails the sweep."""
    outcomes: list[Outcome] = []
    sources = [("pybullet_data", pybullet_data_root(), sorted(pybullet_data_root().rglob("*.urdf"))),
               ("dm_control suite", suite_root(), sorted(suite_root().glob("*.xml")))]
    for source, root, paths in sources:
        for path in paths:
            model = path.relative_to(root).as_posix()
            try:
                result = import_model(path)
            except ImportModelError as error:
                text = str(error)
                if not text.startswith(str(path) + ": "):
                    raise AssertionError(f"{path}: the refusal does not name the model: {text}") from None
                outcomes.append(Outcome(source, model, 0, 0, 0,
                                        text[len(str(path)) + 2:].replace(str(root) + "/", "")))
                continue
            joints = sum(len(v) for k, v in result.scene.items() if k.endswith("Joints"))
            outcomes.append(Outcome(source, model, len(result.scene["RigidBodies"]), joints,
                                    len(result.notes), ""))
    return outcomes


def table(outcomes: list[Outcome]) -> str:
    counts = Counter((o.source, o.refusal == "") for o in outcomes)
    lines = [BEGIN, "", "| source | models | imported | refused |", "|---|---|---|---|"]
    for source in dict.fromkeys(o.source for o in outcomes):
        lines.append(f"| {source} | {counts[(source, True)] + counts[(source, False)]} | "
                     f"{counts[(source, True)]} | {counts[(source, False)]} |")
    lines += ["", "Every dm_control suite model, and every refused pybullet_data model:", "",
              "| source | model | outcome |", "|---|---|---|"]
    for o in outcomes:
        if o.source == "pybullet_data" and not o.refusal:
            continue
        outcome = (f"refused: {o.refusal}" if o.refusal else
                   f"{o.bodies} bodies, {o.joints} joints, {o.notes} notes")
        lines.append(f"| {o.source} | `{o.model}` | {outcome.replace('|', '/')} |")
    lines += ["", END]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pbdval.import_model_sweep", description=__doc__)
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", help="replace the table in this Markdown file")
    group.add_argument("--check", help="exit 1 unless this Markdown file holds the current table")
    args = parser.parse_args(argv)
    document = Path(args.write or args.check)
    text = document.read_text(encoding="utf-8")
    if BEGIN not in text or END not in text:
        print(f"{document}: the markers of the sweep table are missing ({BEGIN})", file=sys.stderr)
        return 1
    before, rest = text.split(BEGIN, 1)
    after = rest.split(END, 1)[1]
    current = before + table(sweep()) + after
    if args.write:
        document.write_text(current, encoding="utf-8")
        return 0
    if current != text:
        print(f"{document}: the import sweep's table is stale: run python -m pbdval.import_model_sweep "
              f"--write {document}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
