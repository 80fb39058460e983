"""Rules over the repository's sources, run by scripts/check-style (docs/build.md#style-checks):

- the docs and the code cite only what the repository holds, papers or upstream sources, never
  the working notes that lived beside it (a research folder of Markdown notes, a shared folder
  one level up);
- no Python file outside tests/ edits the import path (sys.path, site.addsitedir): the package
  imports as installed, scripts run with the PYTHONPATH their launcher sets;
- the layers pbd → adapters → validation → python → bench: no C++ #include, CMake target link
  or Python import of a module reaches a higher layer (docs/build.md#layers).

Each rule is one function over file texts; the tests below run it over the repository and,
first, over a small example that breaks it, so that a rule that stopped finding anything fails.
"""

from __future__ import annotations

import ast
import re
import subprocess
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from conftest import REPO

# The chain, lowest first: a module may use its own layer and those below it.
LAYERS = ("pbd", "adapters", "validation", "python", "bench")


def repository_files(*patterns: str) -> list[Path]:
    """Files tracked by git or new (not ignored: no build/, node_modules/ or .venv/), by pattern."""
    listed = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z", "--", *patterns],
                            cwd=REPO, capture_output=True, text=True, check=True).stdout
    return sorted(REPO / name for name in listed.split("\0") if name and (REPO / name).is_file())


def relative(path: Path) -> str:
    return path.relative_to(REPO).as_posix()


def layer_of(path: str) -> int | None:
    """The layer of a repository path (its first folder), or None outside the chain (tests/,
    examples/, cmake/, cases/, docs/, ...)."""
    top = path.split("/", 1)[0]
    return LAYERS.index(top) if top in LAYERS else None


# ---- citations of notes outside the repository ------------------------------------------------

# Built from pieces so that this file does not cite what it forbids.
OUTSIDE_NOTES = re.compile("|".join([
    r"\b" + "research" + r"/[\w.-]+\.md",  # the research notes (pbd, validation, deps, ...)
    r"\.\./" + "shared" + "/",  # anything in the shared folder beside the repository
    "shared" + "/" + "research",
]))


def outside_citations(name: str, text: str) -> list[str]:
    """'FILE:LINE: text' for every line of `text` that cites notes outside the repository."""
    return [f"{name}:{number}: {line.strip()}" for number, line in enumerate(text.splitlines(), start=1)
            if OUTSIDE_NOTES.search(line)]


def text_files() -> Iterator[tuple[str, str]]:
    for path in repository_files():
        try:
            yield relative(path), path.read_text(encoding="utf-8")
        except UnicodeDecodeError:  # binary (meshes, numpy arrays): nothing cited there
            continue


def test_the_citation_rule_finds_notes_outside_the_repository() -> None:
    text = ("// the seed's order (" + "research" + "/pbd.md §3.1)\n"
            "ok: docs/seed-library.md#the-step\n"
            "More: `../" + "shared" + "/DESIGN.md`\n")
    assert [c.split(":")[1] for c in outside_citations("x.h", text)] == ["1", "3"]


def test_no_file_cites_notes_outside_the_repository() -> None:
    found = [c for name, text in text_files() for c in outside_citations(name, text)]
    assert found == [], "cite docs/ or the paper or upstream source instead:\n" + "\n".join(found)


# ---- import path edits ------------------------------------------------------------------------

PATH_MUTATORS = {"insert", "append", "extend", "remove", "pop", "clear", "__setitem__", "__iadd__"}


def is_sys_path(node: ast.AST) -> bool:
    return (isinstance(node, ast.Attribute) and node.attr == "path"
            and isinstance(node.value, ast.Name) and node.value.id == "sys")


