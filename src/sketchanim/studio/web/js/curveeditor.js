// @ts-check
/**
 * The curve editor: the selected object's attribute (or all its animated attributes) as value
 * against time, channel by channel, on one canvas. For each track: the samples its curve keeps
 * (dots), the tolerance band (curve ± tol), the curve, its control points (squares, at their
 * Greville abscissae) and its keys (diamonds: its value at each distinct knot and the ends; a
 * selected key shows its tangent handles). Positions can show their speed instead (view only).
 * Orientations show as continuous Euler angles (degrees, 'XYZ'), the curve staying a
 * quaternion spline: their keys drag (the Euler value turned back into a quaternion on the
 * curve's hemisphere), their control points do not (they are quaternions).
 *
 * Gestures (each one History step, sent on release; the preview changes a copy of the curve
 * in the page only; Escape cancels and sends nothing): drag a control point or several
 * (`curve.points`), a key (`curve.key` with its value; several keys: their least change as
 * `curve.points`), a key's handle (`curve.key` with the slope); I inserts a knot at the
 * playhead, a double-click on a curve one at that time; Delete removes the selected keys'
 * knots (`curve.knots`); drag on empty space box-selects (Shift adds; Shift-click toggles);
 * Home frames all, F the selection; the wheel zooms time (Ctrl or Shift: values); a middle
 * or Alt drag pans; N normalises each channel to -1..1. The selection is the studio's
 * (`studio.points`), shared with the viewport's motion paths.
 *
 * Drawing is cached: every track's sampled curve and its points' screen positions are
 * computed when the curve or the view changes; what does not move is drawn once into a
 * layer that each frame copies, and a frame draws only when something changed. Marks are
 * drawn once per 3 px cell, and not at all for a track denser than one per 4 px (zoom in); hit tests search the points, sorted by time, by bisection.
 * While a take is recorded over the shown attribute, its raw trail (dots) and the reduced
 * pieces (thick) grow as the server finishes them.
 */
import { greville, keyKnots, nearestEuler, nearestPoint, quatToEuler, eulerToQuat, rangeOf, response, unwrappedEulers, valueAndSlope } from './curvegeometry.js';
import { sampleCurve } from './evaluate.js';
import { el } from './dom.js';
import { fitCanvas } from './canvas.js';
import { formatTolerance } from './resolution.js';
import { tickStep, viewRange } from './timescale.js';
import { ToleranceBar } from './tolerancebar.js';

const CHANNELS = ['#ff6b6b', '#5cd65c', '#5aa0ff', '#c8c8c8', '#e0a0ff'];
const NAMES = { position: 'xyz', scale: 'xyz', orientation: 'xyz', color: 'rgb' };
/** Pixels of the plot's margins (top, bottom: the time labels). */
const TOP = 8;
const BOTTOM = 16;
/** Pixels within which a point, a key or a handle is hit. */
const HIT = 6;
/** Pixels per point or key below which a track's unselected points and keys are not drawn (zoom in to see them; they are still hit and selected). */
const DENSE = 4;
/** Pixels from a key to its handles' ends. */
const HANDLE = 30;

/** @typedef {import('./messages.js').CurveTrack} CurveTrack */
/** @typedef {import('./Studio.js').PointSelection} PointSelection */

/**
 * @typedef {object} Lane   One track as the editor shows it.
 * @property {string} path
 * @property {import('./messages.js').AttrType} type
 * @property {CurveTrack} curve     the server's
 * @property {CurveTrack} shown     the server's, or the copy a drag previews
 * @property {boolean} euler        an orientation shown as Euler angles
 * @property {boolean} speed        shown as its speed (positions, when the speed graph is on)
 * @property {number} dims          channels drawn
 * @property {{a: number, b: number}[]} map   display value = a * value + b, per channel (normalised or not)
 * @property {{times: Float64Array, eulers: [number, number, number][]} | null} ref   an orientation's Euler angles on a fine grid (the branch every Euler value shown is nearest to)
 * @property {Float64Array} pt      control points' times (Greville)
 * @property {Float64Array[]} pv    control points' display values per channel
 * @property {Int32Array} kk        keys' knot indices
 * @property {Float64Array} kt      keys' times
 * @property {Float64Array[]} kv    keys' display values per channel
 * @property {Float64Array[]} ks    keys' display slopes per channel (per second)
 * @property {Map<number, number>} keyOf   key number by knot index
 * @property {{times: Float64Array, values: Float64Array[]} | null} dots   the kept samples, display values
 * @property {{times: Float64Array, values: Float64Array[]}} line  the curve over the view, display values
 * @property {Float32Array} px      screen positions, recomputed when the view or the curve changes
 * @property {Float32Array[]} py
 * @property {Float32Array} kx
 * @property {Float32Array[]} ky
 * @property {Float32Array} dx
 * @property {Float32Array[]} dy
 * @property {string} at            the view the screen positions are for
 */

/**
 * @typedef {object} View   The plotted window: seconds and display values.
 * @property {number} t0
 * @property {number} t1
 * @property {number} v0
 * @property {number} v1
 */

/**
 * @typedef {object} Hit
 * @property {Lane} lane
 * @property {'point' | 'key' | 'handle'} kind
 * @property {number} i    the point's or key's number in the lane
 * @property {number} ch
 */

/**
 * @typedef {object} Drag   A gesture in progress.
 * @property {'move' | 'handle' | 'box' | 'pan'} kind
 * @property {number} x0    where it began (canvas pixels)
 * @property {number} y0
 * @property {number} x
 * @property {number} y
 * @property {boolean} moved
 * @property {Hit} [hit]
 * @property {'point' | 'key'} [what]
 * @property {{lane: Lane, coef: number[][], items: number[], u: Float64Array | null, times: number[]}[]} [lanes]
 * @property {View} [view]
 * @property {PointSelection[]} [base]  the selection a box adds to
 * @property {number[] | null} [quat]   an orientation key's value being dragged to
 */

/**
 * A display map of a channel: identity, or normalised so `lo`..`hi` shows as -1..1.
 * @param {boolean} normalise
 * @param {number} lo
 * @param {number} hi
 */
function channelMap(normalise, lo, hi) {
  if (!normalise || !(hi > lo)) return normalise && Number.isFinite(lo) ? { a: 1, b: -lo } : { a: 1, b: 0 };
  return { a: 2 / (hi - lo), b: -(hi + lo) / (hi - lo) };
}

