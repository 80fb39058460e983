"""python/pyproject.toml against the facts it repeats: the pins of python/requirements.txt, the
version in CMakeLists.txt, and the package folders on disk (docs/build.md#the-python-package);
and the Python engines as modules of the package (no path edits, importable by name)."""

from __future__ import annotations

import re
import tomllib

import setuptools

from conftest import REPO

PYTHON = REPO / "python"


def pyproject() -> dict:
    return tomllib.loads((PYTHON / "pyproject.toml").read_text())


def requirement_pins() -> dict[str, str]:
    """name (lower case) → pinned version, from python/requirements.txt."""
    pins = {}
    for line in (PYTHON / "requirements.txt").read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            name, version = line.split("==")
            pins[name.strip().lower()] = version.strip()
    return pins


def test_every_dependency_of_the_package_is_pinned_as_in_requirements_txt() -> None:
    project = pyproject()["project"]
    declared = list(project["dependencies"])
    for extra in project["optional-dependencies"].values():
        declared += extra
    pins = requirement_pins()
    assert declared, "the package declares no dependencies"
    for requirement in declared:
        name, version = requirement.split("==")
        assert pins.get(name.lower()) == version, f"{requirement} is not python/requirements.txt's pin"


def test_the_package_version_is_the_projects_cmake_version() -> None:
    cmake = re.search(r"project\(pbdval VERSION (\S+)", (REPO / "CMakeLists.txt").read_text())
    assert cmake is not None
    assert pyproject()["project"]["version"] == cmake.group(1)


def test_package_discovery_finds_every_package_folder_of_pbdval() -> None:
    found = pyproject()["tool"]["setuptools"]["packages"]["find"]
    discovered = setuptools.find_packages(where=str(PYTHON / found["where"][0]), include=found["include"])
    # Independently: every folder under python/pbdval with an __init__.py, as a dotted name.
    on_disk = {".".join(p.parent.relative_to(PYTHON).parts)
               for p in (PYTHON / "pbdval").rglob("__init__.py") if "node_modules" not in p.parts}
    assert set(discovered) == on_disk
    assert {"pbdval", "pbdval.external", "pbdval.external.pybullet", "pbdval.external.mujoco"} <= on_disk


def test_no_module_of_the_package_edits_the_import_path() -> None:
    offenders = [str(p.relative_to(REPO)) for p in (PYTHON / "pbdval").rglob("*.py")
                 if "node_modules" not in p.parts and "sys.path" in p.read_text()]
    assert offenders == []


def test_the_engines_siblings_import_as_modules_of_the_package() -> None:
    from pbdval.external.mujoco import contact_law, flexes
    from pbdval.external.mujoco import engine as mujoco_engine
    from pbdval.external.pybullet import deformables, materials
    from pbdval.external.pybullet import engine as pybullet_engine

    assert pybullet_engine.materials is materials and pybullet_engine.deformables is deformables
    assert mujoco_engine.flexes is flexes and mujoco_engine.contact_law is contact_law


def test_importing_the_python_engines_leaves_the_api_function_engines_callable() -> None:
    import pbdval
    import pbdval.external.mujoco.engine
    import pbdval.external.pybullet.engine

    assert callable(pbdval.engines)
