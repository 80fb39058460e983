"""The Pareto front and a method's distance from it (python/pbdval/pareto.py), on toy data whose
answers follow in closed form: power laws t = c · e^-p are straight lines in log error–log time,
so log-log interpolation between their points is exact and every ratio is known."""

from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
from pathlib import Path

import pytest

from conftest import BUILD, REPO, VENV_PYTHON
from pbdval import pareto
from pbdval.pareto import Point

#: Ratios come from exp/log of doubles: equal to ~1e-15 relative; 1e-12 leaves room and still
#: fails on any real interpolation error (those in these tests would be ≥ 1e-3).
REL = 1e-12


def power_law(c: float, p: float, errors: list[float], method: str) -> list[Point]:
    """Points of a method whose time is c · e^-p at each error."""
    return [Point(e, c * e ** -p, method) for e in errors]


def test_the_front_holds_exactly_the_points_no_other_point_beats() -> None:
    points = [Point(1.0, 1.0, "a"), Point(0.5, 2.0, "a"), Point(0.25, 4.0, "b"),
              Point(1.0, 2.0, "c"),  # dominated by (1, 1): as accurate, slower
              Point(0.5, 3.0, "c"),  # dominated by (0.5, 2)
              Point(2.0, 1.0, "d")]  # dominated by (1, 1): as fast, less accurate
    assert pareto.front(points) == [0, 1, 2]


def test_identical_points_are_both_on_the_front() -> None:
    points = [Point(1.0, 1.0, "a"), Point(1.0, 1.0, "b"), Point(0.1, 5.0, "c")]
    assert pareto.front(points) == [0, 1, 2]


def test_diverged_or_untimed_points_are_never_on_the_front() -> None:
    points = [Point(math.nan, 0.1, "diverged"), Point(math.inf, 0.1, "blown up"),
              Point(1e-3, 0.0, "untimed"), Point(1.0, 1.0, "ok")]
    assert pareto.front(points) == [3]


def test_the_front_time_follows_a_power_law_exactly_between_its_points() -> None:
    # t = e^-2: at e = 0.3 (between the points 1 and 0.1) the front time is 1/0.09.
    front = power_law(1.0, 2.0, [1.0, 0.1, 0.01], "a")
    assert pareto.front_time(front, 0.3) == pytest.approx(1 / 0.09, rel=REL)
    assert pareto.front_time(front, 0.01) == pytest.approx(1e4, rel=REL)


def test_above_its_largest_error_the_front_costs_its_fastest_time_and_below_its_smallest_nothing() -> None:
    front = power_law(1.0, 1.0, [1.0, 0.1], "a")
    assert pareto.front_time(front, 5.0) == pytest.approx(1.0, rel=REL)
    assert pareto.front_time(front, 0.01) is None


def test_a_method_four_times_slower_at_every_error_stands_at_four() -> None:
    # The others: a first-order method t = 1/e, measured at the slow method's errors too (so
    # that its points are dominated); the slow one t = 4/e.
    reference = power_law(1.0, 1.0, [1.0, 0.5, 0.1, 0.05, 0.01], "fast")
    slow = power_law(4.0, 1.0, [0.5, 0.05], "slow")
    d = pareto.distance(reference + slow, "slow")
    assert not d.on_front
    assert d.best_ratio == pytest.approx(4.0, rel=REL)
    assert d.point_ratios == pytest.approx((4.0, 4.0), rel=REL)


def test_a_method_four_times_faster_than_the_others_stands_at_a_quarter() -> None:
    other = power_law(4.0, 1.0, [1.0, 0.1], "slow")
    best = power_law(1.0, 1.0, [1.0, 0.1], "fast")
    d = pareto.distance(other + best, "fast")
    assert d.on_front
    assert d.best_ratio == pytest.approx(0.25, rel=REL)
    assert pareto.front(other + best) == [2, 3]


