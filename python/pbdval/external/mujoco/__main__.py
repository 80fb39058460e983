"""`python -m pbdval.external.mujoco --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/mujoco-python.json runs it.
`python -m pbdval.external.mujoco --serve --socket PATH`: the persistent process that serves
many runs, each in a forked child (the catalogue's `serve`; pbdval.protocol.serve_runs).
`python -m pbdval.external.mujoco --catalogue` prints that catalogue entry (catalogue.py)."""

import os
import sys

# One BLAS thread (before numpy is loaded): the engine's array operations are small, and
# OpenBLAS's thread pool costs the interpreter's start 40-45 ms of CPU and leaves threads
# spinning in the server every run's child is forked from (docs/benchmarks.md#fourth-pass).
# A value set in the environment is kept.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

if sys.argv[1:] == ["--catalogue"]:
    from pbdval.external.mujoco.catalogue import catalogue_text

    sys.stdout.write(catalogue_text())
    sys.exit(0)

from pbdval.external.mujoco.engine import main

if sys.argv[1:2] == ["--serve"]:
    from pbdval.protocol import serve_runs

    try:  # the model writer, imported by every run (engine.rigid_model): once, in the server
        from pbdval import _core  # noqa: F401
    except ImportError:
        pass  # each run reports it (engine.rigid_model)

    sys.exit(serve_runs(sys.argv[2:], main, "MuJoCo (Python) as a persistent pbdval external engine"))
sys.exit(main())
