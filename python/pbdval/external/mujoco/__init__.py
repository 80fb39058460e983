"""MuJoCo 4 (the `mujoco` Python package) as an external engine, catalogue name `mujoco-python`
(docs/external-engines.md#mujoco-python): `engine` builds the model with MjSpec and runs it,
`contact_law` maps restitution to solref, `flexes` maps cloth and solids to flexes. Run as
`python -m pbdval.external.mujoco` (__main__.py).
"""