def import_path_edits(name: str, source: str) -> list[str]:
    """'FILE:LINE' for every edit of the import path in a Python source: sys.path mutated,
    assigned or sliced into, and site.addsitedir."""
    found: list[int] = []
    for node in ast.walk(ast.parse(source, filename=name)):
        edit = False
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            edit = ((node.func.attr in PATH_MUTATORS and is_sys_path(node.func.value))
                    or (node.func.attr == "addsitedir" and isinstance(node.func.value, ast.Name)
                        and node.func.value.id == "site"))
        elif isinstance(node, ast.Assign | ast.AugAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            edit = any(is_sys_path(t) or (isinstance(t, ast.Subscript) and is_sys_path(t.value)) for t in targets)
        if edit and isinstance(node, ast.stmt | ast.expr):
            found.append(node.lineno)
    return [f"{name}:{line}" for line in sorted(found)]


def test_the_import_path_rule_finds_each_kind_of_edit() -> None:
    source = ("import site, sys\n"
              "sys.path.insert(0, 'python')\n"
              "sys.path.append('x')\n"
              "sys.path[:0] = ['y']\n"
              "sys.path += ['z']\n"
              "site.addsitedir('w')\n"
              "print(sys.path)\n")  # reading it is no edit
    assert import_path_edits("x.py", source) == [f"x.py:{n}" for n in (2, 3, 4, 5, 6)]


def test_no_python_file_outside_tests_edits_the_import_path() -> None:
    found = [edit for path in repository_files("*.py") if not relative(path).startswith("tests/")
             for edit in import_path_edits(relative(path), path.read_text(encoding="utf-8"))]
    assert found == [], "run with the PYTHONPATH of the launching script instead:\n" + "\n".join(found)


# ---- layering ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Reach:
    """One use of a module of another layer: where, what, and both layers."""

    where: str
    what: str
    source_layer: int
    target_layer: int

    def __str__(self) -> str:
        return (f"{self.where}: {self.what} ({LAYERS[self.source_layer]} uses {LAYERS[self.target_layer]}, "
                "a higher layer)")


INCLUDE = re.compile(r'^\s*#\s*include\s*["<]([^">]+)[">]', re.MULTILINE)
# Where a quoted include is looked up, after the including file's folder: the repository root
# (target_include_directories(... ${PROJECT_SOURCE_DIR})) and the PBD library's public headers.
INCLUDE_ROOTS = ("", "pbd/include")


def include_target(including: str, header: str, exists: Iterable[str]) -> str | None:
    """The repository path a quoted #include names, or None when it names no file of the
    repository (a generated header such as pbdval/build_info.h)."""
    files = set(exists)
    folder = including.rsplit("/", 1)[0] if "/" in including else ""
    for root in (folder, *INCLUDE_ROOTS):
        candidate = f"{root}/{header}" if root else header
        if candidate in files:
            return candidate
    return None


def upward_includes(files: dict[str, str]) -> list[Reach]:
    """Every #include "…" in `files` (path → text) of a header in a higher layer."""
    found = []
    for path, text in files.items():
        source = layer_of(path)
        if source is None:
            continue
        for match in INCLUDE.finditer(text):
            target_path = include_target(path, match.group(1), files)
            target = layer_of(target_path) if target_path else None
            if target is not None and target > source:
                line = text.count("\n", 0, match.start()) + 1
                found.append(Reach(f"{path}:{line}", f'#include "{match.group(1)}"', source, target))
    return found


CMAKE_TARGET = re.compile(r"\b(?:add_library|add_executable|pybind11_add_module)\s*\(\s*([\w.:-]+)")
CMAKE_LINK = re.compile(r"\btarget_link_libraries\s*\(([^)]*)\)", re.DOTALL)


def upward_links(cmake_files: dict[str, str]) -> list[Reach]:
    """Every target_link_libraries of a project target to a target defined in a higher layer;
    a target's layer is that of the folder whose CMakeLists.txt defines it."""
    defined = {}
    for path, text in cmake_files.items():
        for name in CMAKE_TARGET.findall(text):
            defined[name] = layer_of(path)
    found = []
    for path, text in cmake_files.items():
        for match in CMAKE_LINK.finditer(text):
            words = [w for w in re.sub(r"#[^\n]*", "", match.group(1)).split()]
            source = defined.get(words[0]) if words else None
            if source is None:
                continue
            for word in words[1:]:
                target = defined.get(word)
                if target is not None and target > source:
                    line = text.count("\n", 0, match.start()) + 1
                    found.append(Reach(f"{path}:{line}", f"{words[0]} links {word}", source, target))
    return found


def python_module_layers(files: Iterable[str]) -> dict[str, int]:
    """Top-level Python module name → layer: the package pbdval (python/pbdval) and the scripts
    of the layer folders (bench/*.py, ...), by the names they are imported with."""
    layers = {}
    for path in files:
        layer = layer_of(path)
        if layer is None:
            continue
        parts = path.split("/")
        if parts[0] == "python" and len(parts) > 2 and parts[1] == "pbdval":
            layers["pbdval"] = layer
        elif len(parts) == 2 and parts[1].endswith(".py"):
            layers[parts[1][:-3]] = layer
    return layers


def upward_imports(files: dict[str, str]) -> list[Reach]:
    """Every import, in a Python file of a layer folder, of a module of a higher layer."""
    modules = python_module_layers(files)
    found = []
    for path, text in files.items():
        source = layer_of(path)
        if source is None:
            continue
        for node in ast.walk(ast.parse(text, filename=path)):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            for name in names:
                target = modules.get(name.split(".", 1)[0])
                if target is not None and target > source:
                    found.append(Reach(f"{path}:{node.lineno}", f"import {name}", source, target))
    return found


def test_the_layer_rules_find_an_upward_include_link_and_import() -> None:
    headers = {"pbd/include/pbd/model/world.h": '#include <vector>\n#include "pbd/core.h"\n'
                                                '#include <validation/metrics.h>\n',
               "pbd/include/pbd/core.h": "", "validation/metrics.h": '#include "adapters/engine.h"\n',
               "adapters/engine.h": '#include "pbdval/build_info.h"\n'}  # generated: not a file here
    assert [str(r) for r in upward_includes(headers)] == [
        'pbd/include/pbd/model/world.h:3: #include "validation/metrics.h" (pbd uses validation, a higher layer)']
    cmake = {"adapters/CMakeLists.txt": "add_library(engine STATIC e.cpp)\n"
                                        "target_link_libraries(engine PUBLIC pbd  # the library\n  checks)\n",
             "pbd/CMakeLists.txt": "add_library(pbd STATIC x.cpp)\ntarget_link_libraries(pbd PUBLIC Eigen3::Eigen)\n",
             "validation/CMakeLists.txt": "add_library(checks STATIC c.cpp)\ntarget_link_libraries(checks engine)\n"}
    assert [r.what for r in upward_links(cmake)] == ["engine links checks"]
    python = {"python/pbdval/api.py": "import bench_step\nfrom pbdval import protocol\n",
              "python/pbdval/protocol.py": "", "bench/bench_step.py": "import pbdval\n",
              "adapters/host.py": "from pbdval.protocol import read\n"}
    assert sorted(r.where for r in upward_imports(python)) == ["adapters/host.py:1", "python/pbdval/api.py:1"]


def test_no_cpp_include_reaches_a_higher_layer() -> None:
    files = {relative(p): p.read_text(encoding="utf-8")
             for p in repository_files("*.cpp", "*.cc", "*.h", "*.hpp")}
    found = upward_includes(files)
    assert found == [], "\n".join(map(str, found))


def test_no_cmake_target_links_a_target_of_a_higher_layer() -> None:
    files = {relative(p): p.read_text(encoding="utf-8") for p in repository_files("*CMakeLists.txt", "*.cmake")}
    found = upward_links(files)
    assert found == [], "\n".join(map(str, found))


def test_no_python_module_imports_a_module_of_a_higher_layer() -> None:
    files = {relative(p): p.read_text(encoding="utf-8") for p in repository_files("*.py")}
    found = upward_imports(files)
    assert found == [], "\n".join(map(str, found))
