"""pybullet as an external engine (docs/external-engines.md#pybullet): `engine` builds and runs a
scene in maximal coordinates, `multibody` in reduced coordinates (methods pybullet.multibody.*),
`materials` turns per-pair friction and restitution into per-body factors, `deformables` maps
cloth and solids to soft bodies. Run as `python -m pbdval.external.pybullet` (__main__.py).
"""