export class CurveEditor {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root
   */
  constructor(studio, root) {
    this.studio = studio;
    root.dataset.testid = 'curves';
    this.title = el('span', { class: 'curve-title' });
    this.allBox = /** @type {HTMLInputElement} */ (el('input', { type: 'checkbox', 'data-testid': 'curve-all' }));
    const all = el('label', { class: 'toggle', title: "Show every animated attribute of the object, not only the inspector's" });
    all.append(this.allBox, 'all attributes');
    this.speedButton = el('button', { class: 'small toggle', 'data-testid': 'curve-speed', title: 'Positions: show the speed (view only) instead of the values' }, 'speed');
    this.normButton = el('button', { class: 'small toggle', 'data-testid': 'curve-normalise', title: 'Each channel scaled to -1..1 (N)' }, 'normalise');
    this.note = el('span', { class: 'note', 'data-testid': 'curve-note' });
    this.tolerance = new ToleranceBar(studio, () => { this.overlayVersion += 1; });
    const head = el('div', { class: 'curve-head' });
    head.append(this.title, all, this.speedButton, this.normButton, this.tolerance.root, this.note);
    this.canvas = /** @type {HTMLCanvasElement} */ (el('canvas', { 'data-testid': 'curve-editor', tabindex: '0' }));
    root.append(head, this.canvas);
    /** The layer of what does not move, drawn once and copied each frame. */
    this.layer = document.createElement('canvas');
    // Both drawn on the CPU: thousands of small marks rasterise far faster there than through
    // the GPU's path rendering (with a software GL, by orders of magnitude). The first
    // getContext's options stay the canvas's.
    for (const c of [this.canvas, this.layer]) c.getContext('2d', { willReadFrequently: true });
    this.normalised = false;
    this.speed = false;
    /** @type {Lane[]} */
    this.lanes = [];
    this.lanesDirty = true;
    /** Counts the lanes' builds (the automatic view is computed again after one). */
    this.version = 0;
    /** @type {{key: string, view: View} | null} the automatic view, and what it was computed for */
    this.auto = null;
    /** @type {View | null} the view the animator chose (null: follow the tracks and the playhead) */
    this.view = null;
    /** @type {[number, number] | null} the automatic value range (grows during a take, never jumps) */
    this.yRange = null;
    /** @type {Drag | null} */
    this.drag = null;
    /** @type {Set<string>} paths drawn over the layer each frame (being dragged) */
    this.moving = new Set();
    /** @type {Map<string, import('./messages.js').Samples>} the samples each curve keeps, by path */
    this.samples = new Map();
    /** @type {Map<string, CurveTrack>} the curve each path's samples were asked for */
    this.asked = new Map();
    this.layerKey = '';
    this.frameKey = '';
    this.overlayVersion = 0;
    this.lastTitle = '';
    /** Script milliseconds of the last frames the editor drew, and of its pointer moves (a drag's preview), for benchmarks. */
    this.stats = { draw: /** @type {number[]} */ ([]), move: /** @type {number[]} */ ([]) };
    for (const signal of /** @type {const} */ (['selection', 'attribute', 'tracks', 'state'])) {
      studio.signals.on(signal, () => { this.lanesDirty = true; });
    }
    studio.signals.on('selection', () => { this.view = null; this.yRange = null; });
    studio.signals.on('attribute', () => { this.view = null; this.yRange = null; });
    studio.signals.on('points', () => { this.overlayVersion += 1; });
    studio.signals.on('tracks', () => this.dropStaleDrag());
    studio.signals.on('samples', (m) => { this.samples.set(m.path, m); this.lanesDirty = true; });
    studio.signals.on('command', (c) => this.command(c));
    studio.signals.on('frame', () => this.frame());
    this.allBox.addEventListener('change', () => { this.lanesDirty = true; this.view = null; });
    this.speedButton.addEventListener('click', () => { this.speed = !this.speed; this.lanesDirty = true; this.view = null; });
    this.normButton.addEventListener('click', () => this.command('normalise'));
    this.bind();
  }

  // -- the tracks shown -------------------------------------------------------------------

  /** The paths shown: the inspector's attribute, or every animated continuous attribute of the object. */
  shownPaths() {
    const s = this.studio;
    if (!s.selected) return [];
    const own = `${s.selected}.${s.attribute}`;
    if (!this.allBox.checked) return [own];
    const obj = s.objectOf(s.selected);
    const paths = (obj?.attributes ?? []).filter((a) => a.type.continuous).map((a) => `${s.selected}.${a.name}`)
      .filter((p) => p === own || s.tracks.get(p)?.kind === 'curve');
    return [own, ...paths.filter((p) => p !== own)];
  }

  /** Build the lanes again (the tracks, the selection or a mode changed). */
  buildLanes() {
    const s = this.studio;
    const paths = this.shownPaths();
    /** @type {Lane[]} */
    const lanes = [];
    for (const path of paths) {
      const track = s.tracks.get(path);
      const type = s.types.get(path);
      if (!type || track?.kind !== 'curve' || !track.coef.length) continue;
      const euler = !!track.rotation;
      const speed = this.speed && type.name === 'position';
      const lane = /** @type {Lane} */ (/** @type {unknown} */ ({ path, type, curve: track, shown: track, euler, speed,
        dims: speed ? 1 : euler ? 3 : track.dim, map: [], ref: euler ? eulerReference(track) : null, at: '' }));
      this.computeData(lane);
      lane.map = Array.from({ length: lane.dims }, (_, ch) => {
        let lo = Infinity;
        let hi = -Infinity;
        for (const arr of [lane.kv[ch], lane.speed || lane.euler ? null : lane.pv[ch]]) {
          if (arr) for (const v of arr) { if (v < lo) lo = v; if (v > hi) hi = v; }
        }
        return channelMap(this.normalised, lo, hi);
      });
      this.computeData(lane);                       // again, in the mapped units
      lanes.push(lane);
      if (track.takes.length && this.asked.get(path) !== track) {
        this.asked.set(path, track);
        s.askSamples(path);
      }
    }
    this.lanes = lanes;
    this.lanesDirty = false;
    this.version += 1;
    this.tolerance.setTracks(lanes[0]?.path ?? paths[0] ?? null, lanes.length ? lanes.map((l) => l.path) : paths);
    this.layerKey = '';
  }

  /**
   * A lane's points, keys and kept samples in display units, from its shown curve.
   * @param {Lane} lane
   */
  computeData(lane) {
    const c = lane.shown;
    const map = lane.map.length ? lane.map : Array.from({ length: lane.dims }, () => ({ a: 1, b: 0 }));
    lane.pt = greville(c.knots, c.order);
    lane.pv = Array.from({ length: lane.dims }, (_, ch) => Float64Array.from(c.coef, (row) => map[ch].a * row[ch] + map[ch].b));
    lane.kk = keyKnots(c.knots, c.order);
    lane.kt = Float64Array.from(lane.kk, (i) => c.knots[i]);
    lane.kv = Array.from({ length: lane.dims }, () => new Float64Array(lane.kk.length));
    lane.ks = Array.from({ length: lane.dims }, () => new Float64Array(lane.kk.length));
    lane.keyOf = new Map(Array.from(lane.kk, (k, i) => [k, i]));
    this.keyValues(lane, 0, lane.kt.length);
    const kept = this.samples.get(lane.path);
    lane.dots = null;
    if (kept && !lane.speed && this.asked.get(lane.path) === lane.curve) {
      const values = Array.from({ length: lane.dims }, () => new Float64Array(kept.times.length));
      kept.times.forEach((t, i) => {
        const v = lane.euler ? nearestEuler(quatToEuler(kept.values[i]), refAt(lane, t)) : kept.values[i];
        for (let ch = 0; ch < lane.dims; ch++) values[ch][i] = map[ch].a * v[ch] + map[ch].b;
      });
      lane.dots = { times: Float64Array.from(kept.times), values };
    }
    lane.at = '';
  }

  /**
   * The display values and slopes of keys a .. b-1 of a lane, from its shown curve.
   * @param {Lane} lane @param {number} a @param {number} b
   */
  keyValues(lane, a, b) {
    const c = lane.shown;
    const map = lane.map.length ? lane.map : Array.from({ length: lane.dims }, () => ({ a: 1, b: 0 }));
    const low = c.bounds?.[0] ?? -Infinity;
    const high = c.bounds?.[1] ?? Infinity;
    for (let i = a; i < b; i++) {
      const t = lane.kt[i];
      const { value, slope } = valueAndSlope(c.knots, c.order, c.coef, t);
      const shown = this.displayed(lane, t, value, slope);
      for (let ch = 0; ch < lane.dims; ch++) {
        lane.kv[ch][i] = map[ch].a * (lane.euler ? shown.value[ch] : Math.min(Math.max(shown.value[ch], low), high)) + map[ch].b;
        lane.ks[ch][i] = map[ch].a * shown.slope[ch];
      }
    }
  }

