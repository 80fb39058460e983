"""Small, dependency-free SVG line plots for the report (python/pbdval/report.py): axes with
ticks and units, linear or logarithmic scales, one colour, dash and marker per series (the
report's palette, python/pbdval/palette.py), a legend as wide as its longest name, points
labelled when asked, optional reference slopes. Every figure is a standalone SVG document
(downloadable as such).

Curves that coincide stay visible: series are drawn widest first (each next one thinner), with
their own dash, and with markers at staggered samples (each series' markers start at another
offset)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from html import escape

#: Width of a character of the 12 px sans-serif legend, an upper bound (Helvetica's widest
#: lower-case letters are 0.6 em wide; digits and most letters less): a legend this wide per
#: character never cuts a name.
CHAR_WIDTH = 7.2
#: Markers per series on a curve of many samples (sparse, so that the curve stays readable).
SPARSE_MARKERS = 10


@dataclass
class Series:
    label: str
    x: Sequence[float]
    y: Sequence[float]
    color: str
    markers: bool = False  # a marker on every point (else, with `marker`, on a few)
    dashed: bool = False  # the reference slopes' dash
    hollow: Sequence[bool] = field(default_factory=list)  # per point: drawn hollow (left out)
    dash: str = ""  # stroke-dasharray of the palette ("" solid)
    marker: str = ""  # the palette's marker shape ("" none)
    point_labels: Sequence[str] = field(default_factory=list)  # per point: text beside it
    x_spread: Sequence[tuple[float, float]] = field(default_factory=list)  # per point: a bar from..to in x
    legend: bool = True  # an entry in the legend (False: one of a group another series names)


def marker_svg(shape: str, x: float, y: float, colour: str, fill: str, size: float = 3.8) -> str:
    """One marker (circle, square, triangle, down, diamond, cross, plus) centred at (x, y)."""
    r = size
    stroke = f'stroke="{colour}" stroke-width="1.3"'
    if shape == "square":
        return (f'<rect x="{x - r:.1f}" y="{y - r:.1f}" width="{2 * r:.1f}" height="{2 * r:.1f}" '
                f'fill="{fill}" {stroke}/>')
    if shape in ("triangle", "down", "diamond"):
        s = -1 if shape == "down" else 1
        corners = ([(x, y - s * r * 1.2), (x + r * 1.1, y + s * r * 0.8), (x - r * 1.1, y + s * r * 0.8)]
                   if shape != "diamond" else [(x, y - r * 1.3), (x + r, y), (x, y + r * 1.3), (x - r, y)])
        points = " ".join(f"{a:.1f},{b:.1f}" for a, b in corners)
        return f'<polygon points="{points}" fill="{fill}" {stroke}/>'
    if shape in ("cross", "plus"):
        d = r if shape == "plus" else r * 0.8
        lines = ([(x - d, y, x + d, y), (x, y - d, x, y + d)] if shape == "plus"
                 else [(x - d, y - d, x + d, y + d), (x - d, y + d, x + d, y - d)])
        return "".join(f'<line x1="{a:.1f}" y1="{b:.1f}" x2="{c:.1f}" y2="{e:.1f}" stroke="{colour}" '
                       f'stroke-width="1.8"/>' for a, b, c, e in lines)
    return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{r:.1f}" fill="{fill}" {stroke}/>'


def _ticks(lo: float, hi: float, log: bool) -> list[float]:
    if log:
        a, b = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
        if b - a <= 2:  # a narrow range: 1, 2, 5 in every decade
            return [m * 10.0 ** e for e in range(a, b + 1) for m in (1, 2, 5)]
        decades = max(1, (b - a) // 6)
        return [10.0 ** e for e in range(a, b + 1, decades)]
    if hi == lo:
        return [lo]
    raw = (hi - lo) / 5
    magnitude = 10.0 ** math.floor(math.log10(raw))
    step = min((m * magnitude for m in (1, 2, 2.5, 5, 10) if m * magnitude >= raw), default=raw)
    first = math.ceil(lo / step) * step
    return [first + k * step for k in range(int((hi - first) / step) + 1)]


def _label(v: float) -> str:
    if v == 0:
        return "0"
    if abs(v) >= 1e4 or abs(v) < 1e-3:
        return f"{v:.0e}".replace("e-0", "e-").replace("e+0", "e")
    return f"{v:g}"


def line_plot(series: Sequence[Series], *, title: str, xlabel: str, ylabel: str, logx: bool = False,
              logy: bool = False, width: int = 640, height: int = 360, legend_width: int = 180) -> str:
    """An SVG line plot. Points that are not finite (or not positive on a log axis) are skipped;
    a plot with no drawable point says so instead of failing. The legend is at least
    `legend_width` wide and as wide as its longest name (the figure grows to the right: the
    page scales it down to fit)."""
    longest = max((len(s.label) for s in series if s.legend), default=0)
    right = max(legend_width, int(48 + CHAR_WIDTH * longest))
    left, top, bottom = 78, 34, 48
    height = max(height, top + 18 * sum(s.legend for s in series) + 24)  # every legend entry inside
    pw, ph = width - left - legend_width, height - top - bottom
    width = left + pw + right

    def usable(v: float, log: bool) -> bool:
        return math.isfinite(v) and (v > 0 or not log)

    xs = [x for s in series for x, y in zip(s.x, s.y) if usable(x, logx) and usable(y, logy)]
    ys = [y for s in series for x, y in zip(s.x, s.y) if usable(x, logx) and usable(y, logy)]
    out = [(f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" font-family="Helvetica, Arial, sans-serif" font-size="12">'),
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left}" y="20" font-size="14" font-weight="bold">{escape(title)}</text>']
    if not xs:
        out.append(f'<text x="{left}" y="{top + ph / 2}" fill="#666">no data to plot</text></svg>')
        return "\n".join(out)
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    if x0 == x1:
        x0, x1 = (x0 / 2, x0 * 2) if logx else (x0 - 1, x1 + 1)
    if y0 == y1:
        y0, y1 = (y0 / 2, y0 * 2) if logy else (y0 - abs(y0) * 0.1 - 1e-12, y1 + abs(y1) * 0.1 + 1e-12)

    def tx(v: float) -> float:
        f = (math.log10(v) - math.log10(x0)) / (math.log10(x1) - math.log10(x0)) if logx else (v - x0) / (x1 - x0)
        return left + f * pw

    def ty(v: float) -> float:
        f = (math.log10(v) - math.log10(y0)) / (math.log10(y1) - math.log10(y0)) if logy else (v - y0) / (y1 - y0)
        return top + ph - f * ph

    out.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>')
    for t in _ticks(x0, x1, logx):
        if x0 * (1 - 1e-9) <= t <= x1 * (1 + 1e-9) or not logx and x0 <= t <= x1:
            X = tx(t)
            out.append(f'<line x1="{X:.1f}" y1="{top + ph}" x2="{X:.1f}" y2="{top + ph + 5}" stroke="#444"/>'
                       f'<text x="{X:.1f}" y="{top + ph + 18}" text-anchor="middle">{_label(t)}</text>')
    for t in _ticks(y0, y1, logy):
        if y0 * (1 - 1e-9) <= t <= y1 * (1 + 1e-9) or not logy and y0 <= t <= y1:
            Y = ty(t)
            out.append(f'<line x1="{left - 5}" y1="{Y:.1f}" x2="{left}" y2="{Y:.1f}" stroke="#444"/>'
                       f'<line x1="{left}" y1="{Y:.1f}" x2="{left + pw}" y2="{Y:.1f}" stroke="#eee"/>'
                       f'<text x="{left - 8}" y="{Y + 4:.1f}" text-anchor="end">{_label(t)}</text>')
    out.append(f'<text x="{left + pw / 2}" y="{height - 10}" text-anchor="middle">{escape(xlabel)}</text>')
    out.append(f'<text transform="translate(16 {top + ph / 2}) rotate(-90)" text-anchor="middle">'
               f'{escape(ylabel)}</text>')
    count = len(series)
    entry = 0  # legend entries so far
    for k, s in enumerate(series):
        points = [(tx(x), ty(y), (s.hollow[i] if i < len(s.hollow) else False),
                   (s.point_labels[i] if i < len(s.point_labels) else ""))
                  for i, (x, y) in enumerate(zip(s.x, s.y)) if usable(x, logx) and usable(y, logy)]
        for i, (x, y) in enumerate(zip(s.x, s.y)):
            if i < len(s.x_spread) and usable(y, logy) and all(usable(v, logx) for v in s.x_spread[i]):
                lo, hi = s.x_spread[i]
                out.append(f'<line class="spread" x1="{tx(lo):.1f}" y1="{ty(y):.1f}" x2="{tx(hi):.1f}" '
                           f'y2="{ty(y):.1f}" stroke="{s.color}" stroke-width="1.2"/>')
        # Widest first, each next series thinner: a curve under another still shows at its edges.
        stroke_width = 1.4 + 1.8 * (count - 1 - k) / max(1, count - 1)
        dash = s.dash or ("5,4" if s.dashed else "")
        dash_attribute = f' stroke-dasharray="{dash}"' if dash else ""
        if len(points) > 1:
            path = " ".join(f"{'M' if i == 0 else 'L'}{px:.1f},{py:.1f}" for i, (px, py, _, _) in enumerate(points))
            out.append(f'<path d="{path}" fill="none" stroke="{s.color}" stroke-width="{stroke_width:.2f}"'
                       f'{dash_attribute}/>')
        shape = s.marker or ("circle" if s.markers else "")
        if shape:
            if s.markers:
                marked = list(range(len(points)))
            else:  # a few markers, each series starting at another offset
                stride = max(1, len(points) // SPARSE_MARKERS)
                marked = list(range((k * stride) // max(1, count) % stride, len(points), stride))
            for i in marked:
                px, py, hollow, _ = points[i]
                out.append(marker_svg(shape, px, py, s.color, "white" if hollow else s.color))
        for px, py, _, text in points:
            if text:
                out.append(f'<text x="{px + 6:.1f}" y="{py - 6:.1f}" font-size="10" fill="{s.color}">'
                           f'{escape(text)}</text>')
        if not s.legend:
            continue
        ly = top + 14 + 18 * entry
        entry += 1
        out.append(f'<line x1="{left + pw + 12}" y1="{ly - 4}" x2="{left + pw + 40}" y2="{ly - 4}" '
                   f'stroke="{s.color}" stroke-width="2"{dash_attribute}/>')
        if shape:
            out.append(marker_svg(shape, left + pw + 26, ly - 4, s.color, s.color, 3.2))
        out.append(f'<text class="legend" x="{left + pw + 46}" y="{ly}">{escape(s.label)}</text>')
    out.append("</svg>")
    return "\n".join(out)
