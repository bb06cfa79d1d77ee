// @ts-check
/**
 * A sound's waveform at any zoom, fast: a min / max peak pyramid built once from the decoded
 * samples (level 0: the extremes of each `base` samples; each level above: of two bins of the
 * one below), and the extremes per pixel column of a time range read from the coarsest level
 * whose bins are no wider than a column (so a column reads one or two bins whatever the zoom:
 * ten minutes draw as fast as one second). Pure, tested with node (tests/studio/js/waveform.test.js);
 * `drawWaveform` paints the columns on a canvas.
 */

/**
 * @typedef {object} PeakLevel
 * @property {Float32Array} min   the least sample of each bin
 * @property {Float32Array} max   the greatest sample of each bin
 * @property {number} span        samples per bin
 */

/**
 * @typedef {object} Pyramid
 * @property {PeakLevel[]} levels  finest first
 * @property {number} rate         samples per second
 * @property {number} length       samples
 */

/**
 * The peak pyramid of `samples` (one channel, or the channels' mean) at `rate` Hz.
 * @param {Float32Array} samples
 * @param {number} rate
 * @param {number} [base] samples per bin of the finest level
 * @returns {Pyramid}
 *
 * @example
 * const p = peakPyramid(new Float32Array([0, 1, -1, 0.5]), 4, 2);
 * p.levels[0].max;   // Float32Array [1, 0.5]
 * p.levels[1].min;   // Float32Array [-1]
 */
export function peakPyramid(samples, rate, base = 64) {
  const bins = Math.max(1, Math.ceil(samples.length / base));
  let min = new Float32Array(bins);
  let max = new Float32Array(bins);
  for (let b = 0; b < bins; b++) {
    let lo = Infinity;
    let hi = -Infinity;
    const end = Math.min(samples.length, (b + 1) * base);
    for (let i = b * base; i < end; i++) {
      const v = samples[i];
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    min[b] = lo === Infinity ? 0 : lo;
    max[b] = hi === -Infinity ? 0 : hi;
  }
  /** @type {PeakLevel[]} */
  const levels = [{ min, max, span: base }];
  while (min.length > 1) {
    const n = Math.ceil(min.length / 2);
    const upMin = new Float32Array(n);
    const upMax = new Float32Array(n);
    for (let b = 0; b < n; b++) {
      const j = Math.min(2 * b + 1, min.length - 1);
      upMin[b] = Math.min(min[2 * b], min[j]);
      upMax[b] = Math.max(max[2 * b], max[j]);
    }
    min = upMin;
    max = upMax;
    levels.push({ min, max, span: levels[levels.length - 1].span * 2 });
  }
  return { levels, rate, length: samples.length };
}

/**
 * The extremes of the sound in each of `columns` equal parts of the times `t0`..`t1` (seconds
 * of the sound; outside it a column is empty: min > max). Reads the coarsest level whose bins
 * are no wider than a column.
 * @param {Pyramid} pyramid
 * @param {number} t0
 * @param {number} t1
 * @param {number} columns
 * @returns {{min: Float32Array, max: Float32Array, level: number}}
 *
 * @example
 * const p = peakPyramid(new Float32Array([0, 1, -1, 0.5]), 4, 1);
 * columnPeaks(p, 0, 1, 2);   // {min: [0, -1], max: [1, 0.5], level: 1}
 */
export function columnPeaks(pyramid, t0, t1, columns) {
  const n = Math.max(0, Math.floor(columns));
  const min = new Float32Array(n).fill(1);
  const max = new Float32Array(n).fill(-1);
  const perColumn = ((t1 - t0) * pyramid.rate) / Math.max(n, 1);       // samples per column
  let level = 0;
  while (level + 1 < pyramid.levels.length && pyramid.levels[level + 1].span <= perColumn) level += 1;
  const { min: lo, max: hi, span } = pyramid.levels[level];
  for (let c = 0; c < n; c++) {
    const a = (t0 * pyramid.rate + c * perColumn) / span;
    const b = (t0 * pyramid.rate + (c + 1) * perColumn) / span;
    const first = Math.max(0, Math.floor(a));
    const last = Math.min(lo.length - 1, Math.max(first, Math.ceil(b) - 1));
    if (b <= 0 || first >= lo.length || a * span >= pyramid.length) continue;
    let m = Infinity;
    let x = -Infinity;
    for (let i = first; i <= last; i++) {
      if (lo[i] < m) m = lo[i];
      if (hi[i] > x) x = hi[i];
    }
    min[c] = m;
    max[c] = x;
  }
  return { min, max, level };
}

/**
 * Paint the waveform of `pyramid` for the timeline's times `t0`..`t1` into `area` (canvas
 * pixels), the sound starting at `offset` on the timeline: one vertical bar per column from
 * its least to its greatest sample.
 * @param {CanvasRenderingContext2D} g
 * @param {{x: number, y: number, width: number, height: number}} area
 * @param {Pyramid} pyramid
 * @param {number} t0
 * @param {number} t1
 * @param {number} offset
 * @param {string} colour
 */
export function drawWaveform(g, area, pyramid, t0, t1, offset, colour) {
  const columns = Math.max(1, Math.round(area.width));
  const { min, max } = columnPeaks(pyramid, t0 - offset, t1 - offset, columns);
  const mid = area.y + area.height / 2;
  const half = area.height / 2;
  g.fillStyle = colour;
  for (let c = 0; c < columns; c++) {
    if (min[c] > max[c]) continue;
    const top = mid - max[c] * half;
    g.fillRect(area.x + c, top, 1, Math.max(1, (max[c] - min[c]) * half));
  }
}
