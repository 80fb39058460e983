"""`python -m pbdval.external.pybullet --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/pybullet.json runs it.
`python -m pbdval.external.pybullet --serve --socket PATH`: the persistent process that serves
many runs, each in a forked child (the catalogue's `serve`; pbdval.protocol.serve_runs)."""

import os
import sys

# pybullet's C code prints a "pybullet build time" banner to file descriptor 1 when it is
# imported: an engine keeps standard output free of anything but data, so from here on file
# descriptor 1 is standard error (before the import below loads pybullet).
os.dup2(2, 1)

from pbdval.external.pybullet.engine import main

if sys.argv[1:2] == ["--serve"]:
    from pbdval.protocol import serve_runs

    # A served run's output goes to its standard error too, as above.
    sys.exit(serve_runs(sys.argv[2:], main, "pybullet as a persistent pbdval external engine",
                        stdout_to_stderr=True))
sys.exit(main())
