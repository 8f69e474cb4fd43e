// Body parts of an H-Anim skeleton, told apart by joint name, and their sizes.
// Sizes are in metres; the scene is in centimetres (the BVH unit), see UNIT in skeleton.js.

const FINGER = /(thumb|index|middle|ring|pinky)(\d)$/;

// Radius of the limb segment that starts at a joint named `name`, metres.
const SEGMENT_RADIUS = [
  [/^(humanoid_root|sacroiliac)$/, 0.115],
  [/^v[lt]\d+$/, 0.125],
  [/^vc\d+$/, 0.05],
  [/skullbase|head/, 0.05],
  [/sternoclavicular|clavicle|acromioclavicular/, 0.05],
  [/shoulder/, 0.047],
  [/elbow/, 0.037],
  [/wrist/, 0.011],
  [/hip/, 0.08],
  [/knee/, 0.06],
  [/ankle/, 0.045],
];

const FINGER_RADIUS = { thumb: [0.011, 0.012, 0.0105, 0.0095], other: [0.009, 0.0098, 0.0088, 0.0078] };

export const DEFAULT_RADIUS = 0.02;
const UPPER_CHEST_RADIUS = 0.085; // tapers the chest into the neck

export function fingerOf(name) {
  const match = FINGER.exec(name);
  return match ? { finger: match[1], segment: Number(match[2]) } : null;
}

export function isTorso(name) {
  return /^(humanoid_root|sacroiliac|v[lt]\d+)$/.test(name);
}

export function isHead(name) {
  return /skullbase|head/.test(name);
}

export function isEye(name) {
  return /eyeball/.test(name);
}

export function isWrist(name) {
  return /wrist/.test(name);
}

// Clothed parts get the shirt material, the rest skin.
export function isClothed(name) {
  return isTorso(name) || /sternoclavicular|clavicle|shoulder|^vc\d+$/.test(name);
}

// Radius, metres, of the segment from joint `from` to its child `to`. A segment that
// leaves the midline for a side (spine → clavicle) takes the side's size.
export function segmentRadius(from, to) {
  const side = /^[lr]_/;
  if (isTorso(from) && /^vc\d+$/.test(to)) return UPPER_CHEST_RADIUS;
  const name = !side.test(from) && side.test(to) ? to : from;
  const finger = fingerOf(name);
  if (finger) {
    const table = finger.finger === 'thumb' ? FINGER_RADIUS.thumb : FINGER_RADIUS.other;
    return table[Math.min(finger.segment, table.length - 1)];
  }
  for (const [pattern, radius] of SEGMENT_RADIUS) {
    if (pattern.test(name)) return radius;
  }
  return DEFAULT_RADIUS;
}
