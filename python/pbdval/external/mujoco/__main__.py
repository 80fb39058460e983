"""`python -m pbdval.external.mujoco --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/mujoco-python.json runs it.
`python -m pbdval.external.mujoco --catalogue` prints that catalogue entry (catalogue.py)."""

import sys

if sys.argv[1:] == ["--catalogue"]:
    from pbdval.external.mujoco.catalogue import catalogue_text

    sys.stdout.write(catalogue_text())
    sys.exit(0)

from pbdval.external.mujoco.engine import main

sys.exit(main())
