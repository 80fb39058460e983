"""`python -m pbdval.external.dart --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as engines/dart.json runs it; `--serve --socket PATH`:
the persistent process (pbdval.protocol.serve_runs); `--catalogue` prints engines/dart.json."""

import sys

if sys.argv[1:] == ["--catalogue"]:
    from pbdval.external.dart.catalogue import catalogue_text

    sys.stdout.write(catalogue_text())
    sys.exit(0)

from pbdval.external.dart.engine import main

if sys.argv[1:2] == ["--serve"]:
    from pbdval.protocol import serve_runs

    sys.exit(serve_runs(sys.argv[2:], main, "DART (dartpy) as a persistent pbdval external engine"))
sys.exit(main())
