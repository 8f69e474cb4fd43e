// The utterance timeline under the avatar: a canvas strip (chunk states, words, gesture
// phases, playhead) and a plain-text list of the same facts. Every key is optional.

const STATE_COLOURS = {
  InPrep: '#8e9aaf',
  Pending: '#c9a227',
  Lurking: '#d98c5f',
  InExec: '#3d9970',
  Subsiding: '#6c8ebf',
  Completed: '#555b66',
};
const PHASE_COLOURS = { preparation: '#f2cc8f', stroke: '#e07a5f', retraction: '#81b29a' };
const STATE_SHORT = { InPrep: 'P', Pending: 'Pe', Lurking: 'L', InExec: 'X', Subsiding: 'S', Completed: 'C' };
const ROW = 18; // px
const AXIS = 16; // px
const LABEL = 96; // px

const number = (value) => (typeof value === 'number' && Number.isFinite(value) ? value : null);
const list = (value) => (Array.isArray(value) ? value : []);
const seconds = (t) => (t === null ? '?' : t.toFixed(2));

// Gesture phases of one behaviour: preparation start→stroke_start, stroke
// stroke_start→stroke_end, retraction stroke_end→end (missing pegs drop the phase).
export function phasesOf(behavior) {
  const pegs = behavior.phases ?? {};
  const spans = [
    ['preparation', number(pegs.start), number(pegs.stroke_start)],
    ['stroke', number(pegs.stroke_start), number(pegs.stroke_end)],
    ['retraction', number(pegs.stroke_end), number(pegs.end)],
  ];
  return spans
    .filter(([, from, to]) => from !== null && to !== null && to >= from)
    .map(([phase, from, to]) => ({ phase, from, to }));
}

// State spans of a chunk: each state lasts until the next; the last one (unless
// Completed) lasts to the end of the timeline.
function stateSpans(chunk, end) {
  const states = list(chunk.states)
    .map((s) => ({ state: String(s.state ?? '?'), time: number(s.time) }))
    .filter((s) => s.time !== null)
    .sort((a, b) => a.time - b.time);
  return states.map((s, i) => ({
    state: s.state,
    from: s.time,
    to: i + 1 < states.length ? states[i + 1].time : s.state === 'Completed' ? s.time : end,
  }));
}

// The timeline with defaults for every missing key, and its duration in seconds.
export function normalizeTimeline(raw, fallbackDuration) {
  const timeline = raw && typeof raw === 'object' ? raw : {};
  const chunks = list(timeline.chunks);
  const behaviors = list(timeline.behaviors);
  const words = list(timeline.words);
  const times = [number(fallbackDuration) ?? 0];
  for (const c of chunks) list(c.states).forEach((s) => times.push(number(s.time) ?? 0));
  for (const b of behaviors) phasesOf(b).forEach((p) => times.push(p.to));
  for (const w of words) times.push(number(w.end) ?? 0);
  const duration = number(timeline.duration) ?? Math.max(...times);
  return {
    name: typeof timeline.name === 'string' ? timeline.name : '',
    duration,
    chunks,
    behaviors,
    words,
    timeTags: timeline.time_tags && typeof timeline.time_tags === 'object' ? timeline.time_tags : {},
  };
}

export class TimelineView {
  constructor(strip, listElement, onSeek) {
    this.strip = strip;
    this.listElement = listElement;
    this.onSeek = onSeek;
    this.background = document.createElement('canvas');
    this.timeline = normalizeTimeline({}, 0);
    this.items = [];
    window.addEventListener('resize', () => {
      this.renderStrip();
      this.update(this.lastTime);
    });
    this.lastTime = 0;
    const seekFromPointer = (event) => {
      const rect = strip.getBoundingClientRect();
      const x = event.clientX - rect.left - LABEL;
      const fraction = Math.min(1, Math.max(0, x / Math.max(1, rect.width - LABEL)));
      this.onSeek(fraction * this.timeline.duration);
    };
    strip.addEventListener('pointerdown', (event) => {
      strip.setPointerCapture(event.pointerId);
      seekFromPointer(event);
    });
    strip.addEventListener('pointermove', (event) => {
      if (event.buttons & 1) seekFromPointer(event);
    });
  }

