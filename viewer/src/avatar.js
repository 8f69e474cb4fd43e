// Flesh on a bone tree: capsules along bones, spheres at joints, a palm per hand and a
// head with a simple face. Meshes are children of the bones, so posing the bones moves the
// body; eyeballs sit on the eyeball joints when the skeleton has them, so they turn with
// the gaze. root.userData.face.apply({jawOpen, eyeBlinkLeft, browInnerUp, …}) moves the
// face: mouth opening and shape, eyelids, eyebrows.
import {
  CapsuleGeometry,
  Group,
  Matrix4,
  Mesh,
  MeshStandardMaterial,
  SphereGeometry,
  Vector3,
} from 'three';
import { RoundedBoxGeometry } from 'three/addons/geometries/RoundedBoxGeometry.js';
import { fingerOf, isClothed, isEye, isHead, isTorso, isWrist, segmentRadius } from './body.js';
import { UNIT } from './skeleton.js';

const SKIN = new MeshStandardMaterial({ color: 0xe2b08f, roughness: 0.62, metalness: 0.0 });
const SHIRT = new MeshStandardMaterial({ color: 0x3d5a80, roughness: 0.8, metalness: 0.0 });
const EYES = new MeshStandardMaterial({ color: 0x1d1d24, roughness: 0.3 });
const SCLERA = new MeshStandardMaterial({ color: 0xf2efe8, roughness: 0.35 });
const LIPS = new MeshStandardMaterial({ color: 0x6e2f2a, roughness: 0.7 });
const HAIR = new MeshStandardMaterial({ color: 0x3b2a20, roughness: 0.9 });

const Y = new Vector3(0, 1, 0);
const TORSO_WIDTH = 1.35; // torso cross-section: wider than deep
const TORSO_DEPTH = 0.72;
const HEAD_RADIUS = 0.1; // metres
const PALM_THICKNESS = 0.028;

// Build the body for the bone tree under `root`; returns the number of meshes added.
export function buildAvatar(root) {
  const bones = [];
  root.traverse((node) => {
    if (node.isBone) bones.push(node);
  });
  let meshes = 0;
  const face = { parts: null, apply: (weights) => face.parts && applyFace(face.parts, weights) };
  root.userData.face = face;
  for (const bone of bones) {
    if (isEye(bone.name) || (bone.name === 'ENDSITE' && isEye(bone.parent?.name ?? ''))) {
      if (isEye(bone.name)) meshes += eyeball(bone);
      continue;
    }
    const children = bone.children.filter((child) => child.isBone && !isEye(child.name));
    for (const child of children) {
      bone.add(limb(bone.name, child));
      meshes += 1;
    }
    if (!isTorso(bone.name)) {
      bone.add(jointBall(bone));
      meshes += 1;
    }
    if (isWrist(bone.name)) {
      const palm = palmFor(bone);
      if (palm) {
        bone.add(palm);
        meshes += 1;
      }
    }
    if (isHead(bone.name) && !isHead(bone.parent?.name ?? '')) {
      const { group, parts } = head(bone);
      bone.add(group);
      face.parts = parts;
      meshes += 1;
    }
  }
  return meshes;
}

// An eyeball on an eyeball joint: white, with a dark iris toward +z (the joint's forward).
function eyeball(bone) {
  const r = HEAD_RADIUS * UNIT;
  const sclera = new Mesh(new SphereGeometry(r * 0.13, 16, 12), SCLERA);
  const iris = new Mesh(new SphereGeometry(r * 0.07, 12, 8), EYES);
  iris.position.set(0, 0, r * 0.09);
  sclera.add(iris);
  bone.add(sclera);
  return 1;
}

// Moves the capsule head's face parts for ARKit weights.
function applyFace(parts, w) {
  const get = (name) => w[name] ?? 0;
  const open = get('jawOpen');
  const round = Math.max(get('mouthPucker'), get('mouthFunnel'));
  const spread = Math.max((get('mouthSmileLeft') + get('mouthSmileRight')) / 2, (get('mouthStretchLeft') + get('mouthStretchRight')) / 2);
  parts.mouth.scale.set(1 + 0.5 * spread - 0.45 * round, 0.15 + 2.2 * open, 1);
  parts.lids.forEach((lid, k) => {
    const closed = get(k === 0 ? 'eyeBlinkLeft' : 'eyeBlinkRight');
    lid.visible = closed > 0.02;
    lid.scale.set(1, Math.max(closed, 0.02), 1);
  });
  parts.brows.forEach((brow, k) => {
    const side = k === 0 ? 'Left' : 'Right';
    const up = 0.6 * get('browInnerUp') + get(`browOuterUp${side}`) - get(`browDown${side}`);
    brow.position.y = brow.userData.y + up * parts.r * 0.12;
  });
}

function material(name) {
  return isClothed(name) ? SHIRT : SKIN;
}

// A capsule from the bone's origin to `child`'s origin, in the bone's frame.
function limb(name, child) {
  const offset = child.position.clone();
  const length = offset.length();
  const childName = child.name === 'ENDSITE' ? name : child.name;
  const radius = segmentRadius(name, childName) * UNIT;
  const mesh = new Mesh(new CapsuleGeometry(radius, Math.max(length, 1e-3), 6, 14), material(name));
  if (length > 1e-6) mesh.quaternion.setFromUnitVectors(Y, offset.clone().divideScalar(length));
  mesh.position.copy(offset).multiplyScalar(0.5);
  if (isTorso(name) && !/^[lr]_/.test(childName)) mesh.scale.set(TORSO_WIDTH, 1, TORSO_DEPTH);
  return mesh;
}

