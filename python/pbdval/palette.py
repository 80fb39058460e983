"""One style per engine/method for every page of every report (docs/report.md#one-palette).

The style of a run is derived from the registry's declaration alone, never from the order in
which a report meets its runs: the engine's position among the registry's engines picks its
colour family and marker, the method's position among its engine's methods picks the dash and
the shade (the engine's colour for its first method, then darker and lighter shades: the 3D
replay, which has no dashes, tells two methods of one engine apart by it). So
`pbd/pbd` has the same colour and dash on a case page, on the convergence page and in the 3D
replay, in this report and in the next, whatever runs the report holds. An engine the registry
does not declare (results of an engine since removed) gets a grey of its own and a dash from a
hash of its name (stable across runs too).
"""

from __future__ import annotations

import functools
import hashlib
from dataclasses import dataclass

#: Engine colours, in the order of the registry's engines (Okabe–Ito first: readable in print
#: and by colour-blind readers).
ENGINE_COLOURS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#999933", "#E69F00", "#000000", "#56B4E9",
                  "#8C564B", "#17BECF", "#BCBD22", "#F0E442")
#: Method dashes (SVG stroke-dasharray; "" solid), in the order of the engine's methods.
DASHES = ("", "7,3", "2,2", "9,3,2,3", "4,4", "12,3,3,3,3,3")
#: Engine markers, in the same order as the colours: curves that coincide stay told apart.
MARKERS = ("circle", "square", "triangle", "diamond", "down", "cross", "plus", "circle", "square", "triangle",
           "diamond", "down")
UNDECLARED_COLOUR = "#999999"
#: Shades of an engine's colour by method position: a factor towards black (< 0) or white (> 0).
SHADES = (0.0, -0.4, 0.45, -0.65, 0.7, -0.2)


def shade(colour: str, amount: float) -> str:
    """`colour` (#rrggbb) moved towards white (amount > 0) or black (amount < 0)."""
    channels = [int(colour[i:i + 2], 16) for i in (1, 3, 5)]
    if amount < 0 and max(channels) < 64:  # black has no darker shade: lighten it instead
        amount = -amount
    target = 255 if amount > 0 else 0
    return "#" + "".join(f"{round(c + abs(amount) * (target - c)):02x}" for c in channels)


@dataclass(frozen=True)
class Style:
    colour: str
    dash: str
    marker: str


@functools.lru_cache(maxsize=1)
def declared_engines() -> tuple[tuple[str, tuple[str, ...]], ...]:
    """(engine, its methods) in the registry's order: the declaration the styles come from."""
    from pbdval.api import engines  # the C++ core, imported only when a style is asked for

    return tuple((e.name, tuple(m.name for m in e.methods)) for e in engines())


def _hash(name: str) -> int:
    return int(hashlib.sha256(name.encode("utf-8")).hexdigest()[:8], 16)


def style_of(engine: str, method: str) -> Style:
    """The style of a run of `method` in `engine`."""
    for index, (name, methods) in enumerate(declared_engines()):
        if name == engine:
            position = methods.index(method) if method in methods else len(DASHES) - 1
            # (dash, shade) differ between any two of an engine's first 36 methods: the dash
            # cycles with the position, the shade with the position plus the number of cycles.
            tint = SHADES[(position + position // len(DASHES)) % len(SHADES)]
            colour = shade(ENGINE_COLOURS[index % len(ENGINE_COLOURS)], tint)
            return Style(colour, DASHES[position % len(DASHES)], MARKERS[index % len(MARKERS)])
    return Style(UNDECLARED_COLOUR, DASHES[_hash(engine + "/" + method) % len(DASHES)], "cross")


def engine_of_method(method: str) -> str:
    """The engine that declares `method` ("" when none does)."""
    for name, methods in declared_engines():
        if method in methods:
            return name
    return ""


def style_of_label(label: str) -> Style:
    """The style of a run label: "engine/method", "engine/method [a=1]" (the engine's colour and
    the method's dash: an assignment does not change who computed it) or a bare method name (a
    sweep's points)."""
    base = label.split(" [", 1)[0]
    if "/" in base:
        engine, method = base.split("/", 1)
    else:
        engine, method = engine_of_method(base), base
    return style_of(engine, method)