  // The colour key of the strip: chunk states, gesture phases, speech, and scene places.
  renderLegend(container, placeColour = null) {
    container.replaceChildren();
    const item = (colour, text, outline = false) => {
      const entry = document.createElement('span');
      entry.className = 'mura-legend-item';
      const swatch = document.createElement('i');
      swatch.style.background = outline ? 'transparent' : colour;
      if (outline) swatch.style.border = `1px ${outline} ${colour}`;
      entry.append(swatch, document.createTextNode(text));
      container.append(entry);
    };
    for (const [state, colour] of Object.entries(STATE_COLOURS)) item(colour, state);
    for (const [phase, colour] of Object.entries(PHASE_COLOURS)) item(colour, phase);
    item('#ffffff', 'speech', 'solid');
    item('#ffffff', 'affiliate', 'dashed');
    item('#ff4d4d', 'now');
    if (placeColour) item(placeColour, 'scene place');
  }

  setTimeline(timeline) {
    this.timeline = timeline;
    this.renderList();
    this.renderStrip();
  }

  rows() {
    const t = this.timeline;
    return [
      ...t.chunks.map((chunk, i) => ({ kind: 'chunk', label: `chunk ${chunk.index ?? i}`, item: chunk })),
      { kind: 'words', label: 'words', item: t.words },
      ...t.behaviors.map((b, i) => ({ kind: 'behavior', label: String(b.id ?? `behavior ${i}`), item: b })),
    ];
  }

  renderStrip() {
    const rows = this.rows();
    const ratio = window.devicePixelRatio || 1;
    const width = Math.max(200, this.strip.clientWidth || 800);
    const height = rows.length * ROW + AXIS;
    this.strip.style.height = `${height}px`;
    for (const canvas of [this.strip, this.background]) {
      canvas.width = Math.round(width * ratio);
      canvas.height = Math.round(height * ratio);
    }
    const g = this.background.getContext('2d');
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.fillStyle = '#16191e';
    g.fillRect(0, 0, width, height);
    g.font = '11px sans-serif';
    g.textBaseline = 'middle';
    const x = (t) => LABEL + (t / Math.max(1e-9, this.timeline.duration)) * (width - LABEL);
    rows.forEach((row, i) => {
      const top = i * ROW;
      g.fillStyle = i % 2 ? '#1b1f25' : '#1f242b';
      g.fillRect(0, top, width, ROW);
      g.fillStyle = '#c8ccd4';
      g.fillText(row.label, 4, top + ROW / 2, LABEL - 8);
      if (row.kind === 'chunk') this.drawChunk(g, row.item, top, x);
      if (row.kind === 'words') this.drawWords(g, row.item, top, x);
      if (row.kind === 'behavior') this.drawBehavior(g, row.item, top, x);
    });
    this.drawAxis(g, rows.length * ROW, x, width);
    this.width = width;
    this.height = height;
    this.x = x;
  }

  drawChunk(g, chunk, top, x) {
    const onset = number(chunk.speech_onset);
    const end = number(chunk.speech_end);
    for (const span of stateSpans(chunk, this.timeline.duration)) {
      g.fillStyle = STATE_COLOURS[span.state] ?? '#777';
      g.fillRect(x(span.from), top + 2, Math.max(1, x(span.to) - x(span.from)), ROW - 4);
    }
    // State names only where they fit and the speech text is not written: never overlapping.
    const speech = onset !== null && end !== null ? [x(onset), x(end)] : null;
    let free = -Infinity;
    for (const span of stateSpans(chunk, this.timeline.duration)) {
      const left = x(span.from) + 2;
      const width = x(span.to) - x(span.from) - 4;
      const text = width >= g.measureText(span.state).width ? span.state : STATE_SHORT[span.state] ?? '';
      const textWidth = g.measureText(text).width;
      const clash = speech && left < speech[1] && left + textWidth > speech[0];
      if (!text || textWidth > width || left < free || clash) continue;
      g.fillStyle = '#101317';
      g.fillText(text, left, top + ROW / 2);
      free = left + textWidth + 4;
    }
    if (onset !== null && end !== null) {
      g.strokeStyle = '#ffffff';
      g.strokeRect(x(onset), top + 1.5, x(end) - x(onset), ROW - 3);
      g.fillStyle = '#ffffff';
      g.fillText(String(chunk.text ?? ''), x(onset) + 3, top + ROW / 2, Math.max(10, x(end) - x(onset) - 6));
    }
  }

  drawWords(g, words, top, x) {
    for (const word of words) {
      const from = number(word.start);
      const to = number(word.end);
      if (from === null || to === null) continue;
      g.fillStyle = '#4a5568';
      g.fillRect(x(from), top + 2, Math.max(1, x(to) - x(from) - 1), ROW - 4);
      g.fillStyle = '#e8eaed';
      g.fillText(String(word.text ?? ''), x(from) + 2, top + ROW / 2, Math.max(4, x(to) - x(from) - 3));
    }
  }

