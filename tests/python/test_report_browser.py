"""The report as a person sees it (docs/report.md#the-browser-test): a real run's report opened in
headless Chromium (Debian's `chromium`, installed by scripts/install-deps; driven with
Playwright, pinned in python/requirements.txt). Every page loads with no console error and no
failed load, every figure has drawn something, the 3D replay advances when played and stops
when paused, and screenshots of the overview, a case page with its replay and the convergence
page are saved under the build folder (PBDVAL_BUILD_DIR/report-screenshots)."""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser, ConsoleMessage, Page, Request, sync_playwright

from pbdval.report import build_report
from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[2]
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
#: The flags of the issue, plus SwiftShader: headless Chromium without a GPU draws WebGL in
#: software only when allowed to.
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--no-first-run", "--enable-unsafe-swiftshader"]


def screenshots_folder() -> Path:
    build = Path(os.environ.get("PBDVAL_BUILD_DIR", REPO / "build/release"))
    folder = build / "report-screenshots"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("browser") / "out"
    subprocess.run([str(pbdval_binary()), "run", str(REPO / "cases/double_pendulum.json"),
                    str(REPO / "cases/contact_seed_bounce.json"), str(REPO / "cases/cloth_hanging.json"),
                    "--engines", "pbd,ode,bullet",
                    "--out", str(out), "--jobs", "2", "--quiet"], check=True, capture_output=True)
    index = build_report(out, out / "report", sweeps=[REPO / "reports/sweeps/joint_hinge-timestep"], quiet=True)
    assert (out / "report/assets/three.min.js").is_file(), "three.js was not bundled (scripts/install-deps)"
    return index.parent


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    assert Path(CHROMIUM).is_file(), f"{CHROMIUM} is missing: scripts/install-deps installs Debian's chromium"
    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        yield launched
        launched.close()


class Watched:
    """A page with its console errors, uncaught exceptions and failed loads collected."""

    def __init__(self, browser: Browser) -> None:
        self.page: Page = browser.new_page(viewport={"width": 1280, "height": 1000})
        self.problems: list[str] = []
        self.page.on("console", self._console)
        self.page.on("pageerror", lambda error: self.problems.append(f"uncaught: {error}"))
        self.page.on("requestfailed", self._failed)

    def _console(self, message: ConsoleMessage) -> None:
        if message.type == "error":
            self.problems.append(f"console error: {message.text}")

    def _failed(self, request: Request) -> None:
        self.problems.append(f"failed load: {request.url} ({request.failure})")

    def open(self, path: Path) -> Page:
        self.page.goto(path.as_uri(), wait_until="load")
        return self.page


#: Counts the replay canvas's pixels that are not the white background.
COLOURED_PIXELS = """() => {
    const canvas = document.querySelector('#replay canvas');
    const probe = document.createElement('canvas');
    probe.width = canvas.width; probe.height = canvas.height;
    const context = probe.getContext('2d');
    context.drawImage(canvas, 0, 0);
    const pixels = context.getImageData(0, 0, probe.width, probe.height).data;
    let count = 0;
    for (let i = 0; i < pixels.length; i += 4)
        if (pixels[i] < 240 || pixels[i + 1] < 240 || pixels[i + 2] < 240) ++count;
    return count;
}"""


def legend_colour(page: Page, name: str) -> str:
    """The stroke of the legend line of the first figure entry of `name` (a case page's run label,
    or a convergence page's method, "pbd: p = 0.95, R² 1.000")."""
    colour: str = page.evaluate("""(name) => {
        for (const text of document.querySelectorAll('figure svg text.legend'))
            if (text.textContent === name || text.textContent.startsWith(name + ': ')) {
                let line = text.previousElementSibling;
                while (line && line.tagName !== 'line') line = line.previousElementSibling;
                return line ? line.getAttribute('stroke') : '';
            }
        return '';
    }""", name)
    return colour


def drawn_figures(page: Page) -> list[dict[str, Any]]:
    """Every figure's SVG: its size and how many marks (paths, lines, circles) it drew."""
    figures: list[dict[str, Any]] = page.evaluate("""() => Array.from(document.querySelectorAll('figure svg')).map(
        svg => {
        const box = svg.getBoundingClientRect();
        return {width: box.width, height: box.height,
                marks: svg.querySelectorAll('path, polyline, line, circle').length};
    })""")
    return figures


def test_overview_loads_cleanly(browser: Browser, report: Path) -> None:
    watched = Watched(browser)
    page = watched.open(report / "index.html")
    assert "pbdval report" in page.title()
    assert page.locator("a[href='cases/double_pendulum.html']").count() == 1
    page.screenshot(path=str(screenshots_folder() / "overview.png"), full_page=True)
    assert watched.problems == []


def test_case_page_figures_render_and_the_replay_plays(browser: Browser, report: Path) -> None:
    watched = Watched(browser)
    page = watched.open(report / "cases/double_pendulum.html")
    figures = drawn_figures(page)
    assert figures, "no figure on the case page"
    for figure in figures:
        assert figure["width"] > 100 and figure["height"] > 100 and figure["marks"] > 3, figure
    page.wait_for_function("window.pbdvalReplay && window.pbdvalReplay.ready === true", timeout=10_000)
    assert page.evaluate("window.pbdvalReplay.runs") == 4  # pbd, pbd.xpbd, ode.quickstep, bullet.si
    start = page.evaluate("window.pbdvalReplay.time()")
    page.click("#replay-play")
    page.wait_for_timeout(800)
    assert page.evaluate("window.pbdvalReplay.playing()")
    page.click("#replay-play")  # pause
    paused_at = page.evaluate("window.pbdvalReplay.time()")
    assert paused_at > start + 0.1, f"the replay did not advance: {start} -> {paused_at}"
    page.wait_for_timeout(300)
    assert page.evaluate("window.pbdvalReplay.time()") == paused_at, "the replay did not pause"
    assert "t = " in page.locator("#replay-label").inner_text()
    # The canvas shows something other than the background.
    coloured = page.evaluate(COLOURED_PIXELS)
    assert coloured > 500, "the replay canvas is blank"
    page.screenshot(path=str(screenshots_folder() / "case-double_pendulum.png"), full_page=True)
    page.locator("#replay").screenshot(path=str(screenshots_folder() / "replay-double_pendulum.png"))
    assert watched.problems == []


