// Skeletons for the viewer: from BVH text (file mode) or from a live stream's first message.
import { Bone, Skeleton } from 'three';
import { BVHLoader } from 'three/addons/loaders/BVHLoader.js';

// Scene length unit: centimetres per metre (mura's BVH is written in centimetres).
export const UNIT = 100;
const END_SITE_FRACTION = 0.75; // end-site length over the leaf's own bone, as in agent/export/bvh.py

// Parse a whole BVH file: { skeleton, clip } as three.js' BVHLoader returns them.
export function parseBVH(text) {
  return new BVHLoader().parse(text);
}

// A skeleton from a live stream's `skeleton` field: either BVH HIERARCHY text (with or
// without a MOTION part) or a joint list [{name, parent, offset: [x, y, z] metres}].
export function skeletonFromLive(description) {
  if (typeof description === 'string') return parseBVH(withMotionStub(description)).skeleton;
  if (Array.isArray(description)) return skeletonFromJoints(description);
  throw new Error('mura viewer: live skeleton must be BVH text or a joint list');
}

function withMotionStub(text) {
  if (/^\s*MOTION\s*$/m.test(text)) return text;
  const channels = [...text.matchAll(/CHANNELS\s+(\d+)/g)].reduce((sum, m) => sum + Number(m[1]), 0);
  return `${text.trimEnd()}\nMOTION\nFrames: 1\nFrame Time: 1\n${new Array(channels).fill('0').join(' ')}\n`;
}

function skeletonFromJoints(joints) {
  const bones = joints.map((joint, index) => {
    const bone = new Bone();
    bone.name = String(joint.name ?? `joint${index}`);
    const [x, y, z] = joint.offset ?? [0, 0, 0];
    bone.position.set(x * UNIT, y * UNIT, z * UNIT);
    return bone;
  });
  joints.forEach((joint, index) => {
    const parent = Number(joint.parent ?? -1);
    if (parent >= 0 && parent < index) bones[parent].add(bones[index]);
  });
  // Leaves get an end site continuing their bone, as the BVH writer adds, so fingertips
  // have a last phalanx to draw.
  const ends = bones
    .filter((bone) => bone.parent && !bone.children.some((child) => child.isBone))
    .map((leaf) => {
      const end = new Bone();
      end.name = 'ENDSITE';
      end.position.copy(leaf.position).multiplyScalar(END_SITE_FRACTION);
      leaf.add(end);
      return end;
    });
  return new Skeleton([...bones, ...ends]);
}

// Bones that carry rotations, in file/joint order (BVH end sites excluded).
export function jointBones(skeleton) {
  return skeleton.bones.filter((bone) => bone.name !== 'ENDSITE');
}
