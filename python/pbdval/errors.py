"""The exceptions of `import pbdval` (raised by the C++ core and the Python parts alike)."""

from __future__ import annotations

import subprocess
from collections.abc import Sequence
from typing import Any


class PbdvalError(Exception):
    """Base class of every pbdval error."""


class ArgumentError(PbdvalError, ValueError):
    """An argument outside its documented domain: a NaN, zero or negative duration, sample
    interval or wall-time limit, a step count beyond the cap, an empty or non-finite trajectory
    time, an array of the wrong shape, dtype or memory layout, an object of the wrong type, an
    unknown parameter or value. The message names the argument and what was expected."""


class SceneError(PbdvalError, ValueError):
    """A scene file that cannot be loaded: the file, the JSON path and what was expected.

    ``str(error)`` is ``"FILE: JSON.PATH: MESSAGE"``, the same text the pbdval command prints.
    """

    def __init__(self, file: str, json_path: str, message: str) -> None:
        self.file = file
        self.json_path = json_path
        self.message = message
        parts = [p for p in (file, json_path, message) if p]
        super().__init__(": ".join(parts))

    def __reduce__(self) -> tuple[type[SceneError], tuple[str, str, str]]:
        return (SceneError, (self.file, self.json_path, self.message))


class EngineError(PbdvalError, RuntimeError):
    """An engine failed (rejected the model, reported an error while stepping)."""


class DivergenceError(EngineError):
    """The run became non-finite or blew up (positions beyond 1e6 m, speeds beyond 1e6 m/s)."""


class UnsupportedError(PbdvalError, ValueError):
    """The engine/method cannot represent a feature of the scene; the message names each one."""


class ResultsError(PbdvalError, ValueError):
    """A folder that is not a pbdval results folder, or a results.json that cannot be read."""


class CommandError(PbdvalError, subprocess.CalledProcessError):
    """The pbdval command itself failed (bad usage, unreadable input, an --out that another
    pbdval command is writing or that holds another plan's results, a signal): nothing was
    written. ``returncode``, ``cmd`` and ``stderr`` as in subprocess.CalledProcessError (it is
    one); ``str(error)`` ends with the command's own message."""

    def __init__(self, returncode: int, cmd: Sequence[str], output: str | None = None,
                 stderr: str | None = None) -> None:
        subprocess.CalledProcessError.__init__(self, returncode, list(cmd), output, stderr)

    def __str__(self) -> str:
        message = (self.stderr or "").strip().splitlines()
        detail = message[-1] if message else "no message"
        return f"{' '.join(self.cmd[:2])} exited with status {self.returncode}: {detail}"

    def __reduce__(self) -> tuple[type[CommandError], tuple[Any, ...]]:
        return (CommandError, (self.returncode, self.cmd, self.output, self.stderr))


class BuildMissingError(PbdvalError, ImportError):
    """The C++ core (pbdval._core) or the pbdval binary has not been built yet."""
