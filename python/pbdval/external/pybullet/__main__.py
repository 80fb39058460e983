"""`python -m pbdval.external.pybullet --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/pybullet.json runs it."""

import os
import sys

# pybullet's C code prints a "pybullet build time" banner to file descriptor 1 when it is
# imported: an engine keeps standard output free of anything but data, so from here on file
# descriptor 1 is standard error (before the import below loads pybullet).
os.dup2(2, 1)

from pbdval.external.pybullet.engine import main  # noqa: E402

sys.exit(main())
