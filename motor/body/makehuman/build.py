"""Assembling the default avatar from the MakeHuman assets: skinned body and definition.

Steps (each deterministic, so the same wheel gives byte-identical files):

1. read the base mesh, its vertex groups, the default rig and its skin weights, and the
   52 face units (ARKit blendshape names);
2. place mura's H-Anim joints on the mesh and merge the rig's weights onto them
   (:mod:`.rig`), then re-pose mesh and joints into mura's rest pose (:mod:`.repose`);
3. keep the body and the helper geometry a face needs (eyes, eyelashes, teeth, tongue,
   a hair cap), colour it (skin; lips and nails from the assets' UV masks; eyebrows and
   irises painted by position), and turn the face units into sparse morph targets;
4. measure the avatar definition on the re-posed skin (:mod:`motor.body.definition`).
"""

from __future__ import annotations

import io
from dataclasses import dataclass

import numpy as np

from motor.body.definition import Body, Definition, Skin, derive_definition
from motor.body.makehuman import assets as mh
from motor.body.makehuman.mesh import BaseMesh, read_obj, read_target
from motor.body.makehuman.repose import repose
from motor.body.makehuman.rig import map_rig
from motor.body.skinned import MorphTarget, Part, SkinnedBody, strongest_influences, vertex_normals

NAME = "makehuman"
DESCRIPTION = (
    "Skinned human built at set-up from the MakeHuman community's CC0 base mesh (hm08), default rig, "
    "skin weights and Face Units, re-posed into mura's rest pose."
)

#: Face groups kept, with their part name, colour (linear RGBA) and roughness.
PARTS: tuple[tuple[str, tuple[str, ...], tuple[float, float, float, float], float], ...] = (
    ("skin", ("body",), (1.0, 1.0, 1.0, 1.0), 0.66),
    ("eyes", ("helper-l-eye", "helper-r-eye"), (0.92, 0.92, 0.90, 1.0), 0.15),
    ("teeth", ("helper-upper-teeth", "helper-lower-teeth"), (0.85, 0.83, 0.76, 1.0), 0.3),
    ("tongue", ("helper-tongue",), (0.62, 0.26, 0.26, 1.0), 0.5),
    ("eyelashes", ("helper-l-eyelashes", "helper-r-eyelashes"), (0.05, 0.04, 0.035, 1.0), 0.9),
)
#: Vertex-colour tints from the assets' UV masks: mask file and tint (multiplies the skin).
MASKS: tuple[tuple[str, tuple[float, float, float]], ...] = (
    ("mpfb_lips.jpg", (0.78, 0.52, 0.52)),
    ("mpfb_fingernails.jpg", (1.12, 1.08, 1.08)),
)
SKIN = (0.80, 0.56, 0.44)
EYEBROW = (0.16, 0.12, 0.10)
HAIR = (0.13, 0.085, 0.055)
#: Clothes painted by skin weight: colour and the joints whose weights it follows.
CLOTHES: tuple[tuple[tuple[float, float, float], tuple[str, ...]], ...] = (
    ((0.17, 0.17, 0.19), ("humanoid_root", "l_hip", "r_hip", "l_knee", "r_knee")),
    ((0.13, 0.22, 0.36), ("sacroiliac", "vl5", "vl3", "vl1", "vt10", "vt6", "vt1", "l_sternoclavicular", "r_sternoclavicular")),
    ((0.09, 0.07, 0.06), ("l_ankle", "r_ankle", "l_metatarsal", "r_metatarsal")),
)
IRIS = (0.12, 0.20, 0.28)
PUPIL = (0.02, 0.02, 0.02)


@dataclass(frozen=True)
class BuiltAvatar:
    """The skinned body, its definition, and the provenance of every asset used."""

    body: SkinnedBody
    definition: Definition
    provenance: tuple[mh.Provenance, ...]


