"""`python -m pbdval.external.newton --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as engines/newton.json runs it; `--serve --socket PATH`:
the persistent process (pbdval.protocol.serve_runs: Warp and Newton imported once, each run in
a forked child); `--catalogue` prints engines/newton.json."""

import sys

if sys.argv[1:] == ["--catalogue"]:
    from pbdval.external.newton.catalogue import catalogue_text

    sys.stdout.write(catalogue_text())
    sys.exit(0)

from pbdval.external.newton.engine import main

if sys.argv[1:2] == ["--serve"]:
    from pbdval.protocol import serve_runs

    sys.exit(serve_runs(sys.argv[2:], main, "NVIDIA Newton as a persistent pbdval external engine"))
sys.exit(main())
