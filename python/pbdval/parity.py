"""The parity record, generated from the engines' feature tables (docs/engines.md#features).

Every engine declares once how it maps every scene feature: the built-in engines in code
(adapters/*/…_features.cpp), the external ones in their catalogue entry (engines/*.json,
"features"). This module renders those tables: the generated blocks of docs/parity*.md and the
report's parity page. Nothing is read back from Markdown.

    .venv/bin/python -m pbdval.parity --write   # regenerate the blocks in docs/
    .venv/bin/python -m pbdval.parity --check   # exit 1 naming the stale files
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from pbdval.api import EngineInfo, FeatureSupport, _core, engines

DOCS = Path(__file__).resolve().parents[2] / "docs"
REGENERATE = ".venv/bin/python -m pbdval.parity --write"
#: The engine pages whose feature block is generated (engine → file), then the overview page.
ENGINE_PAGES = {
    "bullet": "parity-bullet.md",
    "ode": "parity-ode.md",
    "mujoco": "parity-mujoco.md",
    "pybullet": "parity-pybullet.md",
    "mujoco-python": "parity-mujoco-python.md",
    "dart": "engine-dart.md",
    "newton": "engine-newton.md",
    "drake": "parity-drake.md",
}
OVERVIEW_PAGE = "parity.md"
#: Sections of the tables: key prefix → title, in order.
SECTIONS = (("shape", "Shapes (collisionObjectType)"), ("joint", "Joints"), ("body", "Bodies"),
            ("contact", "Contacts"), ("particle", "Particles"), ("cloth", "Cloth (TriangleModels)"),
            ("solid", "Solids (TetModels)"), ("rod", "Rods"), ("fluid", "Fluids"))
ABBREVIATIONS = {"native": "N", "approximated": "A", "unsupported": "U", "undeclared": "–"}
COLOURS = {"native": "#d9f2d9", "approximated": "#ffe9a8", "unsupported": "#f7c6c6", "undeclared": "#ffffff"}


@dataclass(frozen=True)
class Feature:
    key: str
    description: str
    from_scene: bool


@dataclass(frozen=True)
class Cell:
    """How one engine maps one feature: one (support, text) per group of its methods that the
    table treats alike; `methods` empty when every method is treated alike."""

    parts: tuple[tuple[str, str, tuple[str, ...]], ...]

    @property
    def support(self) -> str:
        """The most limited support over the methods (the colour of the cell)."""
        order = ("undeclared", "unsupported", "approximated", "native")
        return min((p[0] for p in self.parts), key=order.index)


def features() -> list[Feature]:
    """The feature vocabulary (adapters/features.cpp), in page order."""
    return [Feature(f["key"], f["description"], bool(f["from_scene"])) for f in _core()._scene_features()]


def _covers(entry: str, key: str) -> bool:
    return entry == key or key.startswith(entry + ".")


def resolve(table: Sequence[FeatureSupport], key: str, method: str) -> FeatureSupport | None:
    """The entry that decides `key` for `method`, as FeatureTable::resolve in adapters/features.cpp:
    the most specific entry restricted to `method`, else the most specific for every method."""
    for restricted in (True, False):
        candidates = [e for e in table if _covers(e.feature, key)
                      and ((method in e.methods) if restricted else not e.methods)]
        if candidates:
            return max(candidates, key=lambda e: len(e.feature))
    return None


def cell(engine: EngineInfo, key: str) -> Cell:
    """How `engine` maps `key` over its methods."""
    groups: dict[tuple[str, str], list[str]] = {}
    for method in engine.methods:
        entry = resolve(engine.features, key, method.name)
        value = (entry.support, entry.text) if entry else ("undeclared", "not in the engine's feature table")
        groups.setdefault(value, []).append(method.name)
    if len(groups) == 1:
        (support, text), = groups
        return Cell(((support, text, ()),))
    return Cell(tuple((support, text, tuple(methods)) for (support, text), methods in groups.items()))


def _escape(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _sections(vocabulary: Sequence[Feature]) -> list[tuple[str, list[Feature]]]:
    return [(title, [f for f in vocabulary if f.key.split(".")[0] == prefix]) for prefix, title in SECTIONS]


def engine_block(engine: EngineInfo, vocabulary: Sequence[Feature]) -> str:
    """The generated feature table of one engine's page."""
    lines = [f"| feature | `{engine.name}` | how, or why not |", "|---|---|---|"]
    for title, members in _sections(vocabulary):
        lines.append(f"| **{title}** | | |")
        for f in members:
            c = cell(engine, f.key)
            if len(c.parts) == 1:
                support, text, _ = c.parts[0]
                lines.append(f"| {_escape(f.description)} | {support} | {_escape(text)} |")
            else:
                supports = "; ".join(f"{s} ({', '.join(f'`{m}`' for m in ms)})" for s, _, ms in c.parts)
                texts = "; ".join(f"{', '.join(f'`{m}`' for m in ms)}: {_escape(t)}" for _, t, ms in c.parts)
                lines.append(f"| {_escape(f.description)} | {supports} | {texts} |")
    if engine.honoured_settings:
        lines += ["", "Simulation settings the engine honours (`--set` of any other has no effect in it): "
                  + ", ".join(f"`{s}`" for s in engine.honoured_settings) + "."]
    return "\n".join(lines)


