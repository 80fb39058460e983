"""`python -m pbdval.external.drake --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/drake.json runs it.
`python -m pbdval.external.drake --serve --socket PATH`: the persistent process that serves many
runs, each in a forked child (the catalogue's `serve`; pbdval.protocol.serve_runs).
`python -m pbdval.external.drake --catalogue` prints that catalogue entry (catalogue.py)."""

import sys

if sys.argv[1:] == ["--catalogue"]:
    from pbdval.external.drake.catalogue import catalogue_text

    sys.stdout.write(catalogue_text())
    sys.exit(0)

from pbdval.external.drake.engine import main

if sys.argv[1:2] == ["--serve"]:
    from pbdval.protocol import serve_runs

    sys.exit(serve_runs(sys.argv[2:], main, "Drake as a persistent pbdval external engine"))
sys.exit(main())
