"""python/requirements-dev.txt, the style checks' pins (docs/build.md#style-checks), against the
venv scripts/install-deps made from it and python/requirements.txt: every pin installed, every
package the style tools need pinned in one of the two files, no package pinned in both."""

from __future__ import annotations

import importlib.metadata
import re

from packaging.requirements import Requirement

from conftest import REPO

PYTHON = REPO / "python"


def pins(file: str) -> dict[str, str]:
    """Normalised name (PEP 503: lower case, runs of -_. as -) → pinned version."""
    found = {}
    for line in (PYTHON / file).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            name, version = line.split("==")
            found[normalised(name)] = version.strip()
    return found


def normalised(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name.strip()).lower()


def runtime_requirements(distribution: str) -> list[str]:
    """The names a distribution requires here (this interpreter and platform, no extras)."""
    names = []
    for text in importlib.metadata.requires(distribution) or []:
        requirement = Requirement(text)
        if requirement.marker is None or requirement.marker.evaluate({"extra": ""}):
            names.append(normalised(requirement.name))
    return names


def test_every_style_tool_pin_is_the_installed_version() -> None:
    development = pins("requirements-dev.txt")
    assert {"ruff", "mypy"} <= set(development)
    for name, version in development.items():
        assert importlib.metadata.version(name) == version, f"{name}: run scripts/install-deps"


def test_every_package_the_style_tools_need_is_pinned() -> None:
    pinned = pins("requirements.txt") | pins("requirements-dev.txt")
    unvisited, seen = ["ruff", "mypy"], set()
    while unvisited:
        name = unvisited.pop()
        if name in seen:
            continue
        seen.add(name)
        assert name in pinned, f"{name} (needed by the style tools) is not pinned"
        unvisited += runtime_requirements(name)
    # mypy's own dependencies are there: the walk went beyond the two tools.
    assert {"mypy-extensions", "pathspec", "librt"} <= seen


def test_no_package_is_pinned_in_both_files() -> None:
    assert set(pins("requirements.txt")) & set(pins("requirements-dev.txt")) == set()
