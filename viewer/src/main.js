// mura's avatar page. File mode: the page carries the BVH (script#mura-bvh, a JSON string)
// and the timeline (script#mura-timeline) inline and plays them against <audio id=mura-audio>.
// Live mode (?live=1): see live.js; as a client of `mura serve` (?live=ws): see socket.js.
// Query ?t=SECONDS opens the page paused at that time.
// When the first frame is drawn, window.__muraReady is true; window.__mura exposes
// time(), seek(t), play(), pause(), jointPosition(name), face() (the morph weights shown
// now), morph(name) (the model's morph influence), showFace(on) and counts for tests and scripting.
// The face's morph weights (script#mura-face, see face.js) play on the model's ARKit
// morph targets, VRM expressions, or the capsule figure's face.
import {
  AnimationMixer,
  Box3,
  Color,
  DirectionalLight,
  GridHelper,
  HemisphereLight,
  PerspectiveCamera,
  Scene,
  Vector3,
  WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { buildAvatar } from './avatar.js';
import { Clock } from './clock.js';
import { corpusSpec, startCorpus } from './corpus.js';
import { faceAt, morphDriver, readFace, vrmDriver } from './face.js';
import { loadModel, modelSpec } from './model.js';
import { PLACE_COLOUR, addPlaces } from './places.js';
import { applyFrame, connectLive } from './live.js';
import { connectSocket, describeFeedback, socketUrl } from './socket.js';
import { UNIT, jointBones, parseBVH, skeletonFromLive } from './skeleton.js';
import { CSS } from './style.js';
import { TimelineView, normalizeTimeline } from './timeline.js';

function readJSON(id) {
  const element = document.getElementById(id);
  return element ? JSON.parse(element.textContent) : undefined;
}

function element(tag, props = {}, parent = null) {
  const node = Object.assign(document.createElement(tag), props);
  if (parent) parent.append(node);
  return node;
}

function buildUI() {
  const style = element('style', { textContent: CSS });
  document.head.append(style);
  const app = document.getElementById('mura-app') ?? element('div', { id: 'mura-app' }, document.body);
  const title = element('h1', { textContent: app.dataset.name ? `mura — ${app.dataset.name}` : 'mura' });
  const stage = element('div', { id: 'mura-stage' });
  const status = element('div', { id: 'mura-status' }, stage);
  const controls = element('div', { id: 'mura-controls' });
  const play = element('button', { id: 'mura-play', type: 'button', textContent: 'Play' }, controls);
  const scrub = element('input', { id: 'mura-scrub', type: 'range', min: '0', max: '1', step: '0.001', value: '0' }, controls);
  const time = element('span', { id: 'mura-time', textContent: '0.00 s' }, controls);
  const views = element('span', { id: 'mura-views' }, controls);
  const viewButtons = Object.fromEntries(
    VIEWS.map(([name, label]) => [name, element('button', { type: 'button', textContent: label, title: `${label} view` }, views)]),
  );
  Object.entries(viewButtons).forEach(([name, button]) => (button.dataset.view = name));
  const strip = element('canvas', { id: 'mura-timeline-strip' });
  const legend = element('div', { id: 'mura-legend' });
  const list = element('section', { id: 'mura-timeline-list' });
  app.prepend(title, stage, controls, strip, legend, list);
  return { app, title, stage, status, controls, play, scrub, time, strip, legend, list, viewButtons };
}

function buildScene(stage) {
  const renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  stage.prepend(renderer.domElement);
  const scene = new Scene();
  scene.background = new Color(0x20252c);
  scene.add(new HemisphereLight(0xf4f1ea, 0x3a3530, 1.6));
  const key = new DirectionalLight(0xffffff, 2.2);
  key.position.set(150, 300, 400);
  scene.add(key);
  const rim = new DirectionalLight(0x9fb8ff, 0.8);
  rim.position.set(-200, 150, -300);
  scene.add(rim);
  const camera = new PerspectiveCamera(32, 1, 1, 10000);
  const controls = new OrbitControls(camera, renderer.domElement);
  const resize = () => {
    const width = stage.clientWidth || 640;
    const height = stage.clientHeight || 480;
    renderer.setSize(width, height, false);
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
  };
  resize();
  window.addEventListener('resize', resize);
  return { renderer, scene, camera, controls };
}

const LEG = /hip|knee|ankle|foot|toe|metatarsal|tarsal/;
const HAND = /wrist|thumb|index|middle|ring|pinky/;
const HIP_MARGIN = 0.06; // metres below the root that the front view still shows
// The page's camera views: name, button label (key 1, 2, 3 switch between them).
const VIEWS = [
  ['front', 'Front'],
  ['hands', 'Hands'],
  ['side', 'Side'],
  ['face', 'Face'],
];
const FACE_BOX = 0.24; // metres around the face that the face view shows

function isLeg(bone) {
  for (let node = bone; node?.isBone; node = node.parent) if (LEG.test(node.name)) return true;
  return false;
}

// Boxes over the given poses (scene units): the upper body with the crown of the head
// (signing space, hips to head) and the hands; the lowest point of the body for the floor.
function measurePoses(root, poses) {
  const upper = new Box3();
  const hands = new Box3();
  const whole = new Box3();
  const point = new Vector3();
  let lowest = Infinity;
  for (const pose of poses) {
    pose();
    root.updateMatrixWorld(true);
    whole.expandByObject(root);
    root.traverse((node) => {
      if (!node.isBone || isLeg(node)) return;
      node.getWorldPosition(point);
      upper.expandByPoint(point);
      if (HAND.test(node.name) || (node.name === 'ENDSITE' && HAND.test(node.parent?.name ?? ''))) hands.expandByPoint(point);
      if (/skullbase/.test(node.name)) upper.expandByPoint(point.clone().add(new Vector3(0, 0.24 * UNIT, 0)));
    });
    lowest = Math.min(lowest, root.getWorldPosition(point).y - HIP_MARGIN * UNIT);
  }
  // signing space: from just below the hips up (hands hanging at rest may leave the frame)
  upper.min.y = Math.max(upper.min.y, lowest);
  return { upper, hands, whole };
}

// Put the camera so that `box` fills the view from `direction` (unit, from the target to the camera).
function fitBox(view, box, direction, margin) {
  const centre = box.getCenter(new Vector3());
  const size = box.getSize(new Vector3());
  const across = Math.abs(direction.x) > 0.5 ? size.z : size.x;
  const depth = Math.abs(direction.x) > 0.5 ? size.x : size.z;
  const tan = Math.tan((view.camera.fov * Math.PI) / 360);
  const distance = Math.max((size.y * margin) / 2 / tan, (across * margin) / 2 / (tan * view.camera.aspect)) + depth / 4;
  view.camera.position.copy(centre).addScaledVector(direction, distance);
  view.controls.target.copy(centre);
  view.controls.update();
}

// Frame a view of the measured poses: 'front' (signing space, hips to crown), 'hands'
// (where the hands go, close up), 'side' (from the avatar's right) or 'face' (the head,
// close up, where it is when chosen).
function frameView(view, boxes, name) {
  const front = new Vector3(0.12, 0.05, 1).normalize();
  if (name === 'face' && boxes.headNow) {
    fitBox(view, boxes.headNow(), new Vector3(0.05, 0.02, 1).normalize(), 1.0);
  } else if (name === 'hands') {
    const box = boxes.handsNow ? boxes.handsNow() : boxes.hands.clone();
    const size = box.getSize(new Vector3());
    const grow = Math.max(0, 0.22 * UNIT - Math.max(size.x, size.y)) / 2;
    box.expandByScalar(grow);
    fitBox(view, box, front, 1.25);
  } else if (name === 'side') {
    fitBox(view, boxes.upper, new Vector3(-1, 0.05, 0.08).normalize(), 1.1);
  } else {
    fitBox(view, boxes.upper, front, 1.06);
  }
  view.current = name;
}

function addFloor(view, boxes) {
  const grid = new GridHelper(400, 20, 0x55606c, 0x343b44);
  grid.position.y = boxes.whole.min.y;
  view.scene.add(grid);
  return grid;
}

// Frame the body from the front over the given poses, with a floor grid under it.
function frameBody(view, root, poses) {
  const boxes = measurePoses(root, poses);
  frameView(view, boxes, 'front');
  return addFloor(view, boxes);
}

const format = (t) => `${t.toFixed(2)} s`;

function startFile(ui, view, timelineView, params) {
  const bvh = readJSON('mura-bvh');
  if (typeof bvh !== 'string') throw new Error('no BVH in the page (script#mura-bvh)');
  const raw = readJSON('mura-timeline') ?? {};
  const { skeleton, clip } = parseBVH(bvh);
  const root = skeleton.bones[0];
  view.scene.add(root);
  const spec = modelSpec();
  const model = spec ? loadModel(spec) : Promise.resolve(null);
  model.then(
    (loaded) => finishFile(ui, view, timelineView, params, { skeleton, clip, root, raw, loaded, spec }),
    (error) => {
      window.__muraModelError = String(error.message ?? error);
      finishFile(ui, view, timelineView, params, { skeleton, clip, root, raw, loaded: null, spec: null });
      ui.status.textContent = `avatar model not shown: ${window.__muraModelError}`;
    },
  );
}

function finishFile(ui, view, timelineView, params, { skeleton, clip, root, raw, loaded, spec }) {
  let meshes = 0;
  if (loaded) {
    view.scene.add(loaded.object);
    root.traverse((node) => (node.visible = false));
  } else {
    meshes = buildAvatar(root);
  }
  const face = readFace();
  const morphs = loaded ? morphDriver(loaded.object) : null;
  const expressions = loaded?.vrm ? vrmDriver(loaded.vrm) : null;
  let shown = {};
  let faceOn = true;
  const mixer = new AnimationMixer(root);
  const action = mixer.clipAction(clip);
  action.play();
  const motionStart = typeof raw.motion_start_time === 'number' ? raw.motion_start_time : 0;
  const pose = (t) => {
    action.time = Math.min(clip.duration, Math.max(0, t - motionStart));
    mixer.update(0);
    if (face) {
      shown = faceOn ? faceAt(face, t - motionStart) : Object.fromEntries(face.names.map((name) => [name, 0]));
      if (morphs) morphs.apply(shown);
      if (expressions) expressions.apply(shown);
      if (!loaded) root.userData.face?.apply(shown);
    }
    if (loaded) {
      root.updateMatrixWorld(true);
      loaded.drive(root);
    }
  };
  const timeline = normalizeTimeline(raw, motionStart + clip.duration);
  const audio = document.getElementById('mura-audio');
  const clock = new Clock(audio, Math.max(timeline.duration, motionStart + clip.duration));
  const setDuration = (duration) => {
    clock.duration = duration;
    timeline.duration = duration;
    ui.scrub.max = String(duration);
    timelineView.setTimeline(timeline);
  };
  setDuration(clock.duration);
  const fitAudio = () => {
    if (Number.isFinite(audio.duration) && audio.duration > clock.duration) setDuration(audio.duration);
  };
  if (audio) {
    audio.addEventListener('loadedmetadata', fitAudio);
    if (audio.readyState >= 1) fitAudio();
  }
  const samples = Array.from({ length: 16 }, (_, i) => () => pose(motionStart + (i / 15) * clip.duration));
  const boxes = measurePoses(root, samples);
  // The close-up frames the hands where they are when it is chosen.
  boxes.handsNow = () => {
    pose(clock.time());
    return measurePoses(root, [() => root.updateMatrixWorld(true)]).hands;
  };
  boxes.headNow = () => {
    pose(clock.time());
    root.updateMatrixWorld(true);
    const eyes = ['l_eyeball_joint', 'r_eyeball_joint'].map((name) => root.getObjectByName(name)).filter(Boolean);
    const centre = new Vector3();
    if (eyes.length === 2) {
      eyes.forEach((eye) => centre.add(eye.getWorldPosition(new Vector3()).multiplyScalar(0.5)));
      centre.y -= 0.03 * UNIT; // between the eyes and the mouth
    } else {
      root.getObjectByName('skullbase')?.getWorldPosition(centre);
      centre.y += 0.07 * UNIT;
    }
    return new Box3().setFromCenterAndSize(centre, new Vector3(1, 1, 1).multiplyScalar(FACE_BOX * UNIT));
  };
  frameView(view, boxes, 'front');
  addFloor(view, boxes);
  pose(motionStart);
  const places = addPlaces(view.scene, raw.places, boxes.whole.min.y, root.getWorldPosition(new Vector3()));
  const show = (name) => {
    frameView(view, boxes, name);
    Object.entries(ui.viewButtons).forEach(([key, button]) => button.classList.toggle('active', key === name));
  };
  Object.entries(ui.viewButtons).forEach(([name, button]) => button.addEventListener('click', () => show(name)));
  show('front');
  timelineView.renderLegend(ui.legend, places.length ? PLACE_COLOUR : null);
  pose(0);

  ui.play.addEventListener('click', () => (clock.playing ? clock.pause() : clock.play()));
  ui.scrub.addEventListener('input', () => clock.seek(Number(ui.scrub.value)));
  timelineView.onSeek = (t) => clock.seek(t);
  document.addEventListener('keydown', (event) => {
    if (event.target instanceof HTMLInputElement) return;
    const digit = VIEWS[Number(event.key) - 1];
    if (digit) show(digit[0]);
    if (event.code !== 'Space') return;
    event.preventDefault();
    ui.play.click();
  });
  const requested = Number(params.get('t'));
  if (params.has('t') && Number.isFinite(requested)) clock.seek(requested);

  const draw = () => {
    clock.tick();
    const t = clock.time();
    pose(t);
    ui.play.textContent = clock.playing ? 'Pause' : 'Play';
    if (document.activeElement !== ui.scrub) ui.scrub.value = String(t);
    ui.time.textContent = `${format(t)} / ${format(clock.duration)}`;
    timelineView.update(t);
    view.controls.update();
    view.renderer.render(view.scene, view.camera);
  };
  const loop = () => {
    draw();
    requestAnimationFrame(loop);
  };
  draw();
  window.__mura = {
    time: () => clock.time(),
    seek: (t) => {
      clock.seek(t);
      draw();
    },
    play: () => clock.play(),
    pause: () => clock.pause(),
    duration: () => clock.duration,
    joints: jointBones(skeleton).length,
    meshes,
    model: loaded ? { format: spec.format, morphs: loaded.morphs } : null,
    places: places.length,
    view: (name) => {
      show(name);
      draw();
      return view.current;
    },
    // Where a joint is drawn on the stage, CSS pixels from its top-left corner.
    screenOf: (name) => {
      const bone = root.getObjectByName(name);
      if (!bone) return null;
      const p = bone.getWorldPosition(new Vector3()).project(view.camera);
      const rect = view.renderer.domElement.getBoundingClientRect();
      return [((p.x + 1) / 2) * rect.width, ((1 - p.y) / 2) * rect.height];
    },
    camera: () => ({ position: view.camera.position.toArray(), target: view.controls.target.toArray(), aspect: view.camera.aspect }),
    // World position of a joint in the drawn pose, scene units (cm).
    jointPosition: (name) => root.getObjectByName(name)?.getWorldPosition(new Vector3()).toArray() ?? null,
    face: () => ({ ...shown }),
    // Play the face (true) or hold it at rest (false), to see what the face alone changes.
    showFace: (on) => {
      faceOn = Boolean(on);
      draw();
      return faceOn;
    },
    morph: (name) => morphs?.influence(name) ?? null,
    faceNames: face ? face.names.length : 0,
  };
  window.__muraReady = true;
  requestAnimationFrame(loop);
}

// The realizer's page: a box to send BML, the latest feedback line in the status.
function buildSender(ui, send) {
  const form = element('form', { id: 'mura-send' });
  const box = element('textarea', { id: 'mura-bml', rows: 4, placeholder: '<bml xmlns="http://www.bml-initiative.org/bml/bml-1.0" id="b1">…</bml>' }, form);
  element('button', { type: 'submit', textContent: 'Send BML' }, form);
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    send(box.value);
  });
  ui.controls.after(form);
}