  /**
   * A drag's preview changed control points `first` .. `last` of a lane's shown curve: their
   * display values and the keys over their spans again (the rest stays).
   * @param {Lane} lane @param {number} first @param {number} last
   */
  reshaped(lane, first, last) {
    const c = lane.shown;
    for (let ch = 0; ch < lane.dims; ch++) {
      const { a, b } = lane.map[ch];
      for (let j = first; j <= last; j++) lane.pv[ch][j] = a * c.coef[j][ch] + b;
    }
    const [ka, kb] = rangeOf(lane.kt, c.knots[first], c.knots[Math.min(last + c.order, c.knots.length - 1)]);
    this.keyValues(lane, ka, kb);
    lane.at = '';
  }

  /**
   * A raw value and slope of a lane's curve as shown: itself, the speed, or Euler angles.
   * @param {Lane} lane
   * @param {number} t
   * @param {number[]} value
   * @param {number[]} slope
   * @returns {{value: number[], slope: number[]}}
   */
  displayed(lane, t, value, slope) {
    if (lane.speed) return { value: [Math.hypot(...slope)], slope: [0] };
    if (lane.euler) {
      const norm = Math.hypot(...value);
      return { value: nearestEuler(quatToEuler(value.map((v) => v / norm)), refAt(lane, t)), slope: [0, 0, 0] };
    }
    return { value, slope };
  }

  /**
   * Sample a lane's curve over the view's time, in display units.
   * @param {Lane} lane
   * @param {View} view
   * @param {number} count
   */
  sampleLine(lane, view, count) {
    const c = lane.shown;
    const map = lane.map;
    const values = Array.from({ length: lane.dims }, () => new Float64Array(count));
    const times = new Float64Array(count);
    if (lane.speed) {
      for (let i = 0; i < count; i++) {
        const t = view.t0 + ((view.t1 - view.t0) * i) / (count - 1);
        times[i] = t;
        const inside = t >= c.knots[c.order - 1] && t <= c.knots[c.knots.length - c.order];
        values[0][i] = map[0].a * (inside ? Math.hypot(...valueAndSlope(c.knots, c.order, c.coef, t).slope) : 0) + map[0].b;
      }
      return { times, values };
    }
    const played = sampleCurve(c, view.t0, view.t1, count);
    for (let i = 0; i < count; i++) {
      times[i] = played.times[i];
      if (lane.euler) {
        const e = nearestEuler(quatToEuler(played.values.map((ch) => ch[i])), refAt(lane, played.times[i]));
        for (let ch = 0; ch < 3; ch++) values[ch][i] = map[ch].a * e[ch] + map[ch].b;
      } else {
        for (let ch = 0; ch < lane.dims; ch++) values[ch][i] = map[ch].a * played.values[ch][i] + map[ch].b;
      }
    }
    return { times, values };
  }

  /**
   * The lane's curve, points and keys at the view's screen positions (when either changed).
   * @param {Lane} lane
   * @param {View} view
   * @param {number} w
   * @param {number} h
   */
  place(lane, view, w, h) {
    const key = `${view.t0},${view.t1},${view.v0},${view.v1},${w},${h}`;
    if (lane.at === key) return;
    lane.line = this.sampleLine(lane, view, Math.max(2, Math.round(w / 2)));                 // a sample per 2 px
    const X = (/** @type {number} */ t) => ((t - view.t0) / (view.t1 - view.t0)) * w;
    const ph = h - TOP - BOTTOM;
    const Y = (/** @type {number} */ v) => TOP + ((view.v1 - v) / (view.v1 - view.v0)) * ph;
    lane.px = Float32Array.from(lane.pt, X);
    lane.py = lane.pv.map((vs) => Float32Array.from(vs, Y));
    lane.kx = Float32Array.from(lane.kt, X);
    lane.ky = lane.kv.map((vs) => Float32Array.from(vs, Y));
    lane.dx = lane.dots ? Float32Array.from(lane.dots.times, X) : new Float32Array(0);
    lane.dy = lane.dots ? lane.dots.values.map((vs) => Float32Array.from(vs, Y)) : [];
    lane.at = key;
  }

  // -- the view -----------------------------------------------------------------------------

  /**
   * The view to draw: the animator's, or one that holds the tracks, the loop and the playhead
   * (its value range grown to what is drawn).
   * @param {number} w
   * @param {number} h
   * @returns {View}
   */
  currentView(w, h) {
    if (this.view) return this.view;
    if (this.drag && this.auto) return this.auto.view;          // still while dragging
    const s = this.studio;
    const [t0, t1] = viewRange(s.span, s.transport.clock.loop, s.transport.time);
    const trail = this.trail();
    const key = `${t0},${t1},${w},${h}|${this.version}|${trail ? trail.times.length : -1}`;
    if (this.auto?.key === key) return this.auto.view;
    let lo = Infinity;
    let hi = -Infinity;
    const see = (/** @type {number} */ v) => { if (v < lo) lo = v; if (v > hi) hi = v; };
    const probe = { t0, t1, v0: 0, v1: 1 };
    for (const lane of this.lanes) {
      for (const vs of this.sampleLine(lane, probe, Math.max(2, Math.round(w / 2))).values) vs.forEach(see);
      const [a, b] = rangeOf(lane.kt, t0, t1);
      for (const vs of lane.kv) for (let i = a; i < b; i++) see(vs[i]);
    }
    if (trail && !this.speed) for (const row of trail.values) row.forEach(see);
    if (!Number.isFinite(lo)) {
      const own = s.selected ? s.values.get(`${s.selected}.${s.attribute}`) : null;
      (Array.isArray(own) ? own : [0]).forEach((v) => typeof v === 'number' && see(v));
    }
    if (trail?.live && this.yRange) { see(this.yRange[0]); see(this.yRange[1]); }
    if (hi - lo < 1e-6) { lo -= 0.5; hi += 0.5; }
    this.yRange = [lo, hi];
    const pad = (hi - lo) * 0.08;
    this.auto = { key, view: { t0, t1, v0: lo - pad, v1: hi + pad } };
    return this.auto.view;
  }

  /** The animator's view from now on: the current one, to zoom or pan from. */
  ownView() {
    if (!this.view) {
      const { w, h } = this.size();
      this.view = { ...this.currentView(w, h) };
    }
    return this.view;
  }

  size() {
    return { w: this.canvas.clientWidth, h: this.canvas.clientHeight };
  }

  /**
   * Frame a time span and value range (padded).
   * @param {number} t0 @param {number} t1 @param {number} v0 @param {number} v1
   */
  frameOn(t0, t1, v0, v1) {
    if (!(t1 - t0 > 1e-6)) { t0 -= 0.5; t1 += 0.5; }
    if (!(v1 - v0 > 1e-9)) { v0 -= 0.5; v1 += 0.5; }
    const pt = (t1 - t0) * 0.05;
    const pv = (v1 - v0) * 0.08;
    this.view = { t0: t0 - pt, t1: t1 + pt, v0: v0 - pv, v1: v1 + pv };
  }

  /** Home: every shown curve, whole. */
  frameAll() {
    let t0 = Infinity, t1 = -Infinity, v0 = Infinity, v1 = -Infinity;
    for (const lane of this.lanes) {
      t0 = Math.min(t0, lane.kt[0]);
      t1 = Math.max(t1, lane.kt[lane.kt.length - 1]);
      for (const vs of [...lane.kv, ...(lane.euler || lane.speed ? [] : lane.pv)]) for (const v of vs) { if (v < v0) v0 = v; if (v > v1) v1 = v; }
      const line = this.sampleLine(lane, { t0: lane.kt[0], t1: lane.kt[lane.kt.length - 1], v0: 0, v1: 1 }, 512);
      for (const vs of line.values) for (const v of vs) { if (v < v0) v0 = v; if (v > v1) v1 = v; }
    }
    if (Number.isFinite(t0)) this.frameOn(t0, t1, v0, v1);
    else this.view = null;
  }

