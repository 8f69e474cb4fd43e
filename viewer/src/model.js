// The avatar's own model (skinned GLB built by mura, or a user's VRM/glTF), driven by the
// BVH skeleton. The page names the model in script#mura-model (JSON) and a sidecar script
// beside the page (mura-avatar-KEY.js, loaded by a <script src>, which works from file://)
// puts its bytes in window.__muraModels[KEY] as base64.
//
// "glb" models carry mura's H-Anim joint names with identity rest rotations: a BVH joint's
// local rotation is the model bone's. "vrm" models are posed through three-vrm's
// normalized humanoid bones: mura's global rotation W of a joint, taken relative to the
// model's rest (W · C⁻¹, C the rest correction mura computed for that bone), becomes the
// bone's local rotation relative to its nearest mapped ancestor.
import { Quaternion } from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { VRMLoaderPlugin, VRMUtils } from '@pixiv/three-vrm';
import { UNIT } from './skeleton.js';

export function modelSpec() {
  const element = document.getElementById('mura-model');
  return element ? JSON.parse(element.textContent) : null;
}

function bytesOf(key) {
  const text = window.__muraModels?.[key];
  if (typeof text !== 'string') throw new Error(`avatar model ${key} is missing (mura-avatar-${key}.js beside the page)`);
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i += 1) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

// Parse the model; resolves to { object, drive(bvhRoot), morphs }.
export function loadModel(spec) {
  const loader = new GLTFLoader();
  if (spec.format === 'vrm') loader.register((parser) => new VRMLoaderPlugin(parser));
  return new Promise((resolve, reject) => {
    loader.parse(
      bytesOf(spec.key),
      '',
      (gltf) => {
        try {
          resolve(spec.format === 'vrm' ? vrmModel(gltf, spec) : hanimModel(gltf, spec));
        } catch (error) {
          reject(error);
        }
      },
      (error) => reject(error instanceof Error ? error : new Error(String(error))),
    );
  });
}

function bonesByName(bvhRoot) {
  const bones = new Map();
  bvhRoot.traverse((node) => {
    if (node.isBone && node.name !== 'ENDSITE') bones.set(node.name, node);
  });
  return bones;
}

function countMorphs(object) {
  let count = 0;
  object.traverse((node) => {
    if (node.morphTargetDictionary) count = Math.max(count, Object.keys(node.morphTargetDictionary).length);
  });
  return count;
}

function hanimModel(gltf, spec) {
  const object = gltf.scene;
  object.scale.setScalar(UNIT);
  const modelBones = new Map();
  object.traverse((node) => {
    if (node.isBone || node.type === 'Bone' || node.name) modelBones.set(node.name, node);
  });
  const pairs = [];
  let root = null;
  return {
    object,
    morphs: countMorphs(object),
    drive(bvhRoot) {
      if (!pairs.length) {
        for (const [name, bone] of bonesByName(bvhRoot)) {
          const target = modelBones.get(name);
          if (target) pairs.push([bone, target]);
        }
        root = pairs.find(([bone]) => bone === bvhRoot) ?? null;
      }
      for (const [bone, target] of pairs) target.quaternion.copy(bone.quaternion);
      if (root) root[1].position.copy(bvhRoot.position).divideScalar(UNIT);
    },
  };
}

function vrmModel(gltf, spec) {
  const vrm = gltf.userData.vrm;
  if (!vrm) throw new Error('the model is not a VRM (no VRM extension)');
  VRMUtils.rotateVRM0(vrm);
  const flip = vrm.meta?.metaVersion === '0';
  const object = vrm.scene;
  object.scale.setScalar(UNIT);
  const joints = Object.keys(spec.bones);
  const rest = Object.fromEntries(joints.map((j) => [j, new Quaternion(...spec.rest[j]).invert()]));
  const world = new Map();
  const scratch = new Quaternion();
  const toRoot = new Quaternion();
  let bvhBones = null;
  return {
    object,
    vrm,
    morphs: countMorphs(object),
    drive(bvhRoot) {
      bvhBones ??= bonesByName(bvhRoot);
      bvhRoot.parent?.getWorldQuaternion(toRoot).invert();
      for (const joint of joints) {
        const bone = bvhBones.get(joint);
        if (!bone) continue;
        const w = bone.getWorldQuaternion(new Quaternion()).premultiply(toRoot).multiply(rest[joint]);
        world.set(joint, w);
        const parent = spec.parents[joint];
        const local = parent && world.has(parent) ? scratch.copy(world.get(parent)).invert().multiply(w) : scratch.copy(w);
        if (flip) local.set(-local.x, local.y, -local.z, local.w);
        const node = vrm.humanoid.getNormalizedBoneNode(spec.bones[joint]);
        if (node) node.quaternion.copy(local);
      }
      vrm.update(0);
    },
  };
}