def test_convergence_page_renders(browser: Browser, report: Path) -> None:
    watched = Watched(browser)
    page = watched.open(report / "convergence.html")
    figures = drawn_figures(page)
    assert len(figures) == 2  # the sweep's order plot and its cost plot (error against wall time)
    for figure in figures:
        assert figure["marks"] > 5, figure
    page.screenshot(path=str(screenshots_folder() / "convergence.png"), full_page=True)
    assert watched.problems == []


def test_parity_page_loads_cleanly(browser: Browser, report: Path) -> None:
    watched = Watched(browser)
    page = watched.open(report / "parity.html")
    assert page.locator("td", has_text="unsupported").count() > 10
    page.screenshot(path=str(screenshots_folder() / "parity.png"), full_page=True)
    assert watched.problems == []


def test_every_case_page_loads_cleanly(browser: Browser, report: Path) -> None:
    for case in ("double_pendulum", "contact_seed_bounce", "cloth_hanging"):
        watched = Watched(browser)
        page = watched.open(report / "cases" / f"{case}.html")
        page.wait_for_function("window.pbdvalReplay !== undefined", timeout=10_000)
        assert watched.problems == [], case


def test_a_cloth_replay_paints_its_surface_and_advances_when_played(browser: Browser, report: Path) -> None:
    watched = Watched(browser)
    page = watched.open(report / "cases/cloth_hanging.html")
    page.wait_for_function("window.pbdvalReplay && window.pbdvalReplay.ready === true", timeout=10_000)
    assert page.evaluate("window.pbdvalReplay.runs") == 2  # pbd and pbd.xpbd: the cloth's particles
    # Bullet and ODE cannot run cloth: the page says they are not replayed, and why.
    notes = page.locator("ul.replay-notes").inner_text()
    assert "bullet/bullet.si: unsupported" in notes and "ode/ode.quickstep: unsupported" in notes
    assert page.evaluate(COLOURED_PIXELS) > 2000, "the cloth replay canvas is blank"
    start = page.evaluate("window.pbdvalReplay.time()")
    page.click("#replay-play")
    page.wait_for_timeout(800)
    page.click("#replay-play")
    assert page.evaluate("window.pbdvalReplay.time()") > start + 0.1, "the cloth replay did not advance"
    page.locator("#replay").screenshot(path=str(screenshots_folder() / "replay-cloth_hanging.png"))
    assert watched.problems == []


def test_an_engine_has_the_same_colour_on_a_case_page_and_on_the_convergence_page(browser: Browser,
                                                                                  report: Path) -> None:
    case = Watched(browser).open(report / "cases/double_pendulum.html")
    convergence = Watched(browser).open(report / "convergence.html")
    pbd_case, pbd_sweep = legend_colour(case, "pbd/pbd"), legend_colour(convergence, "pbd")
    assert pbd_case and pbd_case == pbd_sweep
    ode_case, ode_sweep = legend_colour(case, "ode/ode.quickstep"), legend_colour(convergence, "ode.quickstep")
    assert ode_case and ode_case == ode_sweep and ode_case != pbd_case


def test_no_legend_text_is_cut(browser: Browser, report: Path) -> None:
    for name in ("cases/double_pendulum.html", "cases/cloth_hanging.html", "convergence.html"):
        page = Watched(browser).open(report / name)
        cut = page.evaluate("""() => {
            const out = [];
            let legends = 0;
            for (const svg of document.querySelectorAll('figure svg')) {
                const frame = svg.getBoundingClientRect();
                for (const text of svg.querySelectorAll('text.legend')) {
                    ++legends;
                    const box = text.getBoundingClientRect();
                    if (box.right > frame.right + 0.5 || box.bottom > frame.bottom + 0.5 || box.left < frame.left)
                        out.push(text.textContent);
                }
            }
            return {cut: out, legends: legends};
        }""")
        assert cut["legends"] >= 2 and cut["cut"] == [], (name, cut)


def test_the_overview_shows_each_metrics_unit_and_marks_the_best(browser: Browser, report: Path) -> None:
    page = Watched(browser).open(report / "index.html")
    rows = page.locator("table.ranking tr:has(td)")
    assert rows.count() == 3
    for i in range(rows.count()):
        row = rows.nth(i)
        assert row.locator("th.metric .unit").inner_text().startswith("("), row.inner_text()
        assert row.locator(".best").count() >= 1, row.inner_text()
        assert row.locator(".best").first.is_visible()
    # The table scrolls inside its box rather than past the page.
    fits = page.evaluate("""() => { const box = document.querySelector('div.scroll');
        return box.getBoundingClientRect().right <= document.documentElement.clientWidth; }""")
    assert fits
    page.screenshot(path=str(screenshots_folder() / "overview-ranking.png"))