def test_a_higher_order_method_takes_the_front_where_its_errors_are_small() -> None:
    # The others: a first-order method t = 1/e; the method t = 10 e^-1/2: at e = 1e-2 both take
    # 100 (ratio 1); at e = 1e-4 it takes 1e3 against 1e4 (ratio 0.1).
    first = power_law(1.0, 1.0, [1.0, 1e-1, 1e-2, 1e-3, 1e-4], "first")
    high = power_law(10.0, 0.5, [1e-2, 1e-4], "high")
    d = pareto.distance(first + high, "high")
    assert d.on_front
    assert d.point_ratios == pytest.approx((1.0, 0.1), rel=REL)
    assert d.best_ratio == pytest.approx(0.1, rel=REL)
    assert d.best_error == pytest.approx(1e-4, rel=REL)


def test_a_method_more_accurate_than_every_other_has_no_ratio_there() -> None:
    points = [Point(1.0, 1.0, "other"), Point(1e-6, 50.0, "precise")]
    d = pareto.distance(points, "precise")
    assert d.on_front
    assert d.point_ratios == (None,)
    assert d.best_ratio is None


def test_the_smallest_ratio_is_found_at_a_break_point_of_the_front_inside_the_methods_range() -> None:
    # The front bends at e = 0.1 (a third method's point), which the method never measured:
    # front (1, 1), (0.1, 100), (0.01, 1000); the method (1, 3), (0.01, 3000) interpolates to
    # 3 · 10^1.5 at e = 0.1, so its ratio there is 3 · 10^1.5 / 100 = 0.9487 (< 1: between its
    # settings the method's interpolation passes below the front's), 3 at both of its points.
    points = [Point(1.0, 1.0, "a"), Point(0.01, 1000.0, "a"), Point(0.1, 100.0, "b"),
              Point(1.0, 3.0, "m"), Point(0.01, 3000.0, "m")]
    d = pareto.distance(points, "m")
    assert d.point_ratios == pytest.approx((3.0, 3.0), rel=REL)
    assert d.best_ratio == pytest.approx(3 * 10 ** 1.5 / 100, rel=REL)
    assert d.best_error == pytest.approx(0.1, rel=REL)


def test_a_method_less_accurate_than_every_front_point_is_measured_against_the_fastest() -> None:
    points = [Point(0.1, 1.0, "front"), Point(0.01, 10.0, "front"), Point(1.0, 5.0, "coarse")]
    d = pareto.distance(points, "coarse")
    assert d.point_ratios == pytest.approx((5.0,), rel=REL)
    assert d.best_ratio == pytest.approx(5.0, rel=REL)


def test_a_method_with_a_dominated_setting_is_measured_along_its_other_settings() -> None:
    # The method's (0.5, 10) is beaten by its own (0.25, 8): its curve runs (0.25, 8), (1, 2),
    # t = 2/e, twice the front's t = 1/e.
    front = power_law(1.0, 1.0, [1.0, 0.5, 0.25, 0.1], "front")
    method = [Point(1.0, 2.0, "m"), Point(0.5, 10.0, "m"), Point(0.25, 8.0, "m")]
    assert pareto.method_time(method, 0.5) == pytest.approx(4.0, rel=REL)  # 2 · (0.5)^-1 on (1,2)-(0.25,8)
    d = pareto.distance(front + method, "m")
    assert d.best_ratio == pytest.approx(2.0, rel=REL)


def test_a_zero_error_counts_as_the_round_off_floor() -> None:
    points = [Point(0.0, 2.0, "exact"), Point(1e-3, 1.0, "approximate")]
    assert pareto.front(points) == [1, 0]
    assert pareto.front_time(points, pareto.ERROR_FLOOR) == pytest.approx(2.0, rel=REL)


