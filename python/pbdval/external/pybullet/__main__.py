"""`python -m pbdval.external.pybullet --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/pybullet.json runs it.
`python -m pbdval.external.pybullet --serve --socket PATH`: the persistent process that serves
many runs, each in a forked child (the catalogue's `serve`; pbdval.protocol.serve_runs)."""

import os
import sys
from typing import Any

# pybullet's C code prints a "pybullet build time" banner to file descriptor 1 when it is
# imported: an engine keeps standard output free of anything but data, so from here on file
# descriptor 1 is standard error (before the import below loads pybullet).
os.dup2(2, 1)

import pybullet as pb

from pbdval.external.pybullet.engine import main


def connect_ahead() -> None:
    """Serve mode: the next run's child opens its DIRECT physics client while it waits for its
    run (pb.connect costs 20-40 ms on its own), and the run's first pb.connect(pb.DIRECT) gets
    that client: the same fresh client the single-shot run opens, opened earlier. Served and
    single-shot runs are compared bit for bit (tests/python/test_serve.py,
    ServedShippedEngines in tests/validation/test_external_engine.cpp)."""
    opened = [pb.connect(pb.DIRECT)]
    connect = pb.connect

    def connect_or_take_the_open_client(*args: Any, **kwargs: Any) -> Any:
        if opened and args == (pb.DIRECT,) and not kwargs:
            return opened.pop()
        return connect(*args, **kwargs)

    pb.connect = connect_or_take_the_open_client


if sys.argv[1:2] == ["--serve"]:
    from pbdval.external.pybullet import multibody  # noqa: F401 -- once, not in each run's child
    from pbdval.protocol import serve_runs

    # A served run's output goes to its standard error too, as above.
    sys.exit(serve_runs(sys.argv[2:], main, "pybullet as a persistent pbdval external engine",
                        stdout_to_stderr=True, prepare=connect_ahead))
sys.exit(main())
