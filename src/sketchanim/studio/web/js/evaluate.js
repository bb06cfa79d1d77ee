// @ts-check
/**
 * Track evaluation in the page: a port of anim/player.py's kernel, so the page plays
 * every track itself each frame and matches the model (to 1e-9; tests/studio/js/evaluate.test.js
 * checks it against values dumped from Player.values).
 *
 * The continuous tracks are packed end to end once (again only when the tracks change):
 * knots, coefficients (row-major, n x dim) and each track's offsets. Each frame, one pass
 * evaluates them all at a time by de Boor's algorithm, the time clamped to each track's
 * span (a track holds its end values outside it), orientations normalised, a bounded
 * attribute's channels clamped to its bounds (the curve keeps them; this guards against
 * rounding, and the float32 the values go to keeps them too, rounding being monotone).
 * Discrete tracks step: the value of the last time <= t, or null before the first.
 */

/**
 * @typedef {object} Curve   A continuous track as the project document holds it.
 * @property {string} path
 * @property {number} order      Spline order (degree + 1).
 * @property {number[]} knots
 * @property {number[][]} coef   n rows of dim numbers.
 * @property {boolean} [rotation] A quaternion curve (normalised when played).
 * @property {(number|null)[] | null} [bounds] The attribute's low and high (null: that side unbounded).
 */

/**
 * @typedef {object} Steps   A discrete track: values holding from their time on.
 * @property {string} path
 * @property {number[]} times
 * @property {Array<boolean|string|null>} values
 */

/**
 * @typedef {object} Packed
 * @property {string[]} paths
 * @property {Float64Array} knots
 * @property {Int32Array} kofs
 * @property {Float64Array} coef
 * @property {Int32Array} cofs
 * @property {Int32Array} orders
 * @property {Int32Array} dims
 * @property {Uint8Array} rotation
 * @property {Float64Array} low  Each track's least value (-Infinity: unbounded).
 * @property {Float64Array} high Each track's greatest value (Infinity: unbounded).
 * @property {Int32Array} oofs   Where each track's values start in the output (length + 1).
 * @property {Float64Array} out  The values of the last evaluation, end to end.
 * @property {Float64Array} work Scratch for de Boor.
 * @property {[number, number] | null} span  First and last time of any curve.
 */

/**
 * Pack curves for evaluation.
 * @param {Curve[]} curves
 * @returns {Packed}
 */
export function pack(curves) {
  const n = curves.length;
  const kofs = new Int32Array(n + 1);
  const cofs = new Int32Array(n + 1);
  const oofs = new Int32Array(n + 1);
  const orders = new Int32Array(n);
  const dims = new Int32Array(n);
  const rotation = new Uint8Array(n);
  const low = new Float64Array(n).fill(-Infinity);
  const high = new Float64Array(n).fill(Infinity);
  let maxOrder = 1;
  curves.forEach((c, j) => {
    const dim = c.coef.length ? c.coef[0].length : 0;
    if (c.knots.length - c.order !== c.coef.length || dim < 1) {
      throw new Error(`${c.path}: ${c.knots.length} knots of order ${c.order} need ${c.knots.length - c.order} coefficient rows, got ${c.coef.length}`);
    }
    kofs[j + 1] = kofs[j] + c.knots.length;
    cofs[j + 1] = cofs[j] + c.coef.length * dim;
    oofs[j + 1] = oofs[j] + dim;
    orders[j] = c.order;
    dims[j] = dim;
    rotation[j] = c.rotation ? 1 : 0;
    low[j] = c.bounds?.[0] ?? -Infinity;
    high[j] = c.bounds?.[1] ?? Infinity;
    maxOrder = Math.max(maxOrder, c.order);
  });
  const knots = new Float64Array(kofs[n]);
  const coef = new Float64Array(cofs[n]);
  /** @type {[number, number] | null} */
  let span = null;
  curves.forEach((c, j) => {
    knots.set(c.knots, kofs[j]);
    const dim = dims[j];
    c.coef.forEach((row, r) => coef.set(row, cofs[j] + r * dim));
    const start = c.knots[c.order - 1];
    const end = c.knots[c.knots.length - c.order];
    span = span ? [Math.min(span[0], start), Math.max(span[1], end)] : [start, end];
  });
  return {
    paths: curves.map((c) => c.path), knots, kofs, coef, cofs, orders, dims, rotation, low, high, oofs,
    out: new Float64Array(oofs[n]), work: new Float64Array(maxOrder), span,
  };
}

