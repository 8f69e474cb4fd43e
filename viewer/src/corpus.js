// Corpus mode: one viewer for many motions (the page mura batch / mura sign write as
// index.html). script#mura-corpus lists the items and the joints of the skeleton they
// share; each rendered item's frames are in NAME.motion.js beside the page, loaded (by a
// <script src>, which works from file://) when the item is chosen; the file calls
// window.__muraMotion(name, payload) with
//   {fps, frames, start, duration, rotations: base64 int16 x,y,z,w per joint per frame
//    (/ 32767), root: base64 float32 x,y,z metres per frame, timeline}.
// The list is searched by gloss, an item plays, and ←/→ (or the buttons) step through
// the items found. An item with speech names its WAV (`audio`), which plays with it.
// URL: #NAME opens that item.
import { Quaternion } from 'three';
import { buildAvatar } from './avatar.js';
import { faceAt, morphDriver, vrmDriver } from './face.js';
import { Clock } from './clock.js';
import { loadModel, modelSpec } from './model.js';
import { UNIT, jointBones, skeletonFromLive } from './skeleton.js';

const QUATERNION_SCALE = 32767;
const CACHED_MOTIONS = 48; // motions kept decoded in memory
const LISTED = 1000; // list entries drawn at once (the rest are counted)

export function corpusSpec() {
  const element = document.getElementById('mura-corpus');
  return element ? JSON.parse(element.textContent) : null;
}

function element(tag, props = {}, parent = null) {
  const node = Object.assign(document.createElement(tag), props);
  if (parent) parent.append(node);
  return node;
}

function decode(payload) {
  const bytes = (text) => Uint8Array.from(atob(text), (c) => c.charCodeAt(0)).buffer;
  return {
    fps: payload.fps,
    frames: payload.frames,
    start: payload.start ?? 0,
    duration: payload.duration,
    rotations: new Int16Array(bytes(payload.rotations)),
    root: new Float32Array(bytes(payload.root)),
    face: payload.face && payload.face.names?.length ? payload.face : null,
  };
}

// Motion files arrive through one global callback; each load waits for its own name.
function motionLoader() {
  const waiting = new Map();
  const cache = new Map();
  window.__muraMotion = (name, payload) => {
    const resolve = waiting.get(name);
    if (!resolve) return;
    waiting.delete(name);
    resolve(decode(payload));
  };
  return (item) => {
    if (cache.has(item.name)) return Promise.resolve(cache.get(item.name));
    return new Promise((resolve, reject) => {
      waiting.set(item.name, (motion) => {
        cache.set(item.name, motion);
        if (cache.size > CACHED_MOTIONS) cache.delete(cache.keys().next().value);
        resolve(motion);
      });
      const script = element('script', { src: item.motion });
      script.onerror = () => {
        waiting.delete(item.name);
        reject(new Error(`cannot load ${item.motion}`));
      };
      script.onload = () => script.remove();
      document.head.append(script);
    });
  };
}

function buildPanel(ui, corpus) {
  const panel = element('section', { id: 'mura-corpus-panel' });
  const search = element('input', { id: 'mura-search', type: 'search', placeholder: 'Search by gloss…' }, panel);
  const count = element('span', { id: 'mura-count' }, panel);
  const list = element('ol', { id: 'mura-items' }, panel);
  const more = element('p', { id: 'mura-more' }, panel);
  ui.stage.after(panel);
  const prev = element('button', { id: 'mura-prev', type: 'button', textContent: '◀', title: 'previous item (←)' });
  const next = element('button', { id: 'mura-next', type: 'button', textContent: '▶', title: 'next item (→)' });
  const all = element('label', { id: 'mura-play-all', textContent: ' play all' });
  const box = element('input', { type: 'checkbox' });
  all.prepend(box);
  ui.play.before(prev);
  ui.play.after(next);
  ui.time.after(all);
  ui.title.textContent = `mura — ${corpus.title ?? 'corpus'}`;
  return { panel, search, count, list, more, prev, next, playAll: box };
}

