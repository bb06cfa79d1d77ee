// @ts-check
/**
 * The transport (record, play / pause, stop, time, speed, loop, punch-in or additive,
 * count-in, loop recording, capture speed) and the timeline under it (drag: scrub;
 * shift-drag: set the loop range; the selected object's takes drawn as bars).
 */
import { fitCanvas } from './canvas.js';
import { formatTime, tickStep, viewRange } from './timescale.js';

/**
 * @param {string} tag
 * @param {Record<string, string>} [attrs]
 * @param {string} [text]
 */
export function el(tag, attrs = {}, text = '') {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  if (text) node.textContent = text;
  return node;
}

/**
 * A labelled select.
 * @param {string} label
 * @param {[string, string][]} options value, text
 * @param {string} value
 * @param {(value: string) => void} onChange
 * @param {string} testid
 */
function choice(label, options, value, onChange, testid) {
  const wrap = el('label', { class: 'field' }, label);
  const select = /** @type {HTMLSelectElement} */ (el('select', { 'data-testid': testid }));
  for (const [v, text] of options) select.append(el('option', { value: v }, text));
  select.value = value;
  select.addEventListener('change', () => onChange(select.value));
  wrap.append(select);
  return wrap;
}

export class Timeline {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} bar      the transport's buttons
   * @param {HTMLCanvasElement} canvas
   */
  constructor(studio, bar, canvas) {
    this.studio = studio;
    this.canvas = canvas;
    const s = studio;
    this.recordButton = /** @type {HTMLButtonElement} */ (el('button', { class: 'record', 'data-testid': 'record', title: 'Record mode (R): every grab is a take' }));
    this.recordButton.innerHTML = '<span class="dot"></span><span class="label">REC</span>';
    this.recordButton.addEventListener('click', () => s.setRecord(!s.record));
    this.stopButton = el('button', { 'data-testid': 'stop', title: 'Stop (Enter): back to the start' }, '■');
    this.stopButton.addEventListener('click', () => s.stop());
    this.playButton = el('button', { class: 'play', 'data-testid': 'play', title: 'Play / pause (Space)' }, '▶');
    this.playButton.addEventListener('click', () => (s.clock.playing ? s.pause() : s.play()));
    this.clockText = el('span', { class: 'clock', 'data-testid': 'time' }, '0:00.00');
    this.loopButton = el('button', { class: 'toggle', 'data-testid': 'loop', title: 'Loop the range (L); shift-drag on the timeline sets it' }, '⟲ loop');
    this.loopButton.addEventListener('click', () => s.setLoop(s.clock.loop ? null : this.lastLoop ?? this.defaultLoop()));
    /** @type {[number, number] | null} */
    this.lastLoop = null;
    const speed = choice('speed', [['0.25', '¼×'], ['0.5', '½×'], ['1', '1×'], ['2', '2×'], ['-1', '−1×']], '1',
      (v) => s.setSpeed(Number(v)), 'speed');
    const mode = choice('layer', [['replace', 'punch-in'], ['additive', 'additive']], s.mode,
      (v) => { s.mode = /** @type {'replace' | 'additive'} */ (v); }, 'mode');
    const countIn = choice('count-in', [['0', 'off'], ['1', '1 s'], ['2', '2 s'], ['4', '4 s']], '0',
      (v) => { s.countIn = Number(v); }, 'count-in');
    const capture = choice('capture', [['1', '1×'], ['0.5', '½×'], ['0.25', '¼×']], '1',
      (v) => { s.captureSpeed = Number(v); }, 'capture-speed');
    capture.title = 'Perform with the transport at a fraction of real time; the motion plays at full speed';
    const loopRec = el('label', { class: 'field check', title: 'While looping, each pass is a take; the last one is kept' });
    const loopRecBox = /** @type {HTMLInputElement} */ (el('input', { type: 'checkbox', 'data-testid': 'loop-record' }));
    loopRecBox.addEventListener('change', () => { s.loopRecord = loopRecBox.checked; });
    loopRec.append(loopRecBox, 'loop rec');
    this.undoButton = /** @type {HTMLButtonElement} */ (el('button', { 'data-testid': 'undo', title: 'Undo (Ctrl+Z)' }, '↶ undo'));
    this.undoButton.addEventListener('click', () => s.undo());
    this.redoButton = /** @type {HTMLButtonElement} */ (el('button', { 'data-testid': 'redo', title: 'Redo (Ctrl+Shift+Z)' }, '↷ redo'));
    this.redoButton.addEventListener('click', () => s.redo());
    this.status = el('span', { class: 'take-status', 'data-testid': 'take-status' });
    const group = (/** @type {HTMLElement[]} */ ...items) => { const g = el('div', { class: 'group' }); g.append(...items); return g; };
    bar.append(group(this.recordButton, mode, countIn, capture, loopRec),
      group(this.stopButton, this.playButton, this.clockText, speed, this.loopButton),
      this.status, group(this.undoButton, this.redoButton));
    s.on('history', () => this.showHistory());
    s.on('state', () => this.showHistory());
    s.on('record', () => this.showTransport());
    s.on('transport', () => this.showTransport());
    s.on('frame', () => this.draw());
    this.bindCanvas();
  }

  /** @returns {[number, number]} */
  defaultLoop() {
    const [a, b] = this.studio.span;
    return b > a ? [a, b] : [0, 4];
  }

  showHistory() {
    const h = this.studio.history;
    this.undoButton.disabled = !h.can_undo;
    this.redoButton.disabled = !h.can_redo;
    this.undoButton.title = h.can_undo ? `Undo ${h.undo[h.undo.length - 1]} (Ctrl+Z)` : 'Nothing to undo';
    this.redoButton.title = h.can_redo ? `Redo ${h.redo[h.redo.length - 1]} (Ctrl+Shift+Z)` : 'Nothing to redo';
  }

  showTransport() {
    const s = this.studio;
    this.recordButton.classList.toggle('on', s.record);
    this.recordButton.setAttribute('aria-pressed', String(s.record));
    document.body.classList.toggle('recording', s.record);
    this.playButton.textContent = s.clock.playing ? '❚❚' : '▶';
    this.loopButton.classList.toggle('on', !!s.clock.loop);
    if (s.clock.loop) this.lastLoop = s.clock.loop;
  }

  /** @param {number} x client x */
  timeAt(x) {
    const rect = this.canvas.getBoundingClientRect();
    const [t0, t1] = this.range();
    return t0 + ((x - rect.left) / rect.width) * (t1 - t0);
  }

  range() {
    const s = this.studio;
    return viewRange(s.span, s.clock.loop, s.time);
  }

  bindCanvas() {
    /** @type {{loopFrom: number | null} | null} */
    let drag = null;
    this.canvas.addEventListener('pointerdown', (e) => {
      this.canvas.setPointerCapture(e.pointerId);
      const t = this.timeAt(e.clientX);
      drag = { loopFrom: e.shiftKey ? t : null };
      if (!e.shiftKey) this.studio.seek(t);
    });
    this.canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const t = this.timeAt(e.clientX);
      if (drag.loopFrom === null) this.studio.seek(t);
      else this.studio.setLoop([Math.min(drag.loopFrom, t), Math.max(drag.loopFrom, t)]);
    });
    const end = () => { drag = null; };
    this.canvas.addEventListener('pointerup', end);
    this.canvas.addEventListener('pointercancel', end);
  }

  draw() {
    const s = this.studio;
    this.clockText.textContent = formatTime(s.time);
    const counting = s.countingIn;
    const grab = s.grab;
    this.status.textContent = counting > 0 ? `count-in ${counting.toFixed(1)} s`
      : grab?.take ? `● recording ${grab.paths.join(', ')} · ${grab.take.times.length} samples`
        : s.record ? 'record mode: grab something to record it' : '';
    this.status.classList.toggle('live', !!grab?.take);
    const { g, w, h } = fitCanvas(this.canvas);
    g.fillStyle = '#17191e';
    g.fillRect(0, 0, w, h);
    const [t0, t1] = this.range();
    const x = (/** @type {number} */ t) => ((t - t0) / (t1 - t0)) * w;
    if (s.clock.loop) {
      g.fillStyle = 'rgba(90, 150, 255, 0.18)';
      g.fillRect(x(s.clock.loop[0]), 0, x(s.clock.loop[1]) - x(s.clock.loop[0]), h);
      g.fillStyle = '#5a96ff';
      g.fillRect(x(s.clock.loop[0]), 0, 2, h);
      g.fillRect(x(s.clock.loop[1]) - 2, 0, 2, h);
    }
    const step = tickStep(w / (t1 - t0));
    g.font = '10px system-ui, sans-serif';
    g.fillStyle = '#8b93a3';
    g.strokeStyle = '#3a404c';
    g.beginPath();
    for (let t = Math.ceil(t0 / step) * step; t <= t1; t += step) {
      const xt = Math.round(x(t)) + 0.5;
      g.moveTo(xt, 0);
      g.lineTo(xt, 8);
      g.fillText(`${+t.toFixed(3)}s`, xt + 3, 10);
    }
    g.stroke();
    // the selected object's takes, one row per animated attribute
    const name = s.selected;
    let row = 0;
    for (const track of s.tracks.values()) {
      if (!name || !track.path.startsWith(`${name}.`) || track.kind !== 'curve') continue;
      const y = 15 + row * 7;
      row += 1;
      g.fillStyle = track.path === `${name}.${s.attribute}` ? '#e8b04b' : '#6b7385';
      g.fillRect(x(track.start), y, Math.max(x(track.end) - x(track.start), 2), 4);
      g.fillStyle = 'rgba(255,255,255,0.55)';
      for (const take of track.takes) g.fillRect(x(take.start), y, 1, 4);
    }
    if (grab?.take && grab.take.times.length) {
      g.fillStyle = '#ff4d4d';
      const a = grab.take.times[0];
      g.fillRect(x(a), h - 6, Math.max(x(grab.take.last) - x(a), 2), 4);
    }
    if (counting > 0) {
      g.fillStyle = 'rgba(255, 77, 77, 0.25)';
      g.fillRect(x(s.time), 0, x(s.punchFrom) - x(s.time), h);
    }
    g.fillStyle = s.record ? '#ff4d4d' : '#ffffff';
    g.fillRect(Math.round(x(s.time)) - 1, 0, 2, h);
  }
}