  /** F: the selected points and keys. */
  frameSelection() {
    let t0 = Infinity, t1 = -Infinity, v0 = Infinity, v1 = -Infinity;
    for (const { lane, kind, i } of this.selectedItems()) {
      const t = kind === 'point' ? lane.pt[i] : lane.kt[i];
      t0 = Math.min(t0, t); t1 = Math.max(t1, t);
      for (const vs of kind === 'point' ? lane.pv : lane.kv) { v0 = Math.min(v0, vs[i]); v1 = Math.max(v1, vs[i]); }
    }
    if (Number.isFinite(t0)) this.frameOn(t0, t1, v0, v1);
  }

  // -- the selection ------------------------------------------------------------------------

  /** The selected points and keys of the shown lanes. */
  selectedItems() {
    /** @type {{lane: Lane, kind: 'point' | 'key', i: number}[]} */
    const out = [];
    const byPath = new Map(this.lanes.map((l) => [l.path, l]));
    for (const q of this.studio.points) {
      const lane = byPath.get(q.path);
      if (!lane) continue;
      const i = q.kind === 'point' ? (q.index < lane.pt.length && !lane.euler && !lane.speed ? q.index : -1) : lane.keyOf.get(q.index) ?? -1;
      if (i >= 0) out.push({ lane, kind: q.kind, i });
    }
    return out;
  }

  /**
   * The selection's entry for a lane's point or key.
   * @param {Lane} lane @param {'point' | 'key'} kind @param {number} i
   * @returns {PointSelection}
   */
  entry(lane, kind, i) {
    return { path: lane.path, kind, index: kind === 'point' ? i : lane.kk[i] };
  }

  /** @param {PointSelection} q */
  isSelected(q) {
    return this.studio.points.some((p) => p.path === q.path && p.kind === q.kind && p.index === q.index);
  }

  // -- the frame ------------------------------------------------------------------------------

  /** Each animation frame: draw when something changed. */
  frame() {
    const started = performance.now();
    if (this.lanesDirty) this.buildLanes();
    const { g, w, h } = fitCanvas(this.canvas);
    if (w < 2 || h < 2) return;
    const view = this.currentView(w, h);
    for (const lane of this.lanes) this.place(lane, view, w, h);
    const trail = this.trail();
    const live = trail?.live ? `${trail.times.length}/${(this.studio.pieces.get(this.lanes[0]?.path ?? '') ?? []).length}` : '';
    const viewKey = `${w}x${h}|${view.t0},${view.t1},${view.v0},${view.v1}`;
    const layerKey = `${viewKey}|${this.lanes.map((l) => l.curve.knots.length + l.path).join()}|${live}|${[...this.moving].join()}|${this.lanes.map((l) => (l.dots ? 1 : 0)).join('')}`;
    if (layerKey !== this.layerKey || this.lanes.some((l) => !this.moving.has(l.path) && l.shown !== l.curve)) {
      this.drawLayer(view, w, h, trail);
      this.layerKey = layerKey;
    }
    const s = this.studio;
    const frameKey = `${layerKey}|${s.transport.time}|${s.transport.record}|${this.overlayVersion}`;
    if (frameKey !== this.frameKey) {
      this.frameKey = frameKey;
      const dpr = window.devicePixelRatio || 1;
      g.setTransform(1, 0, 0, 1, 0, 0);
      g.drawImage(this.layer, 0, 0);
      g.setTransform(dpr, 0, 0, dpr, 0, 0);
      this.drawOverlay(g, view, w, h);
      this.stats.draw.push(performance.now() - started);
      if (this.stats.draw.length > 600) this.stats.draw.shift();
    }
    this.showTitle(trail);
  }

  /**
   * Draw what does not move into the layer: the grid, the takes, and every lane not being dragged.
   * @param {View} view @param {number} w @param {number} h
   * @param {{times: number[], values: number[][], live: boolean} | null} trail
   */
  drawLayer(view, w, h, trail) {
    const dpr = window.devicePixelRatio || 1;
    this.layer.width = this.canvas.width;
    this.layer.height = this.canvas.height;
    const g = /** @type {CanvasRenderingContext2D} */ (this.layer.getContext('2d'));
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.fillStyle = '#131519';
    g.fillRect(0, 0, w, h);
    const X = (/** @type {number} */ t) => ((t - view.t0) / (view.t1 - view.t0)) * w;
    const ph = h - TOP - BOTTOM;
    const Y = (/** @type {number} */ v) => TOP + ((view.v1 - v) / (view.v1 - view.v0)) * ph;
    // grid and labels
    g.font = '10px system-ui, sans-serif';
    g.strokeStyle = '#262a32';
    g.fillStyle = '#6f7787';
    g.beginPath();
    const tstep = tickStep(w / (view.t1 - view.t0), 70);
    for (let t = Math.ceil(view.t0 / tstep) * tstep; t <= view.t1; t += tstep) {
      const x = Math.round(X(t)) + 0.5;
      g.moveTo(x, TOP); g.lineTo(x, h - BOTTOM);
      g.fillText(`${+t.toFixed(3)}s`, x + 2, h - 4);
    }
    const vstep = tickStep(ph / (view.v1 - view.v0), 28);
    for (let v = Math.ceil(view.v0 / vstep) * vstep; v <= view.v1; v += vstep) {
      const y = Math.round(Y(v)) + 0.5;
      g.moveTo(0, y); g.lineTo(w, y);
      g.fillText(`${+v.toFixed(4)}`, 3, y - 2);
    }
    g.stroke();
    const own = this.lanes[0];
    if (own) {
      g.fillStyle = 'rgba(232, 176, 75, 0.06)';
      for (const take of own.curve.takes) g.fillRect(X(take.start), 0, X(take.end) - X(take.start), h);
    }
    const cells = new Uint32Array(Math.ceil(w / 3 + 1) * Math.ceil(h / 3 + 1));
    const marks = { gen: 0, cells, cw: Math.ceil(w / 3 + 1) };
    this.lanes.forEach((lane, n) => {
      if (!this.moving.has(lane.path)) this.drawLane(g, lane, n, view, w, h, marks, !!trail?.live && n === 0);
    });
    if (trail && !this.speed) this.drawTrail(g, trail, X, Y);
  }

  /**
   * One lane: its band, kept samples, curve, control points and keys.
   * @param {CanvasRenderingContext2D} g
   * @param {Lane} lane
   * @param {number} n  the lane's number (its colours)
   * @param {View} view @param {number} w @param {number} h
   * @param {{gen: number, cells: Uint32Array, cw: number}} marks
   * @param {boolean} dim  a take is recorded over it: the old curve faint
   */
  drawLane(g, lane, n, view, w, h, marks, dim) {
    const ph = h - TOP - BOTTOM;
    const scale = ph / (view.v1 - view.v0);
    const [pa, pb] = rangeOf(lane.pt, view.t0, view.t1);
    const [ka, kb] = rangeOf(lane.kt, view.t0, view.t1);
    const line = lane.line;
    const xs = Float32Array.from(line.times, (t) => ((t - view.t0) / (view.t1 - view.t0)) * w);
    for (let ch = 0; ch < lane.dims; ch++) {
      const colour = this.colour(n, ch);
      const ys = line.values[ch];
      const Y = (/** @type {number} */ v) => TOP + (view.v1 - v) * scale;
      if (!lane.speed) {                                                     // the tolerance band
        const band = lane.curve.tol * lane.map[ch].a;
        g.globalAlpha = 0.12;
        g.fillStyle = colour;
        g.beginPath();
        for (let i = 0; i < xs.length; i++) g.lineTo(xs[i], Y(ys[i] + band));
        for (let i = xs.length - 1; i >= 0; i--) g.lineTo(xs[i], Y(ys[i] - band));
        g.fill();
      }
      if (lane.dots) {                                                       // the kept samples
        g.globalAlpha = 0.45;
        const [da, db] = rangeOf(lane.dx, 0, w);
        dots(g, lane.dx, lane.dy[ch], da, db, 1, marks, h);
      }
      g.globalAlpha = dim ? 0.35 : 0.95;                                     // the curve
      g.strokeStyle = colour;
      g.lineWidth = 1.6;
      g.beginPath();
      for (let i = 0; i < xs.length; i++) g.lineTo(xs[i], Y(ys[i]));
      g.stroke();
      g.lineWidth = 1;
      g.globalAlpha = 0.9;
      if (!lane.euler && !lane.speed && pb - pa <= w / DENSE) {              // control points: hollow squares
        g.strokeStyle = colour;
        marks.gen += 1;
        g.beginPath();
        for (let i = pa; i < pb; i++) {
          const x = lane.px[i], y = lane.py[ch][i];
          if (y < 0 || y > h || !mark(marks, x, y)) continue;
          g.rect(x - 2.5, y - 2.5, 5, 5);
        }
        g.stroke();
      }
      g.fillStyle = '#f4f4f4';                                               // keys: diamonds
      marks.gen += 1;
      g.beginPath();
      for (let i = ka; i < (kb - ka <= w / DENSE ? kb : ka); i++) {
        const x = lane.kx[i], y = lane.ky[ch][i];
        if (y < 0 || y > h || !mark(marks, x, y)) continue;
        g.moveTo(x, y - 3.5); g.lineTo(x + 3.5, y); g.lineTo(x, y + 3.5); g.lineTo(x - 3.5, y); g.closePath();
      }
      g.fill();
      g.globalAlpha = 1;
    }
  }

