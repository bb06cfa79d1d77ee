// @ts-check
/**
 * The curve view: one attribute of the selected object against time, channel by
 * channel. The track's curve (solid), the take being recorded as its raw trail (dots)
 * and the reduced pieces growing as the server finishes windows (bright, thick), then
 * the final curve after the release. Shares the timeline's time axis.
 */
import { sampleCurve } from './evaluate.js';
import { el } from './dom.js';
import { fitCanvas } from './canvas.js';
import { formatTolerance } from './resolution.js';
import { viewRange } from './timescale.js';

const CHANNELS = ['#ff6b6b', '#5cd65c', '#5aa0ff', '#c8c8c8', '#e0a0ff'];
const NAMES = { position: 'xyz', scale: 'xyz', orientation: 'xyzw', color: 'rgb' };

export class CurveView {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root
   */
  constructor(studio, root) {
    this.studio = studio;
    this.title = el('div', { class: 'curve-title' });
    this.canvas = /** @type {HTMLCanvasElement} */ (el('canvas', { 'data-testid': 'curves' }));
    root.append(this.title, this.canvas);
    /** @type {[number, number] | null} the value range shown (grows during a take, never jumps) */
    this.yRange = null;
    /** @type {any} */
    this.cache = null;
    this.lastTitle = '';
    for (const signal of /** @type {const} */ (['selection', 'attribute', 'tracks', 'state'])) {
      studio.signals.on(signal, () => { this.yRange = null; this.cache = null; });
    }
    studio.signals.on('frame', () => this.draw());
  }

  get path() {
    const s = this.studio;
    return s.selected ? `${s.selected}.${s.attribute}` : null;
  }

  /** The take whose samples to draw: the one being recorded, else the latest of this path. */
  trail() {
    const s = this.studio;
    const path = this.path;
    if (!path) return null;
    const live = s.performer.grab?.take;
    if (live?.paths.includes(path)) return { sampler: live, live: true };
    const log = [...s.takes].reverse().find((l) => l.sampler.paths.includes(path));
    return log ? { sampler: log.sampler, live: false } : null;
  }

