// The face's ARKit morph weights on the page: read from script#mura-face
// ({"fps", "names", "weights": [[...] per frame]}), interpolated at any time, and played
// on whatever the avatar has — morph targets named as ARKit blendshapes (mura's skinned
// avatar, many VRMs), VRM expressions (the visemes aa/ih/ou/ee/oh and the blinks), or the
// capsule figure's simple face (avatar.js).

export function readFace(id = 'mura-face') {
  const element = document.getElementById(id);
  if (!element) return null;
  const face = JSON.parse(element.textContent);
  if (!Array.isArray(face.names) || !Array.isArray(face.weights) || !(face.fps > 0)) return null;
  return face;
}

// Weights at `t` seconds from the first frame: { name: weight }, linear between frames.
export function faceAt(face, t) {
  const out = {};
  const count = face.weights.length;
  if (!count) return out;
  const position = Math.min(Math.max(t * face.fps, 0), count - 1);
  const i = Math.floor(position);
  const j = Math.min(i + 1, count - 1);
  const u = position - i;
  const a = face.weights[i];
  const b = face.weights[j];
  face.names.forEach((name, k) => {
    out[name] = a[k] + u * (b[k] - a[k]);
  });
  return out;
}

// Sets morph target influences by name on every mesh of `object` that has them.
export function morphDriver(object) {
  const meshes = [];
  object.traverse((node) => {
    if (node.morphTargetDictionary && node.morphTargetInfluences) meshes.push(node);
  });
  return {
    count: meshes.length,
    apply(weights) {
      for (const mesh of meshes) {
        for (const [name, value] of Object.entries(weights)) {
          const index = mesh.morphTargetDictionary[name];
          if (index !== undefined) mesh.morphTargetInfluences[index] = value;
        }
      }
    },
    influence(name) {
      for (const mesh of meshes) {
        const index = mesh.morphTargetDictionary[name];
        if (index !== undefined) return mesh.morphTargetInfluences[index];
      }
      return null;
    },
  };
}

// VRM expressions from ARKit weights: the five visemes and the blinks.
const VRM_EXPRESSIONS = {
  aa: (w) => w.jawOpen ?? 0,
  ih: (w) => ((w.mouthSmileLeft ?? 0) + (w.mouthSmileRight ?? 0)) / 2,
  ee: (w) => ((w.mouthStretchLeft ?? 0) + (w.mouthStretchRight ?? 0)) / 2,
  oh: (w) => w.mouthFunnel ?? 0,
  ou: (w) => w.mouthPucker ?? 0,
  blinkLeft: (w) => w.eyeBlinkLeft ?? 0,
  blinkRight: (w) => w.eyeBlinkRight ?? 0,
};

export function vrmDriver(vrm) {
  const manager = vrm?.expressionManager;
  return {
    apply(weights) {
      if (!manager) return;
      for (const [name, value] of Object.entries(VRM_EXPRESSIONS)) {
        if (manager.getExpression(name)) manager.setValue(name, Math.min(1, Math.max(0, value(weights))));
      }
    },
  };
}
