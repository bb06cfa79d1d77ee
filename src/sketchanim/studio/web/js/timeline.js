// @ts-check
/**
 * The timeline: the time axis with the playhead, the loop range and the selected object's
 * tracks and takes as bars (one row per animated attribute; the one in the curve view
 * highlighted), the take being recorded and the count-in. Drag: scrub; shift-drag: set the
 * loop range.
 */
import { fitCanvas } from './canvas.js';
import { tickStep, viewRange } from './timescale.js';

export class Timeline {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLCanvasElement} canvas
   */
  constructor(studio, canvas) {
    this.studio = studio;
    this.canvas = canvas;
    studio.signals.on('frame', () => this.draw());
    this.bind();
  }

  /** @param {number} x client x */
  timeAt(x) {
    const rect = this.canvas.getBoundingClientRect();
    const [t0, t1] = this.range();
    return t0 + ((x - rect.left) / rect.width) * (t1 - t0);
  }

  range() {
    const s = this.studio;
    return viewRange(s.playSpan, s.transport.clock.loop, s.transport.time);
  }

  bind() {
    const transport = this.studio.transport;
    /** @type {{loopFrom: number | null} | null} */
    let drag = null;
    this.canvas.addEventListener('pointerdown', (e) => {
      this.canvas.setPointerCapture(e.pointerId);
      const t = this.timeAt(e.clientX);
      drag = { loopFrom: e.shiftKey ? t : null };
      if (!e.shiftKey) transport.seek(t);
    });
    this.canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const t = this.timeAt(e.clientX);
      if (drag.loopFrom === null) transport.seek(t);
      else transport.setLoop([Math.min(drag.loopFrom, t), Math.max(drag.loopFrom, t)]);
    });
    const end = () => { drag = null; };
    this.canvas.addEventListener('pointerup', end);
    this.canvas.addEventListener('pointercancel', end);
  }

  draw() {
    const s = this.studio;
    const { clock, time, record, punchFrom } = s.transport;
    const counting = s.transport.countingIn;
    const take = s.performer.grab?.take;
    const { g, w, h } = fitCanvas(this.canvas);
    g.fillStyle = '#17191e';
    g.fillRect(0, 0, w, h);
    const [t0, t1] = this.range();
    const x = (/** @type {number} */ t) => ((t - t0) / (t1 - t0)) * w;
    if (clock.loop) {
      g.fillStyle = 'rgba(90, 150, 255, 0.18)';
      g.fillRect(x(clock.loop[0]), 0, x(clock.loop[1]) - x(clock.loop[0]), h);
      g.fillStyle = '#5a96ff';
      g.fillRect(x(clock.loop[0]), 0, 2, h);
      g.fillRect(x(clock.loop[1]) - 2, 0, 2, h);
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
    // the strips (a sound's waveform), under the ticks, above the lanes; the canvas grows to hold them
    let top = 12;
    for (const strip of s.strips) {
      strip.draw(g, { x: 0, y: top, width: w, height: strip.height }, t0, t1);
      top += strip.height;
    }
    const height = `${40 + top - 12}px`;
    if (this.canvas.style.height !== height) this.canvas.style.height = height;
    // the selected object's takes, one row per animated attribute
    const name = s.selected;
    let row = 0;
    for (const track of s.tracks.values()) {
      if (!name || !track.path.startsWith(`${name}.`) || track.kind !== 'curve') continue;
      const y = top + 3 + row * 7;
      row += 1;
      g.fillStyle = track.path === `${name}.${s.attribute}` ? '#e8b04b' : '#6b7385';
      g.fillRect(x(track.start), y, Math.max(x(track.end) - x(track.start), 2), 4);
      g.fillStyle = 'rgba(255,255,255,0.55)';
      for (const part of track.takes) g.fillRect(x(part.start), y, 1, 4);
    }
    if (take && take.times.length) {
      g.fillStyle = '#ff4d4d';
      const a = take.times[0];
      g.fillRect(x(a), h - 6, Math.max(x(take.last) - x(a), 2), 4);
    }
    if (counting > 0) {
      g.fillStyle = 'rgba(255, 77, 77, 0.25)';
      g.fillRect(x(time), 0, x(punchFrom) - x(time), h);
    }
    g.fillStyle = record ? '#ff4d4d' : '#ffffff';
    g.fillRect(Math.round(x(time)) - 1, 0, 2, h);
  }
}
