"""The MakeHuman default rig mapped onto mura's H-Anim skeleton.

The rig (``rig.default.json``) places each bone's head and tail on the mesh by a
strategy — the mean of a joint cube's vertices (``CUBE``), one vertex (``VERTEX``) or the
mean of a few (``MEAN``) — so the joints follow the mesh. mura keeps fewer bones than the
rig's 163 (no face, tongue or twist bones; the face moves by morph targets) and has more
spine joints, so :data:`JOINTS` says, for every H-Anim joint, where it sits (a rig bone's
head, or a point between two heads) and which rig bones' skin weights it takes over.
Weights of rig bones no H-Anim joint names go to the joint whose region holds them
(:data:`ABSORBED`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from motor.body.makehuman.mesh import BaseMesh, vertex_group_ranges


@dataclass(frozen=True)
class JointSpec:
    """One H-Anim joint of the built avatar.

    ``at`` is a rig bone whose head is the joint, or ``(bone_a, bone_b, fraction)`` for a
    point between two heads; ``tip`` names a rig bone whose *tail* is the joint (finger
    ends); ``weights`` the rig bones whose skin weights the joint takes.
    """

    name: str
    parent: str | None
    at: str | tuple[str, str, float]
    weights: tuple[str, ...] = ()


def _side(prefix: str, suffix: str) -> list[JointSpec]:
    """The joints of one side (``l``/``r``), rig bones with suffix ``.L``/``.R``."""
    s = suffix

    def finger(name: str, digit: int, parent: str, first: int = 1) -> list[JointSpec]:
        joints = []
        for segment in range(first, 4):
            bone = f"finger{digit}-{segment - first + 1}{s}"
            joints.append(JointSpec(f"{prefix}_{name}{segment}", parent, bone, (bone,)))
            parent = f"{prefix}_{name}{segment}"
        return joints

    arm = [
        JointSpec(f"{prefix}_sternoclavicular", "vt1", f"clavicle{s}", (f"clavicle{s}", f"shoulder01{s}")),
        JointSpec(f"{prefix}_shoulder", f"{prefix}_sternoclavicular", f"upperarm01{s}", (f"upperarm01{s}", f"upperarm02{s}")),
        JointSpec(f"{prefix}_elbow", f"{prefix}_shoulder", f"lowerarm01{s}", (f"lowerarm01{s}", f"lowerarm02{s}")),
        JointSpec(f"{prefix}_wrist", f"{prefix}_elbow", f"wrist{s}", (f"wrist{s}", f"metacarpal1{s}", f"metacarpal2{s}")),
        *finger("thumb", 1, f"{prefix}_wrist"),
        *finger("index", 2, f"{prefix}_wrist"),
        *finger("middle", 3, f"{prefix}_wrist"),
        JointSpec(f"{prefix}_ring0", f"{prefix}_wrist", f"metacarpal3{s}", (f"metacarpal3{s}",)),
        *finger("ring", 4, f"{prefix}_ring0"),
        JointSpec(f"{prefix}_pinky0", f"{prefix}_wrist", f"metacarpal4{s}", (f"metacarpal4{s}",)),
        *finger("pinky", 5, f"{prefix}_pinky0"),
    ]
    leg = [
        JointSpec(f"{prefix}_hip", "humanoid_root", f"upperleg01{s}", (f"upperleg01{s}", f"upperleg02{s}")),
        JointSpec(f"{prefix}_knee", f"{prefix}_hip", f"lowerleg01{s}", (f"lowerleg01{s}", f"lowerleg02{s}")),
        JointSpec(f"{prefix}_ankle", f"{prefix}_knee", f"foot{s}", (f"foot{s}",)),
        JointSpec(
            f"{prefix}_metatarsal", f"{prefix}_ankle", f"toe3-1{s}",
            tuple(f"toe{t}-{k}{s}" for t in range(1, 6) for k in range(1, 4) if not (t == 1 and k == 3)),
        ),  # fmt: skip
    ]
    eye = [JointSpec(f"{prefix}_eyeball_joint", "skullbase", f"eye{s}", (f"eye{s}",))]
    return arm + leg + eye


#: The built avatar's joints, parents first: H-Anim spine and head, arms with full hands,
#: legs and eyes.
JOINTS: tuple[JointSpec, ...] = (
    JointSpec("humanoid_root", None, "spine05", ("root", "spine05", "pelvis.L", "pelvis.R")),
    JointSpec("sacroiliac", "humanoid_root", ("spine05", "spine04", 0.4)),
    JointSpec("vl5", "sacroiliac", "spine04", ("spine04",)),
    JointSpec("vl3", "vl5", "spine03", ("spine03",)),
    JointSpec("vl1", "vl3", "spine02", ("spine02",)),
    JointSpec("vt10", "vl1", ("spine02", "spine01", 0.5)),
    JointSpec("vt6", "vt10", "spine01", ("spine01", "breast.L", "breast.R")),
    JointSpec("vt1", "vt6", ("spine01", "neck01", 0.5)),
    JointSpec("vc7", "vt1", "neck01", ("neck01",)),
    JointSpec("vc4", "vc7", "neck02", ("neck02", "neck03")),
    JointSpec("skullbase", "vc4", "head", ("head",)),
    *_side("l", ".L"),
    *_side("r", ".R"),
)

#: Rig bone name prefixes whose weights go to the skull base: the face, jaw and tongue
#: bones (the face moves by morph targets instead).
ABSORBED: dict[str, tuple[str, ...]] = {
    "skullbase": ("jaw", "levator", "oris", "oculi", "orbicularis", "risorius", "special", "temporalis", "tongue"),
}

#: Finger ends: H-Anim has no joint there, but locations and volumes need them.
TIPS: dict[str, str] = {
    f"{prefix}_{name}": f"finger{digit}-3{s}"
    for prefix, s in (("l", ".L"), ("r", ".R"))
    for name, digit in (("thumb", 1), ("index", 2), ("middle", 3), ("ring", 4), ("pinky", 5))
}


class RigError(ValueError):
    """The rig or weights do not fit the mesh or the mapping."""


def bone_point(spec: dict, mesh: BaseMesh, groups: dict) -> np.ndarray:
    """A bone end's position from its placement strategy."""
    strategy = spec.get("strategy")
    if strategy == "CUBE":
        return mesh.positions[vertex_group_ranges(groups, spec["cube_name"])].mean(axis=0)
    if strategy == "VERTEX":
        return mesh.positions[int(spec["vertex_index"])]
    if strategy == "MEAN":
        return mesh.positions[np.asarray(spec["vertex_indices"], dtype=int)].mean(axis=0)
    raise RigError(f"unknown bone placement strategy {strategy!r}")


