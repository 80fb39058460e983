"""`python -m pbdval.external.pybullet --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/pybullet.json runs it.
`python -m pbdval.external.pybullet --serve --socket PATH`: the persistent process that serves
many runs, each in a forked child (the catalogue's `serve`; pbdval.protocol.serve_runs)."""

import os
import sys
from typing import Any

# One BLAS thread (before numpy is loaded: pybullet imports it): the engine's array operations
# are small, and OpenBLAS's thread pool costs the interpreter's start 40-45 ms of CPU and leaves
# threads spinning in the server every run's child is forked from
# (docs/benchmarks.md#fourth-pass). A value set in the environment is kept.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# pybullet's C code prints a "pybullet build time" banner to file descriptor 1 when it is
# imported: an engine keeps standard output free of anything but data, so from here on file
# descriptor 1 is standard error (before the import below loads pybullet).
os.dup2(2, 1)

import pybullet as pb

from pbdval.external.pybullet.engine import main


def connect_in_the_server() -> None:
    """Serve mode: the server opens one DIRECT physics client before it forks any run's child
    (pb.connect costs 20-40 ms of CPU on its own), and each child's first
    pb.connect(pb.DIRECT) gets its own copy of it, the fork's: a client as fresh as the one the
    single-shot run opens, since the server never uses it (pybullet's DIRECT client is in the
    process, without threads). Served and single-shot runs are compared bit for bit
    (tests/python/test_serve.py, ServedShippedEngines in
    tests/validation/test_external_engine.cpp)."""
    opened = pb.connect(pb.DIRECT)
    connect = pb.connect
    taken = [False]  # each child has its own copy, False when it is forked

    def connect_or_take_the_open_client(*args: Any, **kwargs: Any) -> Any:
        if not taken[0] and args == (pb.DIRECT,) and not kwargs:
            taken[0] = True
            return opened
        return connect(*args, **kwargs)

    pb.connect = connect_or_take_the_open_client


if sys.argv[1:2] == ["--serve"]:
    from pbdval.external.pybullet import multibody  # noqa: F401 -- once, not in each run's child
    from pbdval.protocol import serve_runs

    # A served run's output goes to its standard error too, as above.
    connect_in_the_server()
    sys.exit(serve_runs(sys.argv[2:], main, "pybullet as a persistent pbdval external engine",
                        stdout_to_stderr=True))
sys.exit(main())