function startLive(ui, view, timelineView, transport = 'sse') {
  ui.play.disabled = true;
  ui.scrub.disabled = true;
  ui.status.textContent = 'live: connecting…';
  let bones = [];
  let root = null;
  let grid = null;
  let framed = false;
  let meshes = 0;
  let time = 0;
  let timeline = normalizeTimeline({}, 0);
  const handlers = {
    onSkeleton(description) {
      if (root) view.scene.remove(root);
      const skeleton = skeletonFromLive(description);
      root = skeleton.bones[0];
      view.scene.add(root);
      meshes = buildAvatar(root);
      bones = jointBones(skeleton);
      framed = false;
      ui.status.textContent = `live: ${bones.length} joints`;
    },
    onTimeline(raw) {
      timeline = normalizeTimeline(raw, time);
      ui.scrub.max = String(timeline.duration);
      timelineView.setTimeline(timeline);
    },
    onFrame(frame) {
      applyFrame(bones, frame, UNIT);
      if (root && frame.face) root.userData.face?.apply(frame.face);
      if (!framed && root) {
        // Frame on the first posed frame: the rest pose has the root at the origin.
        if (grid) view.scene.remove(grid);
        grid = frameBody(view, root, [() => {}]);
        framed = true;
      }
      if (typeof frame.time === 'number') time = frame.time;
    },
    onError(message) {
      ui.status.textContent = message;
    },
    onFeedback(message) {
      const line = describeFeedback(message);
      if (line !== null) ui.status.textContent = line;
    },
  };
  if (transport === 'ws') {
    const client = connectSocket(socketUrl(window.location), handlers);
    buildSender(ui, (xml) => client.send(xml));
  } else {
    connectLive('./stream', handlers);
  }
  const loop = () => {
    ui.scrub.value = String(time);
    ui.time.textContent = format(time);
    timelineView.update(time);
    view.controls.update();
    view.renderer.render(view.scene, view.camera);
    requestAnimationFrame(loop);
  };
  loop();
  window.__mura = { time: () => time, joints: () => bones.length, meshes: () => meshes };
  window.__muraReady = true;
}

function boot() {
  const params = new URLSearchParams(window.location.search);
  const ui = buildUI();
  const timelineView = new TimelineView(ui.strip, ui.list, () => {});
  try {
    const view = buildScene(ui.stage);
    if (corpusSpec()) startCorpus(ui, view, params, { measurePoses, frameView, addFloor });
    else if (params.get('live') === '1') startLive(ui, view, timelineView);
    else if (params.get('live') === 'ws') startLive(ui, view, timelineView, 'ws');
    else startFile(ui, view, timelineView, params);
  } catch (error) {
    ui.status.textContent = `viewer error: ${error.message}`;
    timelineView.setTimeline(normalizeTimeline(readJSON('mura-timeline'), 0));
    window.__muraError = String(error.message);
    window.__muraReady = true;
    throw error;
  }
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', boot);
else boot();
