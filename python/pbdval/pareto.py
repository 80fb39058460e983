"""The error–time Pareto front of many methods, and how far one method stands from it
(docs/benchmarks.md#pareto-fronts, `scripts/bench --pareto`).

A point is (error, time): the error of one run against its reference and the wall time it took.
A point is on the front when no other point is at least as accurate and at least as fast and
strictly better in one of the two. The front, read as a curve, is the time it takes to reach an
error: between two front points, interpolated linearly in (log error, log time) — the power law
e ∝ t^-p that a method of fixed order follows between two of its settings — and, at errors above
the front's largest, the time of its fastest point (a looser error costs no more than that).
Below the front's smallest error nobody measured anything: the front has no time there.

A method's distance from the front at an error e is the ratio T_method(e) / T_front(e) at that
equal error, where T_front is the front of the *other* methods (the front the method has to
beat: a ratio below 1 says how much faster than every other method it reaches that error) and
T_method is interpolated the same way between the method's own non-dominated points (a setting
that another setting of the same method beats is no setting anyone would choose). A method is
on the front when one of its measured points is on the front of all points.
Both curves are piecewise linear in log error, so the ratio's logarithm is too: its extremes over
the method's error range lie at the break points of either curve, and the smallest ratio (the
method's best standing) is found exactly by evaluating it there.

Errors of exactly 0 (a body that never moved) are raised to ERROR_FLOOR before any logarithm:
an error below round-off is no better than round-off.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

#: Errors below this count as this (m, or the metric's unit): the round-off of positions of
#: order 1 in double precision is ~1e-16, so no measured error below 1e-15 means anything.
ERROR_FLOOR = 1e-15


@dataclass(frozen=True)
class Point:
    """One run: its error, its wall time (s) and who made it (method, setting)."""

    error: float
    time: float
    method: str = ""
    setting: str = ""


def _usable(p: Point) -> bool:
    return math.isfinite(p.error) and math.isfinite(p.time) and p.error >= 0 and p.time > 0


def dominates(a: Point, b: Point) -> bool:
    """Whether `a` is at least as accurate and as fast as `b`, and strictly better in one."""
    return a.error <= b.error and a.time <= b.time and (a.error < b.error or a.time < b.time)


def front(points: Sequence[Point]) -> list[int]:
    """Indices of the points on the Pareto front, by increasing time (decreasing error). Points
    with a non-finite or negative error, or a non-positive or non-finite time, are never on it
    (a diverged run has no error to trade). Two identical points are both on it."""
    usable = [i for i, p in enumerate(points) if _usable(p)]
    on = [i for i in usable if not any(dominates(points[j], points[i]) for j in usable if j != i)]
    return sorted(on, key=lambda i: (points[i].time, points[i].error))


def _log(v: float) -> float:
    return math.log(max(v, ERROR_FLOOR))


def _curve(points: Sequence[Point]) -> list[tuple[float, float]]:
    """(log error, log time) of the non-dominated points, by increasing error; one point per
    error (the fastest)."""
    chosen = [points[i] for i in front(points)]
    by_error: dict[float, float] = {}
    for p in chosen:
        key = _log(p.error)
        by_error[key] = min(by_error.get(key, math.inf), math.log(p.time))
    return sorted(by_error.items())


def _interpolate(curve: Sequence[tuple[float, float]], log_error: float, *,
                 flat_above: bool) -> float | None:
    """log time of `curve` at `log_error`: linear between break points; above the largest error
    the fastest point's time when `flat_above` (else None); below the smallest, None."""
    if not curve or log_error < curve[0][0] - 1e-12:
        return None
    if log_error >= curve[-1][0] - 1e-12:
        if abs(log_error - curve[-1][0]) <= 1e-12 or flat_above:
            return curve[-1][1]
        return None
    for (e0, t0), (e1, t1) in itertools.pairwise(curve):
        if e0 - 1e-12 <= log_error <= e1 + 1e-12:
            if e1 == e0:
                return min(t0, t1)
            f = (log_error - e0) / (e1 - e0)
            return t0 + f * (t1 - t0)
    return None  # not reached: the curve covers [first, last]


def front_time(front_points: Sequence[Point], error: float) -> float | None:
    """The front's time (s) at `error`: log-log interpolation between its points, the fastest
    point's time above its largest error, None below its smallest."""
    value = _interpolate(_curve(front_points), _log(error), flat_above=True)
    return None if value is None else math.exp(value)


def method_time(method_points: Sequence[Point], error: float) -> float | None:
    """The method's time (s) at `error` between its own non-dominated points (log-log); None
    outside their error range."""
    value = _interpolate(_curve(method_points), _log(error), flat_above=False)
    return None if value is None else math.exp(value)


@dataclass(frozen=True)
class Distance:
    """How far a method stands from the front over the errors it reaches.

    best_ratio: the smallest T_method(e) / T_others(e) over the errors where both exist (< 1
    where the method beats every other; None when the others reach none of its errors);
    best_error: where; point_ratios: the ratio at each of the method's points (None where the
    others have no time: the point is more accurate than all of them, hence on the front);
    on_front: whether any of its points is on the front of all points."""

    best_ratio: float | None
    best_error: float | None
    point_ratios: tuple[float | None, ...]
    on_front: bool


def distance(points: Sequence[Point], method: str) -> Distance:
    """How far the points of `method` stand from the front of the other methods' points (the
    front it would have to beat), and whether any of its points is on the front of them all."""
    mine = [p for p in points if p.method == method]
    others = [p for p in points if p.method != method]
    on_front = any(points[i].method == method for i in front(points))
    curve = _curve(others)
    own = _curve(mine)
    point_ratios: list[float | None] = []
    for p in mine:
        if not _usable(p):
            point_ratios.append(None)
            continue
        t_front = _interpolate(curve, _log(p.error), flat_above=True)
        point_ratios.append(None if t_front is None else math.exp(math.log(p.time) - t_front))
    # The ratio is piecewise linear in log error: its smallest value lies at a break point of
    # either curve inside the method's error range.
    best: tuple[float, float] | None = None
    if own:
        low, high = own[0][0], own[-1][0]
        breaks = sorted({e for e, _ in own} | {e for e, _ in curve if low <= e <= high})
        for e in breaks:
            t_method = _interpolate(own, e, flat_above=False)
            t_front = _interpolate(curve, e, flat_above=True)
            if t_method is None or t_front is None:
                continue
            ratio = math.exp(t_method - t_front)
            if best is None or ratio < best[0]:
                best = (ratio, math.exp(e))
    return Distance(best_ratio=None if best is None else best[0],
                    best_error=None if best is None else best[1],
                    point_ratios=tuple(point_ratios), on_front=on_front)
