"""pbdval's external engines written in Python, one subpackage each, run by the engine catalogue
(engines/*.json) as `<venv python> -m pbdval.engines.<engine>` through the process protocol
(pbdval.protocol, docs/external-engines.md):

* pbdval.engines.pybullet: Bullet 3 through pybullet (catalogue name `pybullet`);
* pbdval.engines.mujoco: MuJoCo 4 through its Python package (catalogue name `mujoco-python`).

Importing this package imports no engine: each subpackage's modules import their simulator.
"""