  /**
   * What moves: the lanes being dragged, the selection and its handles, the preview of a
   * tolerance, the box being drawn, the playhead.
   * @param {CanvasRenderingContext2D} g
   * @param {View} view @param {number} w @param {number} h
   */
  drawOverlay(g, view, w, h) {
    const s = this.studio;
    const X = (/** @type {number} */ t) => ((t - view.t0) / (view.t1 - view.t0)) * w;
    const ph = h - TOP - BOTTOM;
    const Y = (/** @type {number} */ v) => TOP + ((view.v1 - v) / (view.v1 - view.v0)) * ph;
    const cells = new Uint32Array(Math.ceil(w / 3 + 1) * Math.ceil(h / 3 + 1));
    const marks = { gen: 0, cells, cw: Math.ceil(w / 3 + 1) };
    this.lanes.forEach((lane, n) => { if (this.moving.has(lane.path)) this.drawLane(g, lane, n, view, w, h, marks, false); });
    // tolerance previews: dashed
    g.setLineDash([5, 4]);
    g.lineWidth = 1.4;
    this.lanes.forEach((lane, n) => {
      const preview = this.tolerance.preview.get(lane.path);
      if (!preview || lane.speed) return;
      const ghost = { ...lane, shown: preview };
      const line = this.sampleLine(ghost, view, Math.max(2, Math.round(w / 2)));
      for (let ch = 0; ch < lane.dims; ch++) {
        g.strokeStyle = this.colour(n, ch);
        g.beginPath();
        line.times.forEach((t, i) => g.lineTo(X(t), Y(line.values[ch][i])));
        g.stroke();
      }
    });
    g.setLineDash([]);
    // the selection
    const items = this.selectedItems();
    g.fillStyle = '#e8b04b';
    g.strokeStyle = '#e8b04b';
    g.beginPath();
    marks.gen += 1;
    for (const { lane, kind, i } of items) {
      const x = kind === 'point' ? lane.px[i] : lane.kx[i];
      if (x < -HIT || x > w + HIT) continue;
      for (let ch = 0; ch < lane.dims; ch++) {
        const y = kind === 'point' ? lane.py[ch][i] : lane.ky[ch][i];
        if (!mark(marks, x, y)) continue;
        if (kind === 'point') g.rect(x - 3.5, y - 3.5, 7, 7);
        else { g.moveTo(x, y - 5); g.lineTo(x + 5, y); g.lineTo(x, y + 5); g.lineTo(x - 5, y); g.closePath(); }
      }
    }
    g.fill();
    const handles = items.filter((it) => it.kind === 'key' && !it.lane.euler && !it.lane.speed);
    if (handles.length <= 64) {
      g.lineWidth = 1.2;
      for (const { lane, i } of handles) {
        for (let ch = 0; ch < lane.dims; ch++) {
          const [a, b] = this.handleEnds(lane, i, ch, view, w, h);
          g.beginPath();
          g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]);
          g.stroke();
          g.beginPath();
          g.arc(a[0], a[1], 3, 0, 2 * Math.PI); g.moveTo(b[0] + 3, b[1]); g.arc(b[0], b[1], 3, 0, 2 * Math.PI);
          g.fill();
        }
      }
      g.lineWidth = 1;
    }
    const d = this.drag;
    if (d?.kind === 'box') {
      g.fillStyle = 'rgba(90, 150, 255, 0.12)';
      g.strokeStyle = '#5a96ff';
      const x = Math.min(d.x0, d.x), y = Math.min(d.y0, d.y);
      g.fillRect(x, y, Math.abs(d.x - d.x0), Math.abs(d.y - d.y0));
      g.strokeRect(x + 0.5, y + 0.5, Math.abs(d.x - d.x0), Math.abs(d.y - d.y0));
    }
    g.fillStyle = s.transport.record ? '#ff4d4d' : '#ffffff';
    g.fillRect(Math.round(X(s.transport.time)) - 1, 0, 2, h);
    if (!this.lanes.length) {
      g.fillStyle = '#8b93a3';
      g.font = '12px system-ui, sans-serif';
      g.fillText(s.selected ? 'no track yet: record a take' : 'select an object to see its curves', 12, 24);
    }
  }

  /**
   * The ends of a key's tangent handle, on screen.
   * @param {Lane} lane @param {number} i @param {number} ch @param {View} view @param {number} w @param {number} h
   * @returns {[[number, number], [number, number]]}
   */
  handleEnds(lane, i, ch, view, w, h) {
    const sx = w / (view.t1 - view.t0);
    const sy = (h - TOP - BOTTOM) / (view.v1 - view.v0);
    const dx = sx;
    const dy = -lane.ks[ch][i] * sy;
    const len = Math.hypot(dx, dy) || 1;
    const x = lane.kx[i], y = lane.ky[ch][i];
    return [[x - (dx / len) * HANDLE, y - (dy / len) * HANDLE], [x + (dx / len) * HANDLE, y + (dy / len) * HANDLE]];
  }

  /**
   * The take being recorded (its raw trail and reduced pieces), else nothing.
   * @returns {{times: number[], values: number[][], live: boolean} | null}
   */
  trail() {
    const s = this.studio;
    const path = s.selected ? `${s.selected}.${s.attribute}` : null;
    const live = s.performer.grab?.take;
    if (!path || !live?.paths.includes(path)) return null;
    const { times, values } = live.channel(path);
    const type = s.types.get(path);
    return { times, values: type?.name === 'orientation' ? unwrappedEulers(values) : values, live: true };
  }

  /**
   * The live take: its raw samples as dots and the pieces the server reduced so far, thick.
   * @param {CanvasRenderingContext2D} g
   * @param {{times: number[], values: number[][]}} trail
   * @param {(t: number) => number} X @param {(v: number) => number} Y
   */
  drawTrail(g, trail, X, Y) {
    const s = this.studio;
    const path = `${s.selected}.${s.attribute}`;
    const euler = s.types.get(path)?.name === 'orientation';
    const map = this.lanes[0]?.path === path ? this.lanes[0].map : [];
    const M = (/** @type {number} */ v, /** @type {number} */ ch) => (map[ch] ? map[ch].a * v + map[ch].b : v);
    const dims = trail.values[0]?.length ? (euler ? 3 : trail.values[0].length) : 0;
    const every = Math.max(1, Math.floor(trail.times.length / 1500));
    for (let ch = 0; ch < dims; ch++) {
      g.fillStyle = CHANNELS[ch];
      g.globalAlpha = 0.9;
      for (let i = 0; i < trail.times.length; i += every) g.fillRect(X(trail.times[i]) - 1, Y(M(trail.values[i][ch], ch)) - 1, 2, 2);
    }
    g.globalAlpha = 1;
    g.lineWidth = 3;
    for (const p of s.pieces.get(path) ?? []) {
      const a = p.knots[p.order - 1];
      const b = p.knots[p.knots.length - p.order];
      const piece = sampleCurve(p, a, b, 60);
      const rows = Array.from(piece.times, (_, i) => piece.values.map((ch) => ch[i]));
      const shown = euler ? unwrappedEulers(rows) : rows;
      for (let ch = 0; ch < dims; ch++) {
        g.strokeStyle = CHANNELS[ch];
        g.beginPath();
        piece.times.forEach((t, i) => g.lineTo(X(t), Y(M(shown[i][ch], ch))));
        g.stroke();
      }
    }
    g.lineWidth = 1;
  }

  /** @param {number} lane @param {number} ch */
  colour(lane, ch) {
    if (this.lanes.length <= 1) return CHANNELS[ch % CHANNELS.length];
    return `hsl(${(lane * 360) / this.lanes.length + ch * 28}, 75%, ${62 - ch * 8}%)`;
  }

  /** @param {{live: boolean, times: number[]} | null} trail */
  showTitle(trail) {
    const s = this.studio;
    const lane = this.lanes[0];
    const path = lane?.path ?? (s.selected ? `${s.selected}.${s.attribute}` : null);
    let html;
    if (!path) html = 'Curves: select an object';
    else {
      const names = NAMES[/** @type {keyof NAMES} */ (s.types.get(path)?.name ?? '')] ?? '';
      const legend = this.lanes.length > 1 ? `${this.lanes.length} tracks`
        : [...names.slice(0, lane?.dims ?? 0)].map((n, i) => `<b style="color:${CHANNELS[i]}">${n}</b>`).join(' ');
      const sent = [...s.takes].reverse().find((l) => l.sampler.paths.includes(path))?.sampler.tolerance[path]
        ?? s.performer.grab?.take?.tolerance[path];
      const said = sent ? formatTolerance(sent, sent.input, sent.unit) : '';
      const tol = lane && !(sent && Math.abs(sent.tol - lane.curve.tol) <= 1e-12 * lane.curve.tol) ? `tol ${Number(lane.curve.tol.toPrecision(2))}` : said;
      const what = trail?.live ? `recording · ${trail.times.length} samples (dots) · ${(s.pieces.get(path) ?? []).length} reduced pieces (thick) · ${said}`
        : lane ? `${lane.curve.coef.length} control points · ${lane.kt.length} keys · ${tol}${smoothing(lane.curve)}${lane.curve.edited ? ' · edited by hand' : ''}`
          : 'no track yet';
      html = `<span class="path">${path}</span> ${legend} <span class="what">${what}</span>`;
    }
    const notes = [];
    if (this.lanes.some((l) => l.euler && !l.speed)) notes.push('orientation: Euler angles in degrees; keys drag, control points (quaternions) do not');
    if (this.lanes.some((l) => l.speed)) notes.push('speed: view only');
    const w = this.canvas.clientWidth;
    if (this.lanes.some((l) => l.at && rangeOf(l.kx, 0, w).reduce((a, b) => b - a) > w / DENSE)) notes.push('keys too dense to draw: zoom in (wheel) to see them');
    if (this.normalised) notes.push('normalised: each channel -1..1');
    const note = notes.join(' · ');
    if (note !== this.note.textContent) this.note.textContent = note;
    if (html !== this.lastTitle) {
      this.title.innerHTML = html;
      this.lastTitle = html;
      this.speedButton.classList.toggle('on', this.speed);
      this.speedButton.disabled = !this.shownPaths().some((p) => s.types.get(p)?.name === 'position');
      this.normButton.classList.toggle('on', this.normalised);
    }
  }

  // -- gestures ---------------------------------------------------------------------------------

  /**
   * What is under (x, y): a handle of a selected key first, else the nearest key or control point.
   * @param {number} x @param {number} y
   * @returns {Hit | null}
   */
  hitTest(x, y) {
    const { w, h } = this.size();
    const view = this.currentView(w, h);
    for (const { lane, kind, i } of this.selectedItems()) {
      if (kind !== 'key' || lane.euler || lane.speed) continue;
      for (let ch = 0; ch < lane.dims; ch++) {
        for (const end of this.handleEnds(lane, i, ch, view, w, h)) {
          if (Math.hypot(end[0] - x, end[1] - y) <= HIT) return { lane, kind: 'handle', i, ch };
        }
      }
    }
    /** @type {Hit | null} */
    let best = null;
    let distance = HIT;
    for (const lane of this.lanes) {
      if (lane.speed) continue;
      for (let ch = 0; ch < lane.dims; ch++) {
        const key = nearestPoint(lane.kx, lane.ky[ch], x, y, HIT);
        if (key.index >= 0 && key.distance <= distance) { best = { lane, kind: 'key', i: key.index, ch }; distance = key.distance; }
        if (lane.euler) continue;
        const point = nearestPoint(lane.px, lane.py[ch], x, y, HIT);
        if (point.index >= 0 && point.distance < distance) { best = { lane, kind: 'point', i: point.index, ch }; distance = point.distance; }
      }
    }
    return best;
  }

  /** @param {PointerEvent | MouseEvent | WheelEvent} e */
  local(e) {
    const r = this.canvas.getBoundingClientRect();
    return { x: e.clientX - r.left, y: e.clientY - r.top };
  }

  bind() {
    const c = this.canvas;
    c.addEventListener('pointerdown', (e) => this.press(e));
    c.addEventListener('pointermove', (e) => this.move(e));
    c.addEventListener('pointerup', () => this.release());
    c.addEventListener('pointercancel', () => this.cancel());
    c.addEventListener('dblclick', (e) => this.doubleClick(e));
    c.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
    c.addEventListener('contextmenu', (e) => e.preventDefault());
    // Escape during a drag cancels it (before the studio's keys: it would deselect the object)
    window.addEventListener('keydown', (e) => {
      if (e.key === 'Escape' && this.drag) {
        e.preventDefault();
        e.stopImmediatePropagation();
        this.cancel();
      }
    }, { capture: true });
  }

  /** @param {PointerEvent} e */
  press(e) {
    if (this.drag) return;
    const { x, y } = this.local(e);
    this.canvas.setPointerCapture(e.pointerId);
    /** @type {Drag} */
    const base = { kind: 'box', x0: x, y0: y, x, y, moved: false };
    if (e.button === 1 || (e.button === 0 && e.altKey)) {
      this.drag = { ...base, kind: 'pan', view: { ...this.ownView() } };
      return;
    }
    if (e.button !== 0) return;
    const hit = this.hitTest(x, y);
    if (!hit) {
      this.drag = { ...base, base: e.shiftKey ? [...this.studio.points] : [] };
      if (!e.shiftKey) this.studio.selectPoints([]);
      return;
    }
    if (this.readOnlyRefused()) return;                      // a read-only project: nothing to drag
    if (hit.kind === 'handle') {
      this.drag = { ...base, kind: 'handle', hit };
      this.startMove(this.drag, 'key', [hit.i], hit.lane, true);
      return;
    }
    const item = this.entry(hit.lane, hit.kind, hit.i);
    if (e.shiftKey && this.isSelected(item)) {
      this.studio.selectPoints(this.studio.points.filter((p) => !(p.path === item.path && p.kind === item.kind && p.index === item.index)));
      return;
    }
    if (e.shiftKey) this.studio.selectPoints([...this.studio.points, item]);
    else if (!this.isSelected(item) || hit.lane.euler) this.studio.selectPoints([item]);
    this.drag = { ...base, kind: 'move', hit, what: hit.kind };
    const chosen = this.selectedItems().filter((it) => it.kind === hit.kind);
    for (const lane of new Set(chosen.map((it) => it.lane))) {
      this.startMove(this.drag, hit.kind, chosen.filter((it) => it.lane === lane).map((it) => it.i), lane, false);
    }
  }

  /**
   * Get a lane ready to be dragged: its coefficients copied, the response of the keys moved.
   * @param {Drag} drag @param {'point' | 'key'} what @param {number[]} items @param {Lane} lane @param {boolean} slope
   */
  startMove(drag, what, items, lane, slope) {
    const times = what === 'key' ? [...new Set(items.map((i) => lane.kt[i]))].sort((a, b) => a - b) : [];
    const u = what === 'key' ? response(lane.curve.knots, lane.curve.order, times, slope) : null;
    (drag.lanes ??= []).push({ lane, coef: lane.curve.coef.map((r) => r.slice()), items, u, times });
  }

  /** @param {PointerEvent} e */
  move(e) {
    const d = this.drag;
    if (!d) return;
    const started = performance.now();
    const { x, y } = this.local(e);
    d.x = x;
    d.y = y;
    if (Math.abs(x - d.x0) + Math.abs(y - d.y0) >= 2) d.moved = true;
    const { w, h } = this.size();
    if (d.kind === 'pan' && d.view) {
      const v = d.view;
      const dt = ((x - d.x0) / w) * (v.t1 - v.t0);
      const dv = ((y - d.y0) / (h - TOP - BOTTOM)) * (v.v1 - v.v0);
      this.view = { t0: v.t0 - dt, t1: v.t1 - dt, v0: v.v0 + dv, v1: v.v1 + dv };
    } else if (d.kind === 'box') {
      this.boxSelect(d);
    } else if (d.moved) {
      this.preview(d, this.currentView(w, h), w, h);
    }
    this.overlayVersion += 1;
    this.stats.move.push(performance.now() - started);
    if (this.stats.move.length > 600) this.stats.move.shift();
  }

  /**
   * The selection while a box is drawn: what it holds, added to what was selected before (Shift).
   * @param {Drag} d
   */
  boxSelect(d) {
    const x0 = Math.min(d.x0, d.x), x1 = Math.max(d.x0, d.x), y0 = Math.min(d.y0, d.y), y1 = Math.max(d.y0, d.y);
    /** @type {PointSelection[]} */
    const found = [...(d.base ?? [])];
    const seen = new Set(found.map((q) => `${q.path}|${q.kind}|${q.index}`));
    const add = (/** @type {PointSelection} */ q) => {
      const k = `${q.path}|${q.kind}|${q.index}`;
      if (!seen.has(k)) { seen.add(k); found.push(q); }
    };
    for (const lane of this.lanes) {
      if (lane.speed) continue;
      for (const [kind, xs, ys] of /** @type {const} */ ([['key', lane.kx, lane.ky], ['point', lane.px, lane.py]])) {
        if (kind === 'point' && lane.euler) continue;
        const [a, b] = rangeOf(xs, x0, x1);
        for (let i = a; i < b; i++) {
          if (ys.some((col) => col[i] >= y0 && col[i] <= y1)) add(this.entry(lane, kind, i));
        }
      }
    }
    this.studio.selectPoints(found);
  }

  /**
   * Preview a move: the dragged lanes' copies of the coefficients changed, drawn over the layer.
   * @param {Drag} d @param {View} view @param {number} w @param {number} h
   */
  preview(d, view, w, h) {
    const hit = /** @type {Hit} */ (d.hit);
    const ch = hit.ch;
    const perPixel = (view.v1 - view.v0) / (h - TOP - BOTTOM);
    const shift = (d.y0 - d.y) * perPixel;                        // display units, up is more
    for (const { lane, coef, items, u, times } of d.lanes ?? []) {
      this.moving.add(lane.path);
      const next = coef.map((r) => r.slice());
      const a = lane.map[ch].a;
      if (d.kind === 'handle' && u) {
        const i = hit.i;
        const sx = w / (view.t1 - view.t0);
        const dxs = Math.max(Math.abs(d.x - lane.kx[i]), 2) / sx * Math.sign(d.x - lane.kx[i] || 1);
        const slope = ((lane.ky[ch][i] - d.y) * perPixel) / dxs / a;
        const old = valueAndSlope(lane.curve.knots, lane.curve.order, coef, times[0]).slope[ch];
        u.forEach((wt, j) => { if (wt) next[j][ch] += (slope - old) * wt; });
        d.quat = [slope];
      } else if (d.what === 'point') {
        for (const i of items) next[i][ch] = coef[i][ch] + shift / a;
      } else if (lane.euler && u) {
        const t = times[0];
        const raw = valueAndSlope(lane.curve.knots, lane.curve.order, coef, t).value;
        const norm = Math.hypot(...raw);
        const q = raw.map((v) => v / norm);
        const e = nearestEuler(quatToEuler(q), refAt(lane, t));
        e[ch] += shift / a;
        let q1 = eulerToQuat(e);
        if (q1[0] * q[0] + q1[1] * q[1] + q1[2] * q[2] + q1[3] * q[3] < 0) q1 = /** @type {[number, number, number, number]} */ (q1.map((v) => -v));
        d.quat = q1;
        u.forEach((wt, j) => { if (wt) for (let c = 0; c < 4; c++) next[j][c] += (q1[c] * norm - raw[c]) * wt; });
      } else if (u) {
        u.forEach((wt, j) => { if (wt) next[j][ch] += (shift / a) * wt; });
      }
      lane.shown = { ...lane.curve, coef: next };
      const changed = next.flatMap((row, j) => (row.some((v, k) => v !== coef[j][k]) ? [j] : []));
      if (changed.length) this.reshaped(lane, changed[0], changed[changed.length - 1]);
      this.place(lane, view, w, h);
    }
  }

  /** The pointer went up: send the gesture (one History step), or take a click as a selection. */
  release() {
    const d = this.drag;
    if (!d) return;
    this.drag = null;
    const s = this.studio;
    if (d.moved && d.hit && (d.kind === 'move' || d.kind === 'handle')) {
      const lanes = d.lanes ?? [];
      const ch = d.hit.ch;
      if (d.kind === 'handle' && d.quat) {
        const { lane, coef, times } = lanes[0];
        const slope = valueAndSlope(lane.curve.knots, lane.curve.order, coef, times[0]).slope;
        slope[ch] = d.quat[0];
        s.moveKey(lane.path, times[0], null, slope);
      } else if (d.what === 'key' && lanes.length === 1 && lanes[0].times.length === 1) {
        const { lane, times } = lanes[0];
        const value = lane.euler ? d.quat ?? null : valueAndSlope(lane.shown.knots, lane.shown.order, lane.shown.coef, times[0]).value;
        if (value) s.moveKey(lane.path, times[0], value, null);
      } else {
        /** @type {{path: string, index: number, value: number[]}[]} */
        const edits = [];
        for (const { lane, coef } of lanes) {
          lane.shown.coef.forEach((row, j) => { if (row.some((v, c) => v !== coef[j][c])) edits.push({ path: lane.path, index: j, value: row }); });
        }
        const count = lanes.reduce((n, l) => n + l.items.length, 0);
        s.movePoints(edits, d.what === 'key' ? `move ${count} keys` : `move ${count} control point${count === 1 ? '' : 's'}`);
      }
    }
    this.endDrag();
  }

  /** Escape (or a lost pointer): the drag is dropped, nothing sent. */
  cancel() {
    const d = this.drag;
    this.drag = null;
    if (d?.kind === 'box') this.studio.selectPoints(d.base ?? []);
    if (d?.kind === 'pan' && d.view) this.view = d.view;
    this.endDrag();
  }

  /** A curve being dragged changed under the drag (another tab's edit, an undo): the drag ends,
   * nothing sent (its points and keys would name the curve as it was). */
  dropStaleDrag() {
    const lanes = new Map(this.lanes.map((l) => [l.path, l]));
    const stale = [...this.moving].some((path) => this.studio.tracks.get(path) !== lanes.get(path)?.curve);
    if (!this.drag || !stale) return;
    this.cancel();
    this.studio.tell('info', 'the curve changed while it was dragged (another tab, or an undo): drag it again', 'curve editor');
  }

  endDrag() {
    this.moving.clear();
    for (const lane of this.lanes) {
      if (lane.shown !== lane.curve) {
        lane.shown = lane.curve;
        this.computeData(lane);
      }
    }
    this.layerKey = '';
    this.overlayVersion += 1;
  }

  /** @param {MouseEvent} e a double-click on a curve inserts a knot there */
  doubleClick(e) {
    if (this.readOnlyRefused()) return;
    const { x, y } = this.local(e);
    const { w, h } = this.size();
    const view = this.currentView(w, h);
    const t = view.t0 + (x / w) * (view.t1 - view.t0);
    const ph = h - TOP - BOTTOM;
    for (const lane of this.lanes) {
      const i = Math.round((x / w) * (lane.line.times.length - 1));
      const near = lane.line.values.some((vs) => Math.abs(TOP + ((view.v1 - vs[i]) / (view.v1 - view.v0)) * ph - y) <= HIT);
      if (near) {
        this.insertKnot(lane, this.studio.snapped(t));
        return;
      }
    }
  }

  /**
   * Insert a knot at `t` into a lane's curve (one History step).
   * @param {Lane} lane @param {number} t
   */
  insertKnot(lane, t) {
    const c = lane.curve;
    if (!(t > c.knots[c.order - 1] && t < c.knots[c.knots.length - c.order])) {
      this.studio.tell('info', `a knot goes inside the curve's span (${c.start.toFixed(2)} to ${c.end.toFixed(2)} s)`, 'curve editor');
      return;
    }
    this.studio.editKnots(lane.path, [t], []);
  }

  /** @param {WheelEvent} e the wheel zooms time around the pointer (Ctrl or Shift: values) */
  wheel(e) {
    e.preventDefault();
    const { x, y } = this.local(e);
    const { w, h } = this.size();
    const v = this.ownView();
    const f = Math.exp((e.deltaY || e.deltaX) * 0.0015);
    if (e.ctrlKey || e.shiftKey) {
      const at = v.v1 - ((y - TOP) / (h - TOP - BOTTOM)) * (v.v1 - v.v0);
      this.view = { ...v, v0: at + (v.v0 - at) * f, v1: at + (v.v1 - at) * f };
    } else {
      const at = v.t0 + (x / w) * (v.t1 - v.t0);
      this.view = { ...v, t0: at + (v.t0 - at) * f, t1: at + (v.t1 - at) * f };
    }
  }

  /** @param {import('./keyboard.js').PanelCommand} c */
  command(c) {
    if (c === 'frame-all') this.frameAll();
    else if (c === 'frame-selection') this.frameSelection();
    else if (c === 'normalise') {
      this.normalised = !this.normalised;
      this.buildLanes();
      this.frameAll();
      this.lastTitle = '';
    } else if (c === 'insert-knot') {
      if (this.lanes[0] && !this.readOnlyRefused()) this.insertKnot(this.lanes[0], this.studio.snapped(this.studio.transport.time));
    } else if (c === 'delete-points' && !this.readOnlyRefused()) this.deleteKeys();
  }

  /** Whether the project is read-only (an edit then starts not at all; the page says why). */
  readOnlyRefused() {
    if (!this.studio.readOnly) return false;
    this.studio.tell('info', 'read-only project: curves are shown, not edited', 'curve editor');
    return true;
  }

  /** Delete: the selected keys' knots removed (the curve's ends stay), one step per track. */
  deleteKeys() {
    const byLane = new Map();
    for (const { lane, kind, i } of this.selectedItems()) {
      if (kind !== 'key' || i === 0 || i === lane.kk.length - 1) continue;
      byLane.set(lane, [...(byLane.get(lane) ?? []), lane.kk[i]]);
    }
    if (!byLane.size) {
      this.studio.tell('info', 'select keys inside the curve to delete their knots (control points and the ends stay)', 'curve editor');
      return;
    }
    for (const [lane, knots] of byLane) this.studio.editKnots(lane.path, [], knots);
    this.studio.selectPoints([]);
  }
}