@dataclass(frozen=True, eq=False)
class MappedRig:
    """The rig on the mesh, in mura's joints.

    ``names``/``parents`` parents first; ``positions (J, 3)`` joint positions on the
    unposed mesh (metres); ``tips`` finger name (``l_index``) -> fingertip position;
    ``weights (V, J)`` skin weights per mesh vertex, rows summing to 1 where any.
    """

    names: tuple[str, ...]
    parents: np.ndarray
    positions: np.ndarray
    tips: dict[str, np.ndarray]
    weights: np.ndarray


def map_rig(rig: dict, weights: dict, mesh: BaseMesh, groups: dict) -> MappedRig:
    """Place mura's joints on the mesh and merge the rig's skin weights onto them."""
    heads = {name: bone_point(bone["head"], mesh, groups) for name, bone in rig.items()}
    tails = {name: bone_point(bone["tail"], mesh, groups) for name, bone in rig.items()}
    names = tuple(joint.name for joint in JOINTS)
    parents = np.array([-1 if j.parent is None else names.index(j.parent) for j in JOINTS])
    positions = np.array([_position(joint.at, heads) for joint in JOINTS])
    owner = {bone: joint.name for joint in JOINTS for bone in joint.weights}
    for joint, prefixes in ABSORBED.items():
        for bone in rig:
            if bone not in owner and bone.startswith(prefixes):
                owner[bone] = joint
    unowned = sorted(bone for bone, pairs in weights.items() if pairs and bone not in owner)
    if unowned:
        raise RigError(f"rig bones with skin weights but no H-Anim joint: {', '.join(unowned)}")
    matrix = np.zeros((len(mesh.positions), len(names)))
    for bone, pairs in weights.items():
        if not pairs:
            continue
        table = np.asarray(pairs, dtype=float)
        np.add.at(matrix[:, names.index(owner[bone])], table[:, 0].astype(int), table[:, 1])
    totals = matrix.sum(axis=1, keepdims=True)
    matrix = np.divide(matrix, totals, out=np.zeros_like(matrix), where=totals > 0)
    return MappedRig(names, parents, positions, {finger: tails[bone] for finger, bone in TIPS.items()}, matrix)


def _position(at: str | tuple[str, str, float], heads: dict[str, np.ndarray]) -> np.ndarray:
    if isinstance(at, str):
        return heads[at]
    first, second, fraction = at
    return heads[first] + fraction * (heads[second] - heads[first])
