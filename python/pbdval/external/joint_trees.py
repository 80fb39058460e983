"""The spanning forest of a scene's joints, for the external engines in reduced coordinates
(DART's skeletons, Newton's articulations): which joint becomes a tree joint (parent → child)
and which closes a kinematic loop. Standard library only: the feature checks run it without
loading a simulator.

The scene's joints form a graph over its bodies, every static body one node (the world). Joints
are taken in scene order: a joint whose bodies are already connected closes a loop; any other
joins two trees. Each tree is then oriented from the world (trees holding a static body) or,
for a tree of dynamic bodies only, from its first body in scene order, which gets a free joint.
A joint is `flipped` when its body1 is the child: the engine then swaps what the joint fixes in
its parent and in its child (a hinge's or slider's axis changes sign only; a universal joint's
axes change roles).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from pbdval import protocol as pp

#: The node of every static body (and of a joint's missing body).
WORLD = -1


@dataclass(frozen=True)
class TreeJoint:
    joint: int  # index into scene.joints
    parent: int  # body index (scene order), or WORLD
    child: int  # body index
    flipped: bool  # body1 is the child


@dataclass
class Forest:
    #: Dynamic bodies in an order in which every parent comes before its children.
    order: list[int] = field(default_factory=list)
    #: child body index → the tree joint that carries it; a dynamic body without one is a free root.
    parent_joint: dict[int, TreeJoint] = field(default_factory=dict)
    #: indices (into scene.joints) of the joints that close a loop.
    loops: list[int] = field(default_factory=list)

    def free_roots(self) -> list[int]:
        return [b for b in self.order if b not in self.parent_joint]


def plan_forest(scene: pp.ResolvedScene, tree_joint_types: Iterable[str]) -> Forest:
    """The forest of the joints whose type is in `tree_joint_types` (the others are ignored)."""
    types = set(tree_joint_types)
    index = {b.id: b.index for b in scene.bodies}
    dynamic = {b.index for b in scene.bodies if b.dynamic}

    def node(body_id: int | None) -> int:
        if body_id is None:
            return WORLD
        i = index[body_id]
        return i if i in dynamic else WORLD

    root = {n: n for n in [WORLD, *sorted(dynamic)]}

    def find(x: int) -> int:
        while root[x] != x:
            root[x] = root[root[x]]
            x = root[x]
        return x

    forest = Forest()
    edges: dict[int, list[tuple[int, int]]] = {n: [] for n in root}  # node → (joint, other node)
    for k, j in enumerate(scene.joints):
        if j.type not in types:
            continue
        a, b = node(j.body1), node(j.body2)
        if a == b == WORLD:
            continue  # joins two static bodies: nothing moves
        if find(a) == find(b):
            forest.loops.append(k)
            continue
        root[find(a)] = find(b)
        edges[a].append((k, b))
        edges[b].append((k, a))

    seen: set[int] = set()

    def grow(start: int) -> None:
        queue = [start]
        seen.add(start)
        while queue:
            parent = queue.pop(0)
            for k, child in sorted(edges[parent]):
                if child in seen:
                    continue
                seen.add(child)
                j = scene.joints[k]
                forest.parent_joint[child] = TreeJoint(k, parent, child, flipped=node(j.body1) == child)
                forest.order.append(child)
                queue.append(child)

    grow(WORLD)
    for b in sorted(dynamic):
        if b not in seen:
            forest.order.append(b)
            grow(b)
    return forest


def loop_messages(scene: pp.ResolvedScene, forest: Forest, engine: str) -> list[str]:
    """The unsupported messages of the loop-closing joints (the phrase the feature checks know)."""
    return [f"{scene.joints[k].json_path}: joint {scene.joints[k].type} closes a kinematic loop "
            f"({engine} builds trees of joints; a loop-closing constraint is not mapped)"
            for k in forest.loops]