  draw() {
    const s = this.studio;
    const { g, w, h } = fitCanvas(this.canvas);
    g.fillStyle = '#131519';
    g.fillRect(0, 0, w, h);
    const path = this.path;
    const type = path ? s.types.get(path) : null;
    if (!path || !type || !type.continuous) {
      this.title.textContent = 'Curves: select an object';
      return;
    }
    const [t0, t1] = viewRange(s.span, s.transport.clock.loop, s.transport.time);
    const track = s.tracks.get(path);
    const curve = track && track.kind === 'curve' ? track : null;
    if (curve && (!this.cache || this.cache.curve !== curve || this.cache.t0 !== t0 || this.cache.t1 !== t1)) {
      this.cache = { curve, t0, t1, ...sampleCurve(curve, t0, t1, Math.max(2, Math.round(w / 2))) };
    }
    const drawn = curve ? this.cache : null;
    const trail = this.trail();
    const samples = trail ? trail.sampler.channel(path) : { times: [], values: [] };
    const pieces = trail?.live ? (s.pieces.get(path) ?? []).map((p) => {
      const a = p.knots[p.order - 1];
      const b = p.knots[p.knots.length - p.order];
      return sampleCurve(p, a, b, 60);
    }) : [];
    const dim = type.dim;
    // the value range: everything drawn, grown, never shrunk while drawing the same thing
    let lo = Infinity;
    let hi = -Infinity;
    const see = (/** @type {number} */ v) => { if (v < lo) lo = v; if (v > hi) hi = v; };
    if (drawn) drawn.values.forEach((/** @type {Float64Array} */ ch) => ch.forEach(see));
    samples.values.forEach((row) => row.forEach(see));
    if (!Number.isFinite(lo)) (s.values.get(path) ?? [0]).forEach(see);
    if (this.yRange) { see(this.yRange[0]); see(this.yRange[1]); }
    if (hi - lo < 1e-6) { lo -= 0.5; hi += 0.5; }
    this.yRange = [lo, hi];
    const pad = (hi - lo) * 0.08;
    const x = (/** @type {number} */ t) => ((t - t0) / (t1 - t0)) * w;
    const y = (/** @type {number} */ v) => h - 14 - ((v - lo + pad) / (hi - lo + 2 * pad)) * (h - 24);
    g.strokeStyle = '#262a32';
    g.beginPath();
    for (let i = 0; i <= 4; i++) { const yy = Math.round(10 + (i * (h - 24)) / 4) + 0.5; g.moveTo(0, yy); g.lineTo(w, yy); }
    g.stroke();
    if (curve) {
      g.fillStyle = 'rgba(232, 176, 75, 0.07)';
      for (const take of curve.takes) g.fillRect(x(take.start), 0, x(take.end) - x(take.start), h);
    }
    const names = NAMES[/** @type {keyof NAMES} */ (type.name)] ?? '';
    for (let ch = 0; ch < dim; ch++) {
      const colour = CHANNELS[ch % CHANNELS.length];
      if (drawn) {
        g.strokeStyle = colour;
        g.globalAlpha = trail?.live ? 0.35 : 0.95;
        g.lineWidth = 1.6;
        g.beginPath();
        drawn.times.forEach((/** @type {number} */ t, /** @type {number} */ i) => (i ? g.lineTo(x(t), y(drawn.values[ch][i])) : g.moveTo(x(t), y(drawn.values[ch][i]))));
        g.stroke();
      }
      g.globalAlpha = trail?.live ? 0.9 : 0.35;
      g.fillStyle = colour;
      const every = Math.max(1, Math.floor(samples.times.length / 1500));
      for (let i = 0; i < samples.times.length; i += every) g.fillRect(x(samples.times[i]) - 1, y(samples.values[i][ch]) - 1, 2, 2);
      g.globalAlpha = 1;
      g.strokeStyle = colour;
      g.lineWidth = 3;
      for (const piece of pieces) {
        g.beginPath();
        piece.times.forEach((t, i) => (i ? g.lineTo(x(t), y(piece.values[ch][i])) : g.moveTo(x(t), y(piece.values[ch][i]))));
        g.stroke();
      }
      g.lineWidth = 1;
    }
    g.fillStyle = s.transport.record ? '#ff4d4d' : '#ffffff';
    g.fillRect(Math.round(x(s.transport.time)) - 1, 0, 2, h);
    g.fillStyle = '#8b93a3';
    g.font = '10px system-ui, sans-serif';
    g.fillText(hi.toFixed(3), 4, 18);
    g.fillText(lo.toFixed(3), 4, h - 16);
    const legend = [...names.slice(0, dim)].map((n, i) => `<b style="color:${CHANNELS[i]}">${n}</b>`).join(' ');
    const sent = trail?.sampler.tolerance[path];
    const tol = sent ? formatTolerance(sent, sent.input, sent.unit) : `tol ${curve ? Number(curve.tol.toPrecision(2)) : '?'}`;
    const what = trail?.live ? `recording · ${samples.times.length} samples (dots) · ${pieces.length} reduced pieces (thick) · ${tol}`
      : curve ? `curve: ${curve.coef.length} control points for ${curve.takes.reduce((n, t) => n + t.n, 0)} samples in ${curve.takes.length} take${curve.takes.length === 1 ? '' : 's'} · ${sent && Math.abs(sent.tol - curve.tol) <= 1e-12 * curve.tol ? tol : `tol ${Number(curve.tol.toPrecision(2))}`}${smoothing(curve)}`
        : 'no track yet: record a take';
    const html = `<span class="path">${path}</span> ${legend} <span class="what">${what}</span>`;
    if (this.lastTitle !== html) {
      this.title.innerHTML = html;
      this.lastTitle = html;
    }
  }
}

/**
 * How a curve's takes were smoothed, as its title shows it (" · smoothed 0.05 s", " · 1 of 2
 * takes smoothed 0.02 s"; nothing when none was): its tolerance holds against those samples.
 * @param {import('./messages.js').CurveTrack} curve
 */
function smoothing(curve) {
  const smoothed = curve.takes.filter((t) => t.smoothing > 0);
  if (!smoothed.length) return '';
  const widths = [...new Set(smoothed.map((t) => t.smoothing))].join(' / ');
  const which = smoothed.length === curve.takes.length ? '' : `${smoothed.length} of ${curve.takes.length} takes `;
  return ` · ${which}smoothed ${widths} s`;
}
