"""NVIDIA Newton (on Warp's CPU kernels) as a pbdval external engine (catalogue name `newton`):
`python -m pbdval.external.newton`. Importing this package imports nothing else; engine.py loads
warp and newton (docs/engine-newton.md)."""
