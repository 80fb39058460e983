"""What every Python benchmark records beside its numbers (docs/benchmarks.md: results carry
their machine), and where it writes them: bench/results/<host>/<kind>-<UTC stamp>.json,
atomically."""

from __future__ import annotations

import datetime as dt
import os
import platform
import socket
from pathlib import Path
from typing import Any

from pbdval import protocol as pp

REPO = Path(__file__).resolve().parents[1]


def machine() -> dict[str, Any]:
    """When and where: UTC time, host, CPU model, cores, load average, Python version."""
    cpu = ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as cpuinfo:
            cpu = next(line.split(":", 1)[1].strip() for line in cpuinfo if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"created": dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "host": socket.gethostname(), "cpu": cpu, "cores": os.cpu_count(),
            "load_average": os.getloadavg(), "python": platform.python_version()}


def write_record(kind: str, document: dict[str, Any], out: Path | None = None) -> Path:
    """Writes `document` to `out`, by default bench/results/<host>/<kind>-<UTC stamp>.json, and
    says where."""
    path = out or REPO / "bench" / "results" / socket.gethostname() / (
        f"{kind}-" + dt.datetime.now(dt.UTC).strftime("%Y%m%dT%H%M%SZ") + ".json")
    path.parent.mkdir(parents=True, exist_ok=True)
    pp.write_json_atomically(path, document)
    print(f"wrote {path}")
    return path