def test_the_quick_benchmark_records_every_point_and_a_front_no_point_beats(
        pbdval_binary: Path, tmp_path: Path) -> None:
    """`scripts/bench --pareto --quick` end to end (two families, the C++ engines, 0.2 s): the
    front it records is checked against a brute-force dominance test written here, and each
    time against the median of its passes."""
    out = tmp_path / "pareto.json"
    environment = dict(os.environ, PYTHONPATH=f"{REPO / 'python'}:{BUILD / 'python'}")
    subprocess.run([str(VENV_PYTHON), str(REPO / "bench" / "bench_pareto.py"), "--quick", "--binary",
                    str(pbdval_binary), "--out", str(out), "--svg-dir", str(tmp_path), "--markdown",
                    str(tmp_path / "table.md")], check=True, env=environment, capture_output=True, text=True)
    record = json.loads(out.read_text())
    assert record["complete"] and record["schema"] == "pbdval-bench-pareto"
    assert [f["family"] for f in record["families"]] == ["pendulum", "stack"]
    table = (tmp_path / "table.md").read_text()
    for family in record["families"]:
        points = family["points"]
        ok = [i for i, p in enumerate(points) if p["status"] == "ok" and p["error"] is not None]
        assert {points[i]["method"] for i in ok} >= {"pbd", "pbd.xpbd", "ode.quickstep", "bullet.si"}
        for p in points:  # each time the median of three passes (--repeat 3, the default)
            assert len(p["wall_times_s"]) == 3
            assert p["wall_time_s"] == statistics.median(p["wall_times_s"])
        pairs = [(points[i]["error"], points[i]["wall_time_s"]) for i in ok]
        unbeaten = [i for i, (e, t) in zip(ok, pairs, strict=True)
                    if not any(f <= e and u <= t and (f, u) != (e, t) for f, u in pairs)]
        assert sorted(family["front"]) == unbeaten
        assert set(family["distances"]) == {"pbd", "pbd.xpbd"}
        for method, d in family["distances"].items():
            assert d["on_front"] == any(points[i]["method"] == method for i in family["front"])
            assert f"| {family['family']} (`{family['case']}`) | `{method}` |" in table
        assert "Pareto front" in (tmp_path / f"pareto-{family['family']}.svg").read_text()


def test_a_series_left_out_of_the_legend_is_drawn_but_not_named() -> None:
    from pbdval.svg import Series, line_plot

    svg = line_plot([Series("named", [1.0, 2.0], [1.0, 2.0], "#000000"),
                     Series("unnamed", [1.0, 2.0], [2.0, 1.0], "#c4c4c4", legend=False)],
                    title="t", xlabel="x", ylabel="y")
    assert svg.count('class="legend"') == 1 and ">named<" in svg and ">unnamed<" not in svg
    assert svg.count("<path ") == 2  # both curves drawn


@pytest.mark.parametrize(("arguments", "named"), [
    (["--repeat", "2"], "--repeat: at least 3"),
    (["--timeout", "0"], "--timeout: seconds > 0"),
    (["--families", "pendulum,chian"], "unknown family 'chian'"),
    (["--engines", "pbd,odee"], "unknown engine(s) odee"),
    (["--method-param", "pbd.xpbd=start"], "--method-param: expected METHOD:KEY=VALUE"),
    (["--method-param", "pbd.xpbd:substeps=5,10"], "--method-param: expected METHOD:KEY=VALUE (one value)"),
    (["--method-param", "ode.step:erp=0.1"], "--method-param: ode.step is no method of pbd"),
])
def test_bad_options_are_refused_with_the_option_named(pbdval_binary: Path, arguments: list[str],
                                                       named: str) -> None:
    environment = dict(os.environ, PYTHONPATH=f"{REPO / 'python'}:{BUILD / 'python'}")
    done = subprocess.run([str(VENV_PYTHON), str(REPO / "bench" / "bench_pareto.py"), "--binary", str(pbdval_binary),
                           *arguments], env=environment, capture_output=True, text=True, check=False)
    assert done.returncode != 0
    assert named in done.stderr
