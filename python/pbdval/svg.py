"""Small, dependency-free SVG line plots for the report (python/pbdval/report.py): axes with
ticks and units, linear or logarithmic scales, one colour per series, a legend, optional
reference slopes. Every figure is a standalone SVG document (downloadable as such)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from html import escape

#: One colour per engine/method across the whole report (Okabe–Ito, readable in print and by
#: colour-blind readers), then a few more.
PALETTE = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442",
           "#8C564B", "#7F7F7F", "#17BECF", "#BCBD22")


@dataclass
class Series:
    label: str
    x: Sequence[float]
    y: Sequence[float]
    color: str
    markers: bool = False
    dashed: bool = False
    hollow: Sequence[bool] = field(default_factory=list)  # per point: drawn hollow (left out)


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
    a plot with no drawable point says so instead of failing."""
    left, right, top, bottom = 78, legend_width, 34, 48
    pw, ph = width - left - right, height - top - bottom

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
    for k, s in enumerate(series):
        points = [(tx(x), ty(y), (s.hollow[i] if i < len(s.hollow) else False))
                  for i, (x, y) in enumerate(zip(s.x, s.y)) if usable(x, logx) and usable(y, logy)]
        if len(points) > 1:
            path = " ".join(f"{'M' if i == 0 else 'L'}{px:.1f},{py:.1f}" for i, (px, py, _) in enumerate(points))
            dash = ' stroke-dasharray="5,4"' if s.dashed else ""
            out.append(f'<path d="{path}" fill="none" stroke="{s.color}" stroke-width="1.8"{dash}/>')
        if s.markers:
            for px, py, hollow in points:
                fill = "white" if hollow else s.color
                out.append(f'<circle cx="{px:.1f}" cy="{py:.1f}" r="3.5" fill="{fill}" stroke="{s.color}"/>')
        ly = top + 14 + 18 * k
        legend_dash = ' stroke-dasharray="5,4"' if s.dashed else ""
        out.append(f'<line x1="{left + pw + 12}" y1="{ly - 4}" x2="{left + pw + 32}" y2="{ly - 4}" '
                   f'stroke="{s.color}" stroke-width="2"{legend_dash}/>'
                   f'<text x="{left + pw + 36}" y="{ly}">{escape(s.label)}</text>')
    out.append("</svg>")
    return "\n".join(out)