/**
 * Every packed curve at `t` into `p.out` (and returned): the same arithmetic, in the
 * same order, as player.py's `_evaluate`.
 * @param {Packed} p
 * @param {number} t
 * @returns {Float64Array}
 */
export function evaluate(p, t) {
  const { knots, kofs, coef, cofs, orders, dims, rotation, low, high, oofs, out, work } = p;
  for (let j = 0; j < orders.length; j++) {
    const k = orders[j];
    const deg = k - 1;
    const k0 = kofs[j];
    const n = kofs[j + 1] - k0 - k;
    const x = Math.min(Math.max(t, knots[k0 + deg]), knots[k0 + n]);
    let lo = deg;
    let hi = n - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (knots[k0 + mid] <= x) lo = mid;
      else hi = mid - 1;
    }
    const i = lo;
    const d = dims[j];
    const c0 = cofs[j];
    let norm = 0.0;
    for (let ch = 0; ch < d; ch++) {
      for (let r = 0; r < k; r++) work[r] = coef[c0 + (i - deg + r) * d + ch];
      for (let r = 1; r < k; r++) {
        for (let s = deg; s > r - 1; s--) {
          const idx = k0 + i - deg + s;
          const alpha = (x - knots[idx]) / (knots[idx + k - r] - knots[idx]);
          work[s] = (1.0 - alpha) * work[s - 1] + alpha * work[s];
        }
      }
      out[oofs[j] + ch] = Math.min(Math.max(work[deg], low[j]), high[j]);
      norm += work[deg] * work[deg];
    }
    if (rotation[j]) {
      norm = Math.sqrt(norm);
      for (let ch = 0; ch < d; ch++) out[oofs[j] + ch] /= norm;
    }
  }
  return out;
}

/**
 * The value of the curve `j` of the last evaluation.
 * @param {Packed} p
 * @param {number} j
 * @returns {Float64Array}
 */
export function valueOf(p, j) {
  return p.out.subarray(p.oofs[j], p.oofs[j + 1]);
}

/**
 * A discrete track's value at `t`: the last value whose time is <= t (step semantics),
 * or null before the first.
 * @param {Steps} steps
 * @param {number} t
 * @returns {boolean|string|null}
 */
export function stepValue(steps, t) {
  let lo = 0;
  let hi = steps.times.length;
  while (lo < hi) {            // first index with time > t (searchsorted side="right")
    const mid = (lo + hi) >> 1;
    if (steps.times[mid] <= t) lo = mid + 1;
    else hi = mid;
  }
  return lo ? steps.values[lo - 1] : null;
}

/**
 * A curve's values at `times`, end to end (times.length rows of the curve's dim numbers),
 * as the page plays it.
 * @param {Curve} curve
 * @param {ArrayLike<number>} times
 * @returns {Float64Array}
 */
export function valuesAt(curve, times) {
  const p = pack([curve]);
  const dim = p.dims[0];
  const out = new Float64Array(times.length * dim);
  for (let i = 0; i < times.length; i++) out.set(evaluate(p, times[i]), i * dim);
  return out;
}

/**
 * A curve sampled at `count` evenly spaced times over [t0, t1] (for drawing).
 * @param {Curve} curve
 * @param {number} t0
 * @param {number} t1
 * @param {number} count
 * @returns {{times: Float64Array, values: Float64Array[]}} values[channel][i]
 */
export function sampleCurve(curve, t0, t1, count) {
  const times = Float64Array.from({ length: count }, (_, i) => (count > 1 ? t0 + ((t1 - t0) * i) / (count - 1) : t0));
  const flat = valuesAt(curve, times);
  const dim = count ? flat.length / count : (curve.coef[0]?.length ?? 0);
  const values = Array.from({ length: dim }, (_, ch) => Float64Array.from({ length: count }, (_, i) => flat[i * dim + ch]));
  return { times, values };
}
