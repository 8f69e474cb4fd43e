// Scene places named in the lexicon (`$Loc-Bar_1`), drawn as simple objects with their
// name, so that a pointing gesture points at something. The timeline lists them as
// `places: [{name, position: [x, y, z]}]`, metres relative to the avatar's root joint (the
// hips), as the lexicon gives them; `origin` is where the root is drawn (scene units).
import { CanvasTexture, CylinderGeometry, Mesh, MeshStandardMaterial, SphereGeometry, Sprite, SpriteMaterial, Vector3 } from 'three';
import { UNIT } from './skeleton.js';

export const PLACE_COLOUR = '#d9a441';
const MATERIAL = new MeshStandardMaterial({ color: PLACE_COLOUR, roughness: 0.5, metalness: 0.2 });

function label(text) {
  const canvas = document.createElement('canvas');
  canvas.width = 256;
  canvas.height = 64;
  const g = canvas.getContext('2d');
  g.font = '28px sans-serif';
  g.fillStyle = 'rgba(16,19,23,0.75)';
  g.fillRect(0, 0, canvas.width, canvas.height);
  g.fillStyle = '#f4e3b5';
  g.textBaseline = 'middle';
  g.fillText(text, 10, canvas.height / 2, canvas.width - 20);
  const sprite = new Sprite(new SpriteMaterial({ map: new CanvasTexture(canvas), depthTest: false }));
  sprite.scale.set(0.2 * UNIT, 0.05 * UNIT, 1);
  return sprite;
}

// Add the places to the scene; returns the objects added.
export function addPlaces(scene, places, floor, origin) {
  if (!Array.isArray(places)) return [];
  const added = [];
  for (const place of places) {
    const [x, y, z] = Array.isArray(place?.position) ? place.position.map(Number) : [NaN];
    if (![x, y, z].every(Number.isFinite)) continue;
    const name = String(place.name ?? '');
    const bar = /bar|rod|stick/i.test(name);
    const geometry = bar ? new CylinderGeometry(0.012 * UNIT, 0.012 * UNIT, 0.25 * UNIT, 16) : new SphereGeometry(0.03 * UNIT, 20, 14);
    const object = new Mesh(geometry, MATERIAL);
    if (bar) object.rotation.x = Math.PI / 2;
    object.position.set(x * UNIT, y * UNIT, z * UNIT).add(origin);
    const tag = label(name);
    tag.position.copy(object.position).add(new Vector3(0, 0.07 * UNIT, 0));
    object.userData.floor = floor;
    scene.add(object, tag);
    added.push(object);
  }
  return added;
}
