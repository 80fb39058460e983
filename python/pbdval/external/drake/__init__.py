"""Drake's MultibodyPlant as a pbdval external engine (docs/engine-drake.md):
`python -m pbdval.external.drake --scene RESOLVED.json --out OUTDIR`."""