/**
 * How a curve's takes were smoothed, as its title says it (" · smoothed 0.05 s", " · 1 of 2
 * takes smoothed 0.02 s"; nothing when none was): its tolerance holds against those samples.
 * @param {CurveTrack} curve
 */
function smoothing(curve) {
  const smoothed = curve.takes.filter((t) => t.smoothing > 0);
  if (!smoothed.length) return '';
  const widths = [...new Set(smoothed.map((t) => t.smoothing))].join(' / ');
  const which = smoothed.length === curve.takes.length ? '' : `${smoothed.length} of ${curve.takes.length} takes `;
  return ` · ${which}smoothed ${widths} s`;
}

/**
 * Mark a 3 px cell as drawn; false if it already was (in this pass).
 * @param {{gen: number, cells: Uint32Array, cw: number}} marks @param {number} x @param {number} y
 */
function mark(marks, x, y) {
  if (x < 0 || y < 0) return true;
  const cell = ((x / 3) | 0) + ((y / 3) | 0) * marks.cw;
  if (cell >= marks.cells.length) return true;
  if (marks.cells[cell] === marks.gen) return false;
  marks.cells[cell] = marks.gen;
  return true;
}

/**
 * Small dots, one per 3 px cell.
 * @param {CanvasRenderingContext2D} g @param {Float32Array} xs @param {Float32Array} ys
 * @param {number} a @param {number} b @param {number} r
 * @param {{gen: number, cells: Uint32Array, cw: number}} marks @param {number} h
 */