// Pose `bones` at time t of `motion`: the two nearest frames, slerped.
function poseAt(bones, motion, t) {
  const position = Math.min(motion.frames - 1, Math.max(0, (t - motion.start) * motion.fps));
  const first = Math.floor(position);
  const second = Math.min(first + 1, motion.frames - 1);
  const fraction = position - first;
  const joints = bones.length;
  const q = motion.rotations;
  const a = new Quaternion();
  const b = new Quaternion();
  for (let j = 0; j < joints; j += 1) {
    const i = 4 * (first * joints + j);
    const k = 4 * (second * joints + j);
    a.set(q[i], q[i + 1], q[i + 2], q[i + 3]).normalize();
    b.set(q[k], q[k + 1], q[k + 2], q[k + 3]).normalize();
    bones[j].quaternion.copy(a).slerp(b, fraction);
  }
  const r = motion.root;
  const lerp = (c) => (r[3 * first + c] * (1 - fraction) + r[3 * second + c] * fraction) * UNIT;
  bones[0].position.set(lerp(0), lerp(1), lerp(2));
}

export function startCorpus(ui, view, params, helpers) {
  const corpus = corpusSpec();
  const items = corpus.items ?? [];
  const panel = buildPanel(ui, corpus);
  const skeleton = skeletonFromLive(corpus.skeleton);
  const root = skeleton.bones[0];
  const bones = jointBones(skeleton);
  view.scene.add(root);
  const spec = modelSpec();
  const state = { visible: items, current: null, motion: null, loaded: null, boxes: null, floor: null, token: 0 };
  let clock = new Clock(null, 0);
  const load = motionLoader();

  // The face: the item's morph weights (names it does not move rest at 0), on the model's
  // morph targets or VRM expressions, or on the capsule figure's face.
  let shown = {};
  const drivers = [];
  const poseFace = (t) => {
    const face = state.motion.face;
    const current = face ? faceAt(face, t - state.motion.start) : {};
    if (!face && !Object.keys(shown).length) return;
    const weights = { ...Object.fromEntries(Object.keys(shown).map((name) => [name, 0])), ...current };
    shown = current;
    for (const driver of drivers) driver.apply(weights);
  };

  const pose = (t) => {
    if (!state.motion) return;
    poseAt(bones, state.motion, t);
    poseFace(t);
    if (state.loaded) {
      root.updateMatrixWorld(true);
      state.loaded.drive(root);
    }
  };

  const drawList = () => {
    panel.list.replaceChildren();
    state.visible.slice(0, LISTED).forEach((item) => {
      const entry = element('li', { textContent: item.label, title: item.reason ?? item.source }, panel.list);
      entry.dataset.name = item.name;
      entry.classList.toggle('failed', !item.motion);
      entry.classList.toggle('active', item === state.current);
      if (item.motion) entry.addEventListener('click', () => select(item.name));
    });
    const rendered = state.visible.filter((item) => item.motion).length;
    panel.count.textContent = `${state.visible.length} of ${items.length} (${rendered} rendered)`;
    panel.more.textContent = state.visible.length > LISTED ? `… and ${state.visible.length - LISTED} more: narrow the search` : '';
  };

  const search = (text) => {
    const needle = String(text ?? '').trim().toLowerCase();
    state.visible = needle ? items.filter((item) => item.label.toLowerCase().includes(needle) || item.name.toLowerCase().includes(needle)) : items;
    drawList();
    return state.visible.length;
  };

  const frame = () => {
    const motion = state.motion;
    const samples = Array.from({ length: 12 }, (_, i) => () => poseAt(bones, motion, motion.start + (i / 11) * motion.duration));
    state.boxes = helpers.measurePoses(root, samples);
    helpers.frameView(view, state.boxes, view.current ?? 'front');
    if (state.floor) view.scene.remove(state.floor);
    state.floor = helpers.addFloor(view, state.boxes);
  };

  async function select(name) {
    const item = items.find((candidate) => candidate.name === name);
    if (!item || !item.motion) throw new Error(`no rendered item ${name}`);
    const token = (state.token += 1);
    ui.status.textContent = `loading ${item.label}…`;
    const motion = await load(item);
    if (token !== state.token) return state.current?.name ?? null;
    clock.pause();
    state.current = item;
    state.motion = motion;
    clock = new Clock(audioOf(item), motion.start + motion.duration);
    clock.seek(0);
    ui.scrub.max = String(clock.duration);
    ui.title.textContent = `mura — ${item.label}`;
    ui.status.textContent = `${item.label} · ${item.source}`;
    history.replaceState(null, '', `#${encodeURIComponent(item.name)}`);
    frame();
    pose(0);
    drawList();
    return item.name;
  }

  // The item's speech (utterances): one <audio> element, its source switched per item.
  const audio = element('audio', { id: 'mura-audio', preload: 'auto' }, ui.app);
  const audioOf = (item) => {
    if (!item.audio) {
      audio.removeAttribute('src');
      return null;
    }
    audio.src = item.audio;
    return audio;
  };

  const step = (offset) => {
    const playable = state.visible.filter((item) => item.motion);
    if (!playable.length) return Promise.resolve(null);
    const at = playable.indexOf(state.current);
    const target = playable[(at + offset + playable.length) % playable.length];
    return select(target.name);
  };

  panel.search.addEventListener('input', () => search(panel.search.value));
  panel.prev.addEventListener('click', () => step(-1));
  panel.next.addEventListener('click', () => step(1));
  ui.play.addEventListener('click', () => (clock.playing ? clock.pause() : clock.play()));
  ui.scrub.addEventListener('input', () => clock.seek(Number(ui.scrub.value)));
  Object.entries(ui.viewButtons).forEach(([name, button]) =>
    button.addEventListener('click', () => {
      if (state.boxes) helpers.frameView(view, state.boxes, name);
    }),
  );
  document.addEventListener('keydown', (event) => {
    if (event.target instanceof HTMLInputElement) return;
    if (event.key === 'ArrowRight') step(1);
    if (event.key === 'ArrowLeft') step(-1);
    if (event.code === 'Space') {
      event.preventDefault();
      ui.play.click();
    }
  });

  const draw = () => {
    const wasPlaying = clock.playing;
    clock.tick();
    if (wasPlaying && !clock.playing && panel.playAll.checked) step(1).then(() => clock.play());
    const t = clock.time();
    pose(t);
    ui.play.textContent = clock.playing ? 'Pause' : 'Play';
    if (document.activeElement !== ui.scrub) ui.scrub.value = String(t);
    ui.time.textContent = `${t.toFixed(2)} s / ${clock.duration.toFixed(2)} s`;
    view.controls.update();
    view.renderer.render(view.scene, view.camera);
  };
  const loop = () => {
    draw();
    requestAnimationFrame(loop);
  };

  window.__mura = {
    items: () => items.map((item) => item.name),
    visible: () => state.visible.map((item) => item.name),
    search,
    select,
    next: () => step(1),
    prev: () => step(-1),
    current: () => state.current?.name ?? null,
    time: () => clock.time(),
    seek: (t) => {
      clock.seek(t);
      draw();
    },
    play: () => clock.play(),
    pause: () => clock.pause(),
    duration: () => clock.duration,
    joints: bones.length,
    model: () => (state.loaded ? { format: spec.format, morphs: state.loaded.morphs } : null),
    face: () => ({ ...shown }),
    faceNames: () => state.motion?.face?.names.length ?? 0,
    jointPosition: (name) => root.getObjectByName(name)?.getWorldPosition(root.position.clone()).toArray() ?? null,
  };

  const begin = () => {
    search('');
    const wanted = decodeURIComponent(window.location.hash.slice(1)) || params.get('item');
    const first = items.find((item) => item.name === wanted && item.motion) ?? items.find((item) => item.motion);
    const ready = () => {
      draw();
      window.__muraReady = true;
      requestAnimationFrame(loop);
    };
    if (!first) {
      ui.status.textContent = 'no rendered item in this corpus';
      ready();
      return;
    }
    select(first.name).then(ready, (error) => {
      window.__muraError = String(error.message ?? error);
      ui.status.textContent = window.__muraError;
      ready();
    });
  };

  const model = spec ? loadModel(spec) : Promise.resolve(null);
  model.then(
    (loaded) => {
      state.loaded = loaded;
      if (loaded) {
        view.scene.add(loaded.object);
        root.traverse((node) => (node.visible = false));
        drivers.push(morphDriver(loaded.object));
        if (loaded.vrm) drivers.push(vrmDriver(loaded.vrm));
      } else {
        buildAvatar(root);
        if (root.userData.face) drivers.push(root.userData.face);
      }
      begin();
    },
    (error) => {
      window.__muraModelError = String(error.message ?? error);
      buildAvatar(root);
      if (root.userData.face) drivers.push(root.userData.face);
      begin();
    },
  );
}
