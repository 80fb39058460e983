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
                    str(REPO / "cases/contact_seed_bounce.json"), "--engines", "pbd,ode,bullet",
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


def drawn_figures(page: Page) -> list[dict[str, Any]]:
    """Every figure's SVG: its size and how many marks (paths, lines, circles) it drew."""
    return page.evaluate("""() => Array.from(document.querySelectorAll('figure svg')).map(svg => {
        const box = svg.getBoundingClientRect();
        return {width: box.width, height: box.height,
                marks: svg.querySelectorAll('path, polyline, line, circle').length};
    })""")


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
    coloured = page.evaluate("""() => {
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
    }""")
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
    for case in ("double_pendulum", "contact_seed_bounce"):
        watched = Watched(browser)
        page = watched.open(report / "cases" / f"{case}.html")
        page.wait_for_function("window.pbdvalReplay !== undefined", timeout=10_000)
        assert watched.problems == [], case