function dots(g, xs, ys, a, b, r, marks, h) {
  marks.gen += 1;
  g.beginPath();
  for (let i = a; i < b; i++) {
    const y = ys[i];
    if (y < 0 || y > h || !mark(marks, xs[i], y)) continue;
    g.rect(xs[i] - r, y - r, 2 * r, 2 * r);
  }
  g.fill();
}

/**
 * An orientation curve's Euler angles on a fine grid, unwrapped: every Euler value shown is
 * the nearest to it, so the curve, its keys and its samples agree on the branch.
 * @param {CurveTrack} c
 */
function eulerReference(c) {
  const a = c.knots[c.order - 1];
  const b = c.knots[c.knots.length - c.order];
  const count = Math.min(20000, Math.max(512, 4 * c.knots.length));
  const played = sampleCurve(c, a, b, count);
  const eulers = unwrappedEulers(Array.from(played.times, (_, i) => played.values.map((ch) => ch[i])));
  return { times: played.times, eulers };
}

/**
 * The reference Euler angles of a lane at `t` (the nearest grid sample).
 * @param {Lane} lane @param {number} t
 * @returns {[number, number, number]}
 */
function refAt(lane, t) {
  const ref = /** @type {NonNullable<Lane['ref']>} */ (lane.ref);
  const n = ref.times.length;
  const i = Math.min(n - 1, Math.max(0, Math.round(((t - ref.times[0]) / (ref.times[n - 1] - ref.times[0] || 1)) * (n - 1))));
  return ref.eulers[i];
}