def build_makehuman(wheel_assets: mh.Assets) -> BuiltAvatar:
    """Build the default avatar from the wheel's assets (see the module docstring)."""
    mesh = read_obj(wheel_assets.text(mh.BASE_MESH))
    groups = wheel_assets.json(mh.VERTEX_GROUPS)
    rig = map_rig(wheel_assets.json(mh.RIG), wheel_assets.json(mh.WEIGHTS)["weights"], mesh, groups)
    posed = repose(rig, mesh.positions)
    root = posed.positions[0]
    keep, parts = _kept(mesh)
    remap = np.full(len(mesh.positions), -1)
    remap[keep] = np.arange(len(keep))
    vertices = posed.vertices[keep] - root
    body_vertices = remap[np.unique(mesh.group_triangles("body"))]
    floor = float(-vertices[body_vertices, 1].min())
    joints, weights = strongest_influences(rig.weights[keep])
    triangles = np.concatenate([remap[t] for _, t in parts])
    colors = _colors(wheel_assets, mesh, keep, vertices, posed, rig, root, remap)
    body = SkinnedBody(
        name=NAME,
        joint_names=rig.names,
        parents=tuple(int(p) for p in rig.parents),
        offsets=_offsets(posed.positions, rig.parents),
        root_height=floor,
        positions=vertices,
        normals=vertex_normals(vertices, triangles),
        colors=colors,
        joints=joints,
        weights=weights,
        parts=tuple(Part(name, remap[t], color, rough) for (name, t), (_, _, color, rough) in zip(parts, PARTS)),
        morph_targets=_face_units(wheel_assets, len(mesh.positions), remap),
    )
    owner = np.argmax(rig.weights[keep][body_vertices], axis=1)
    definition = derive_definition(Body(
        name=NAME,
        joint_names=rig.names,
        parents=body.parents,
        positions=posed.positions - root,
        floor=floor,
        tips={finger: tip - root for finger, tip in posed.tips.items()},
        crown=float(vertices[body_vertices, 1].max()),
        skin=Skin(vertices[body_vertices], owner),
        description=DESCRIPTION,
    ))  # fmt: skip
    provenance = tuple(wheel_assets.check_licences())
    credits = tuple(f"{p.path} ({p.licence}): {p.evidence}" for p in provenance)
    body = SkinnedBody(**{**body.__dict__, "credits": (f"{mh.WHEEL} from PyPI, sha256 {mh.SHA256}", *credits)})
    return BuiltAvatar(body, definition, provenance)


def _offsets(positions: np.ndarray, parents: np.ndarray) -> np.ndarray:
    offsets = positions.copy()
    offsets[1:] -= positions[parents[1:]]
    offsets[0] = 0.0
    return offsets


def _kept(mesh: BaseMesh) -> tuple[np.ndarray, list[tuple[str, np.ndarray]]]:
    """Vertices kept (ascending original indices) and each part's triangles (original indices)."""
    parts = [(name, mesh.group_triangles(*groups)) for name, groups, _, _ in PARTS]
    for name, triangles in parts:
        if len(triangles) == 0:
            raise ValueError(f"the base mesh has no triangles for the {name} part")
    keep = np.unique(np.concatenate([t.ravel() for _, t in parts]))
    return keep, parts


def _mask(wheel_assets: mh.Assets, member: str, uvs: np.ndarray) -> np.ndarray:
    """A UV mask (0–1) sampled at per-vertex texture coordinates."""
    from PIL import Image  # only the build decodes JPEG

    data = wheel_assets._zip.read(mh.MPFB + "textures/" + member)
    wheel_assets.used.append(mh.MPFB + "textures/" + member)
    image = np.asarray(Image.open(io.BytesIO(data)).convert("L"), dtype=float) / 255.0
    rows = np.clip(((1.0 - uvs[:, 1]) * image.shape[0]).astype(int), 0, image.shape[0] - 1)
    columns = np.clip((uvs[:, 0] * image.shape[1]).astype(int), 0, image.shape[1] - 1)
    return image[rows, columns]


def _colors(wheel_assets, mesh, keep, vertices, posed, rig, root, remap) -> np.ndarray:
    names = rig.names
    colors = np.ones((len(keep), 4))
    colors[:, :3] = SKIN
    for member, tint in MASKS:
        amount = _mask(wheel_assets, member, mesh.uvs[keep])[:, None]
        colors[:, :3] *= 1.0 + amount * (np.array(tint) - 1.0)
    body = np.zeros(len(keep), dtype=bool)
    body[remap[np.unique(mesh.group_triangles("body"))]] = True
    eyes = remap[np.unique(mesh.group_triangles("helper-l-eye", "helper-r-eye"))]
    index = {name: i for i, name in enumerate(names)}
    for side in ("l", "r"):
        centre = posed.positions[index[f"{side}_eyeball_joint"]] - root
        own = eyes[np.sign(vertices[eyes, 0]) == (1.0 if side == "l" else -1.0)]
        radius = float(np.median(np.linalg.norm(vertices[own] - centre, axis=1)))
        _paint_iris(colors, vertices, own, centre)
        _paint_eyebrow(colors, vertices, body, centre, radius, side)
    eyes_y = float(np.mean([posed.positions[index[f"{s}_eyeball_joint"]][1] for s in ("l", "r")]) - root[1])
    _paint_hair(colors, vertices, body, rig.weights[keep][:, index["skullbase"]], eyes_y)
    _paint_clothes(colors, vertices, body, rig.weights[keep], index, posed.positions - root)
    return colors


