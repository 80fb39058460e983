"""pbdval's external engines written in Python, one subpackage each, run by the engine catalogue
(engines/*.json) as `<venv python> -m pbdval.external.<engine>` through the process protocol
(pbdval.protocol, docs/external-engines.md):

* pbdval.external.pybullet: Bullet 3 through pybullet (catalogue name `pybullet`);
* pbdval.external.mujoco: MuJoCo 4 through its Python package (catalogue name `mujoco-python`);
* pbdval.external.dart: DART through dartpy (catalogue name `dart`, docs/engine-dart.md);
* pbdval.external.newton: NVIDIA Newton on Warp's CPU kernels (catalogue name `newton`,
  docs/engine-newton.md), run only when named.

pbdval.external.joint_trees plans the spanning forest of a scene's joints for the engines in
reduced coordinates (dart, newton); standard library only.

Importing this package imports no engine: each subpackage's modules import their simulator.
(Not `pbdval.engines`: that name is the API's function listing every engine, which a subpackage
of the same name would replace once imported.)
"""