  drawBehavior(g, behavior, top, x) {
    for (const span of phasesOf(behavior)) {
      g.fillStyle = PHASE_COLOURS[span.phase];
      g.fillRect(x(span.from), top + 3, Math.max(1, x(span.to) - x(span.from)), ROW - 6);
    }
    const affiliate = behavior.affiliate ?? {};
    const onset = number(affiliate.onset);
    const end = number(affiliate.end);
    if (onset !== null && end !== null) {
      g.strokeStyle = '#ffffff';
      g.setLineDash([3, 2]);
      g.strokeRect(x(onset), top + 1.5, x(end) - x(onset), ROW - 3);
      g.setLineDash([]);
    }
  }

  drawAxis(g, top, x, width) {
    const duration = this.timeline.duration;
    const step = [0.1, 0.25, 0.5, 1, 2, 5, 10, 30, 60].find((s) => duration / s <= 12) ?? 120;
    g.fillStyle = '#9aa0a8';
    g.strokeStyle = '#4a5058';
    for (let t = 0; t <= duration + 1e-9; t += step) {
      g.beginPath();
      g.moveTo(x(t), 0);
      g.lineTo(x(t), top + 4);
      g.stroke();
      if (x(t) < width - 20) g.fillText(`${+t.toFixed(2)}`, x(t) + 2, top + AXIS / 2);
    }
  }

  // Draw the playhead at time t (seconds) and mark the chunks and behaviours active then.
  update(t) {
    this.lastTime = t;
    if (!this.x) return;
    const g = this.strip.getContext('2d');
    const ratio = window.devicePixelRatio || 1;
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.drawImage(this.background, 0, 0);
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.strokeStyle = '#ff4d4d';
    g.lineWidth = 2;
    g.beginPath();
    g.moveTo(this.x(t), 0);
    g.lineTo(this.x(t), this.height);
    g.stroke();
    g.lineWidth = 1;
    for (const { element, from, to } of this.items) element.classList.toggle('active', t >= from && t <= to);
  }

  renderList() {
    const t = this.timeline;
    const root = this.listElement;
    root.replaceChildren();
    this.items = [];
    const section = (title) => {
      const heading = document.createElement('h3');
      heading.textContent = title;
      root.append(heading);
    };
    const entry = (parent, tag, text, data) => {
      const element = document.createElement(tag);
      element.textContent = text;
      Object.assign(element.dataset, data);
      parent.append(element);
      return element;
    };

    section('Chunks');
    const chunks = document.createElement('ol');
    chunks.className = 'mura-chunks';
    root.append(chunks);
    t.chunks.forEach((chunk, i) => {
      const states = stateSpans(chunk, t.duration).map((s) => `${s.state} ${seconds(s.from)}`).join(' · ');
      const onset = number(chunk.speech_onset);
      const end = number(chunk.speech_end);
      const text = `chunk ${chunk.index ?? i}: “${chunk.text ?? ''}” — speech ${seconds(onset)}–${seconds(end)} s — ${states}`;
      const element = entry(chunks, 'li', text, { chunk: String(chunk.index ?? i) });
      if (onset !== null && end !== null) this.items.push({ element, from: onset, to: end });
    });

    section('Behaviours');
    const behaviors = document.createElement('ul');
    behaviors.className = 'mura-behaviors';
    root.append(behaviors);
    t.behaviors.forEach((behavior, i) => {
      const phases = phasesOf(behavior);
      const arms = list(behavior.arms).join('+');
      const affiliate = behavior.affiliate ?? {};
      const parts = phases.map((p) => `${p.phase} ${seconds(p.from)}–${seconds(p.to)} s`);
      if (number(affiliate.onset) !== null) {
        parts.push(`affiliate ${seconds(number(affiliate.onset))}–${seconds(number(affiliate.end))} s`);
      }
      const id = String(behavior.id ?? `behavior ${i}`);
      const head = `${id} (chunk ${behavior.chunk ?? '?'}${arms ? `, ${arms}` : ''})`;
      const element = entry(behaviors, 'li', `${head}: ${parts.join(', ')}`, { behavior: id });
      if (phases.length) this.items.push({ element, from: phases[0].from, to: phases[phases.length - 1].to });
    });

    section('Words');
    entry(
      root,
      'p',
      t.words.map((w) => `${w.text ?? ''} ${seconds(number(w.start))}–${seconds(number(w.end))}`).join(' · '),
      {},
    ).className = 'mura-words';

    const tags = Object.entries(t.timeTags);
    if (tags.length) {
      section('Time tags');
      entry(root, 'p', tags.map(([id, time]) => `${id} ${seconds(number(time))}`).join(' · '), {}).className =
        'mura-time-tags';
    }
  }
}