def _paint_hair(colors: np.ndarray, vertices: np.ndarray, body: np.ndarray, head: np.ndarray, eyes_y: float) -> None:
    """Short hair painted on the scalp: above a hairline that runs over the forehead,
    above the ears and down the back of the head."""
    x, y, z = vertices[:, 0], vertices[:, 1], vertices[:, 2]
    front = z.max(where=body & (head > 0.5), initial=-np.inf)
    depth = np.clip((front - z) / 0.16, 0.0, 1.0)  # 0 at the face, 1 at the back of the head
    hairline = eyes_y + 0.062 - 0.09 * depth**1.5 - 0.01 * np.clip(np.abs(x) / 0.06, 0.0, 1.0)
    hair = body & (head > 0.5) & (y > hairline)
    colors[hair, :3] = HAIR


def _paint_clothes(colors: np.ndarray, vertices: np.ndarray, body: np.ndarray, weights: np.ndarray, index: dict, joints: np.ndarray) -> None:
    """A shirt with short sleeves, trousers and shoes, blended by skin weight so their
    edges follow the body's joints smoothly."""
    for colour, names in CLOTHES:
        amount = np.clip(1.6 * weights[:, [index[n] for n in names]].sum(axis=1) - 0.3, 0.0, 1.0)
        if names[0] == "sacroiliac":
            for side in ("l", "r"):  # sleeves: the upper half of the upper arm
                shoulder, elbow = joints[index[f"{side}_shoulder"]], joints[index[f"{side}_elbow"]]
                ramp = np.clip((vertices[:, 1] - (elbow[1] + 0.45 * (shoulder[1] - elbow[1]))) / 0.02, 0.0, 1.0)
                amount = np.maximum(amount, np.clip(weights[:, index[f"{side}_shoulder"]] * 1.5, 0, 1) * ramp)
        amount = np.where(body, amount, 0.0)[:, None]
        colors[:, :3] = colors[:, :3] * (1.0 - amount) + np.array(colour) * amount


def _paint_iris(colors: np.ndarray, vertices: np.ndarray, eye: np.ndarray, centre: np.ndarray) -> None:
    """Iris and pupil: eye vertices within 28° (iris) and 12° (pupil) of straight ahead."""
    direction = vertices[eye] - centre
    cosine = direction[:, 2] / np.linalg.norm(direction, axis=1)
    colors[eye[cosine > np.cos(np.radians(28.0))], :3] = IRIS
    colors[eye[cosine > np.cos(np.radians(12.0))], :3] = PUPIL


def _paint_eyebrow(colors: np.ndarray, vertices: np.ndarray, body: np.ndarray, centre: np.ndarray, radius: float, side: str) -> None:
    """A painted eyebrow: an arched band above the eye, thinning toward its outer end."""
    sign = 1.0 if side == "l" else -1.0
    across = sign * (vertices[:, 0] - centre[0]) / radius  # outward positive
    up = (vertices[:, 1] - centre[1]) / radius
    arch = 1.65 + 0.28 * across - 0.22 * across**2
    half = 0.30 - 0.06 * np.clip(across, 0.0, None)
    band = body & (across > -1.05) & (across < 1.75) & (np.abs(up - arch) < half) & (vertices[:, 2] > centre[2])
    colors[band, :3] = EYEBROW


def _face_units(wheel_assets: mh.Assets, vertex_count: int, remap: np.ndarray) -> tuple[MorphTarget, ...]:
    targets = []
    for name in wheel_assets.face_units():
        member = mh.FACE_UNITS + name + ".target"
        indices, offsets = read_target(wheel_assets.text(member), vertex_count, member)
        kept = remap[indices] >= 0
        targets.append(MorphTarget(name, remap[indices[kept]], offsets[kept]))
    return tuple(targets)