function jointBall(bone) {
  const parentName = bone.parent?.isBone ? bone.parent.name : bone.name;
  const radius = segmentRadius(parentName, bone.name === 'ENDSITE' ? parentName : bone.name) * UNIT * 1.04;
  const mesh = new Mesh(new SphereGeometry(radius, 14, 10), material(parentName));
  if (isTorso(parentName) && isTorso(bone.name)) mesh.scale.set(TORSO_WIDTH, 1, TORSO_DEPTH);
  return mesh;
}

// Knuckle positions (finger segment 1) in the wrist's rest frame.
function knuckles(wrist) {
  const found = [];
  wrist.traverse((bone) => {
    const finger = fingerOf(bone.name);
    if (!finger || finger.finger === 'thumb' || finger.segment !== 1) return;
    const position = new Vector3();
    for (let node = bone; node && node !== wrist; node = node.parent) position.add(node.position);
    found.push({ finger: finger.finger, position });
  });
  return found;
}

// A flat rounded box from the wrist to the knuckles, as wide as the knuckle row.
function palmFor(wrist) {
  const points = knuckles(wrist);
  if (points.length < 2) return null;
  const centre = points.reduce((sum, p) => sum.add(p.position), new Vector3()).divideScalar(points.length);
  const length = centre.length();
  if (length < 1e-6) return null;
  const along = centre.clone().divideScalar(length);
  const first = points.find((p) => p.finger === 'index') ?? points[0];
  const last = points.find((p) => p.finger === 'pinky') ?? points[points.length - 1];
  const spread = last.position.clone().sub(first.position);
  const across = spread.clone().sub(along.clone().multiplyScalar(spread.dot(along)));
  const width = across.length();
  if (width < 1e-6) return null;
  across.divideScalar(width);
  const normal = new Vector3().crossVectors(across, along).normalize();
  const fingerRadius = segmentRadius('l_index1', 'l_index2') * UNIT;
  const thickness = PALM_THICKNESS * UNIT;
  const geometry = new RoundedBoxGeometry(width + 2 * fingerRadius, length * 1.04, thickness, 3, thickness * 0.45);
  const mesh = new Mesh(geometry, SKIN);
  mesh.quaternion.setFromRotationMatrix(new Matrix4().makeBasis(across, along, normal));
  mesh.position.copy(centre).multiplyScalar(0.5);
  return mesh;
}

// A head above the skull base, with eyes (unless eyeball joints carry them), a nose, a
// mouth, eyelids and eyebrows, looking along +z (the avatar's front).
function head(skullbase) {
  const up = new Vector3();
  const child = skullbase.children.find((c) => c.isBone && !isEye(c.name));
  if (child && child.position.lengthSq() > 1e-12) up.copy(child.position).normalize();
  else up.copy(Y);
  const hasEyes = skullbase.children.some((c) => isEye(c.name));
  const r = HEAD_RADIUS * UNIT;
  const group = new Group();
  group.quaternion.setFromUnitVectors(Y, up);
  group.position.copy(up).multiplyScalar(r * 0.85);
  const skull = new Mesh(new SphereGeometry(r, 28, 20), SKIN);
  skull.scale.set(0.86, 1.12, 0.95);
  group.add(skull);
  const hair = new Mesh(new SphereGeometry(r * 1.02, 28, 14, 0, Math.PI * 2, 0, Math.PI * 0.42), HAIR);
  hair.scale.set(0.88, 1.14, 0.97);
  hair.position.set(0, r * 0.06, -r * 0.04);
  group.add(hair);
  const lids = [];
  const brows = [];
  for (const side of [1, -1]) {
    if (!hasEyes) {
      const eye = new Mesh(new SphereGeometry(r * 0.12, 12, 8), EYES);
      eye.position.set(side * r * 0.33, r * 0.15, r * 0.86);
      group.add(eye);
    }
    const lid = new Mesh(new SphereGeometry(r * 0.19, 14, 10), SKIN);
    lid.position.set(side * r * 0.32, r * 0.1, r * 0.84);
    lid.visible = false;
    group.add(lid);
    lids.push(lid);
    const brow = new Mesh(new CapsuleGeometry(r * 0.025, r * 0.2, 4, 8), HAIR);
    brow.rotation.z = Math.PI / 2 + side * 0.12;
    brow.position.set(side * r * 0.33, r * 0.32, r * 0.86);
    brow.userData.y = brow.position.y;
    group.add(brow);
    brows.push(brow);
  }
  const nose = new Mesh(new SphereGeometry(r * 0.13, 12, 8), SKIN);
  nose.scale.set(0.8, 1.3, 1.0);
  nose.position.set(0, -r * 0.05, r * 0.95);
  group.add(nose);
  const mouth = new Mesh(new SphereGeometry(r * 0.24, 16, 10), LIPS);
  mouth.geometry.scale(1, 0.4, 0.3);
  mouth.position.set(0, -r * 0.4, r * 0.86);
  mouth.scale.set(1, 0.15, 1);
  group.add(mouth);
  return { group, parts: { mouth, lids, brows, r } };
}
