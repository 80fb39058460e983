"""`python -m pbdval.engines.mujoco --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/mujoco-python.json runs it."""

import sys

from pbdval.engines.mujoco.engine import main

sys.exit(main())