def by_support(c: Cell) -> dict[str, list[str]]:
    """The cell's methods grouped by their support alone (the texts set aside), the support most
    methods have first."""
    groups: dict[str, list[str]] = {}
    for support, _, methods in c.parts:
        groups.setdefault(support, []).extend(methods)
    return dict(sorted(groups.items(), key=lambda item: -len(item[1])))


def _letters(engine: EngineInfo, c: Cell) -> str:
    """N, A or U; with methods that differ, the majority's letter then each other support with its
    methods ("A; U: implicit.newton, discrete.pgs")."""
    groups = by_support(c)
    supports = list(groups)
    if len(supports) == 1:
        return ABBREVIATIONS[supports[0]]
    prefix = engine.name + "."
    others = "; ".join(f"{ABBREVIATIONS[s]}: " + ", ".join(m.removeprefix(prefix) for m in groups[s])
                       for s in supports[1:])
    return f"{ABBREVIATIONS[supports[0]]}; {others}"


def overview_block(all_engines: Sequence[EngineInfo], vocabulary: Sequence[Feature]) -> str:
    """The generated cross-engine table of docs/parity.md: N, A, U per feature and engine (a
    cell whose methods differ lists each support with its methods)."""
    names = [e.name for e in all_engines]
    lines = ["| feature | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for title, members in _sections(vocabulary):
        lines.append(f"| **{title}** |" + " |" * len(names))
        for f in members:
            cells = [_letters(e, cell(e, f.key)) for e in all_engines]
            lines.append(f"| {_escape(f.description)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _markers(name: str) -> tuple[str, str]:
    return (f"<!-- generated: {name} — from the feature tables by `{REGENERATE}`; do not edit -->",
            f"<!-- end generated: {name} -->")


def _replace_block(text: str, name: str, block: str, file: str) -> str:
    begin, end = _markers(name)
    if begin not in text or end not in text:
        raise ValueError(f"docs/{file}: no generated block '{name}' (the lines {begin!r} … {end!r})")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{begin}\n{block}\n{end}{tail}"


def _visible(all_engines: Sequence[EngineInfo]) -> list[EngineInfo]:
    return [e for e in all_engines if e.run_by_default]


def _compared(all_engines: Sequence[EngineInfo]) -> list[EngineInfo]:
    """The engines of the cross-engine table: those run by default, and the opt-in ones with a
    page of their own (newton: its kernels take minutes to compile, so it runs when named;
    it is a reference engine all the same)."""
    return [e for e in all_engines if e.run_by_default or e.name in ENGINE_PAGES]


def generated_pages() -> dict[str, str]:
    """Every generated page (file name in docs/ → its full text, blocks regenerated)."""
    vocabulary = features()
    registry = list(engines())
    by_name = {e.name: e for e in registry}
    pages: dict[str, str] = {}
    for name, file in ENGINE_PAGES.items():
        if name not in by_name:
            continue
        text = (DOCS / file).read_text(encoding="utf-8")
        pages[file] = _replace_block(text, "features", engine_block(by_name[name], vocabulary), file)
    text = (DOCS / OVERVIEW_PAGE).read_text(encoding="utf-8")
    pages[OVERVIEW_PAGE] = _replace_block(text, "features", overview_block(_compared(registry), vocabulary),
                                          OVERVIEW_PAGE)
    return pages


def stale_pages() -> list[str]:
    """The generated pages whose text in docs/ differs from what the tables give."""
    return [file for file, text in generated_pages().items()
            if (DOCS / file).read_text(encoding="utf-8") != text]


def html_table() -> str:
    """The report's parity table (rows: features; columns: the engines run by default), each cell
    coloured by its support, its text in the tooltip."""
    from html import escape as html

    registry = _visible(list(engines()))
    vocabulary = features()
    rows = ["<table><tr><th>scene feature</th>" + "".join(f"<th>{html(e.name)}</th>" for e in registry) + "</tr>"]
    for title, members in _sections(vocabulary):
        rows.append(f"<tr><th colspan='{len(registry) + 1}' style='text-align:left'>{html(title)}</th></tr>")
        for f in members:
            cells = []
            for e in registry:
                c = cell(e, f.key)
                groups = by_support(c)
                if len(c.parts) == 1:
                    label, tip = c.parts[0][0], c.parts[0][1]
                else:
                    first, *rest = groups
                    label = "; ".join([first] + [f"{s}: {', '.join(groups[s])}" for s in rest])
                    tip = " ".join(f"{', '.join(ms)}: {t}" for _, t, ms in c.parts)
                cells.append(f"<td style='background:{COLOURS[c.support]}' title='{html(tip)}'>{html(label)}</td>")
            rows.append(f"<tr><td title='{html(f.key)}'>{html(f.description)}</td>{''.join(cells)}</tr>")
    rows.append("</table>")
    return "\n".join(rows)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pbdval.parity", description=__doc__.splitlines()[0])
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--write", action="store_true", help="regenerate the blocks in docs/")
    action.add_argument("--check", action="store_true", help="exit 1 when a generated block is stale")
    args = parser.parse_args(argv)
    if args.check:
        stale = stale_pages()
        for file in stale:
            print(f"docs/{file}: stale; regenerate with {REGENERATE}", file=sys.stderr)
        return 1 if stale else 0
    for file, text in generated_pages().items():
        path = DOCS / file
        if path.read_text(encoding="utf-8") != text:
            temporary = path.with_suffix(".md.tmp")
            temporary.write_text(text, encoding="utf-8")
            temporary.replace(path)
            print(f"docs/{file}: regenerated")
    return 0


if __name__ == "__main__":
    sys.exit(main())
