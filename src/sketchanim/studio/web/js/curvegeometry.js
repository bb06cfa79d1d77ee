// @ts-check
/**
 * The curve editor's pure math: where a B-spline's control points and keys sit, its basis
 * functions and their slopes at a time, the least change of control points that moves keys,
 * orientations as continuous Euler angles, and hit tests on points sorted by screen x.
 * No DOM; tests/studio/js/curveeditor.test.js checks it.
 *
 * A curve here is `knots` (non-decreasing, clamped) and `order` k (degree + 1); its n = knots.length - k
 * control points are rows of `coef`.
 */

/**
 * The Greville abscissae: control point i drawn at the mean of knots i+1 .. i+k-1.
 * @param {ArrayLike<number>} knots
 * @param {number} order
 * @returns {Float64Array}
 * @example greville([0, 0, 0, 0, 1, 1, 1, 1], 4)   // [0, 1/3, 2/3, 1]
 */
export function greville(knots, order) {
  const n = knots.length - order;
  const out = new Float64Array(n);
  const deg = order - 1;
  for (let i = 0; i < n; i++) {
    let sum = 0;
    for (let j = i + 1; j < i + order; j++) sum += knots[j];
    out[i] = deg > 0 ? sum / deg : knots[i];
  }
  return out;
}

/**
 * Where the keys sit: indices into `knots` of the curve's start, of the first copy of each
 * distinct interior knot, and of its end.
 * @param {ArrayLike<number>} knots
 * @param {number} order
 * @returns {Int32Array}
 * @example keyKnots([0, 0, 0, 0, 0.5, 0.5, 1, 1, 1, 1], 4)   // [3, 4, 6]
 */
export function keyKnots(knots, order) {
  const n = knots.length - order;
  const out = [order - 1];
  for (let i = order; i < n; i++) if (knots[i] !== knots[i - 1] && knots[i] !== knots[order - 1]) out.push(i);
  if (knots[n] !== knots[out[out.length - 1]]) out.push(n);
  return Int32Array.from(out);
}

/**
 * The knot span of `t` (clamped to the curve's span): the largest i in [k-1, n-1] with knots[i] <= t.
 * @param {ArrayLike<number>} knots
 * @param {number} order
 * @param {number} t
 */
export function spanOf(knots, order, t) {
  const n = knots.length - order;
  const x = Math.min(Math.max(t, knots[order - 1]), knots[n]);
  let lo = order - 1;
  let hi = n - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (knots[mid] <= x) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

/**
 * The k basis functions active at `t` and their derivatives (per second): control point
 * `first + r` weighs `value[r]` in the curve's value and `slope[r]` in its slope.
 * @param {ArrayLike<number>} knots
 * @param {number} order
 * @param {number} t
 * @returns {{first: number, value: Float64Array, slope: Float64Array}}
 * @example basisAt([0, 0, 1, 1], 2, 0.25)   // first 0, value [0.75, 0.25], slope [-1, 1]
 */
export function basisAt(knots, order, t) {
  const p = order - 1;
  const span = spanOf(knots, order, t);
  const n = knots.length - order;
  const x = Math.min(Math.max(t, knots[p]), knots[n]);
  const N = new Float64Array(order);
  const left = new Float64Array(order);
  const right = new Float64Array(order);
  N[0] = 1;
  let low = new Float64Array(1).fill(1);            // degree p-1 basis (for the slope)
  for (let j = 1; j <= p; j++) {
    if (j === p) low = N.slice(0, p);
    left[j] = x - knots[span + 1 - j];
    right[j] = knots[span + j] - x;
    let saved = 0;
    for (let r = 0; r < j; r++) {
      const temp = N[r] / (right[r + 1] + left[j - r]);
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
  const first = span - p;
  const slope = new Float64Array(order);
  if (p > 0) {
    for (let r = 0; r <= p; r++) {
      const i = first + r;
      const a = r >= 1 ? low[r - 1] / (knots[i + p] - knots[i]) : 0;
      const b = r <= p - 1 ? low[r] / (knots[i + p + 1] - knots[i + 1]) : 0;
      slope[r] = p * ((Number.isFinite(a) ? a : 0) - (Number.isFinite(b) ? b : 0));
    }
  }
  return { first, value: N, slope };
}

/**
 * The curve's raw value (not normalised, not clamped) and slope at `t`, one number per channel.
 * @param {ArrayLike<number>} knots
 * @param {number} order
 * @param {number[][]} coef
 * @param {number} t
 * @returns {{value: number[], slope: number[]}}
 */
export function valueAndSlope(knots, order, coef, t) {
  const { first, value, slope } = basisAt(knots, order, t);
  const dim = coef[0].length;
  const v = new Array(dim).fill(0);
  const s = new Array(dim).fill(0);
  for (let r = 0; r < order; r++) {
    const row = coef[first + r];
    for (let ch = 0; ch < dim; ch++) {
      v[ch] += value[r] * row[ch];
      s[ch] += slope[r] * row[ch];
    }
  }
  return { value: v, slope: s };
}

/**
 * The least change of the control points (least sum of squares) that moves the curve's value
 * (or, with `slope`, its slope) at each of `times` by 1: add `d` times the response to a
 * channel's control points to move it by `d` at all of them at once. The equations are banded
 * (a time involves k control points), solved by a banded Cholesky factorisation.
 * @param {ArrayLike<number>} knots
 * @param {number} order
 * @param {number[]} times  distinct, increasing
 * @param {boolean} [slope]
 * @returns {Float64Array} one weight per control point (zero off the times' spans)
 * @example response([0, 0, 1, 1], 2, [0.25])   // [1.2, 0.4]: 0.75 * 1.2 + 0.25 * 0.4 = 1
 */
export function response(knots, order, times, slope = false) {
  const n = knots.length - order;
  const m = times.length;
  const rows = times.map((t) => {
    const b = basisAt(knots, order, t);
    return { first: b.first, w: slope ? b.slope : b.value };
  });
  const band = order;                                   // rows i and j share points only when |i - j| < band
  /** @type {Float64Array[]} G[i][i - j] for j in [i - band, i] (the lower band of A Aᵀ) */
  const G = rows.map(() => new Float64Array(band + 1));
  for (let i = 0; i < m; i++) {
    for (let d = 0; d <= band && d <= i; d++) {
      const a = rows[i];
      const b = rows[i - d];
      let dot = 0;
      for (let r = 0; r < order; r++) {
        const q = a.first + r - b.first;
        if (q >= 0 && q < order) dot += a.w[r] * b.w[q];
      }
      G[i][d] = dot;
    }
  }
  // Cholesky in place: G = L Lᵀ (L[i][d] = L_{i, i-d})
  for (let i = 0; i < m; i++) {
    for (let d = Math.min(band, i); d >= 0; d--) {
      const j = i - d;
      let sum = G[i][d];
      for (let e = 1; e <= band - d && e <= j; e++) sum -= G[i][d + e] * G[j][e];
      if (d === 0) G[i][0] = Math.sqrt(Math.max(sum, 1e-300));
      else G[i][d] = sum / G[j][0];
    }
  }
  const y = new Float64Array(m);
  for (let i = 0; i < m; i++) {                         // L y = 1
    let sum = 1;
    for (let d = 1; d <= band && d <= i; d++) sum -= G[i][d] * y[i - d];
    y[i] = sum / G[i][0];
  }
  for (let i = m - 1; i >= 0; i--) {                    // Lᵀ z = y
    let sum = y[i];
    for (let d = 1; d <= band && i + d < m; d++) sum -= G[i + d][d] * y[i + d];
    y[i] = sum / G[i][0];
  }
  const out = new Float64Array(n);
  rows.forEach((row, i) => { for (let r = 0; r < order; r++) out[row.first + r] += row.w[r] * y[i]; });
  return out;
}

const DEG = 180 / Math.PI;

/**
 * A unit quaternion (x, y, z, w) as Euler angles in degrees (three.js's 'XYZ' order).
 * @param {ArrayLike<number>} q
 * @returns {[number, number, number]}
 * @example quatToEuler([Math.SQRT1_2, 0, 0, Math.SQRT1_2])   // [90, 0, 0]
 */
export function quatToEuler(q) {
  const [x, y, z, w] = [q[0], q[1], q[2], q[3]];
  const m11 = 1 - 2 * (y * y + z * z);
  const m12 = 2 * (x * y - z * w);
  const m13 = 2 * (x * z + y * w);
  const m22 = 1 - 2 * (x * x + z * z);
  const m23 = 2 * (y * z - x * w);
  const m32 = 2 * (y * z + x * w);
  const m33 = 1 - 2 * (x * x + y * y);
  const ey = Math.asin(Math.min(Math.max(m13, -1), 1));
  if (Math.abs(m13) < 0.9999999) return [Math.atan2(-m23, m33) * DEG, ey * DEG, Math.atan2(-m12, m11) * DEG];
  return [Math.atan2(m32, m22) * DEG, ey * DEG, 0];
}

/**
 * Euler angles in degrees ('XYZ') as a unit quaternion (x, y, z, w).
 * @param {ArrayLike<number>} e
 * @returns {[number, number, number, number]}
 * @example eulerToQuat([90, 0, 0])   // [0.7071, 0, 0, 0.7071]
 */
export function eulerToQuat(e) {
  const c1 = Math.cos(e[0] / DEG / 2), c2 = Math.cos(e[1] / DEG / 2), c3 = Math.cos(e[2] / DEG / 2);
  const s1 = Math.sin(e[0] / DEG / 2), s2 = Math.sin(e[1] / DEG / 2), s3 = Math.sin(e[2] / DEG / 2);
  return [s1 * c2 * c3 + c1 * s2 * s3, c1 * s2 * c3 - s1 * c2 * s3, c1 * c2 * s3 + s1 * s2 * c3, c1 * c2 * c3 - s1 * s2 * s3];
}

/**
 * The Euler angles of the same rotation as `e` nearest to `ref`: of `e` and its twin
 * (x + 180, 180 - y, z + 180), each channel moved by whole turns to be within 180 of `ref`'s.
 * @param {ArrayLike<number>} e
 * @param {ArrayLike<number>} ref
 * @returns {[number, number, number]}
 * @example nearestEuler([-179, 0, 0], [179, 0, 0])   // [181, 0, 0]
 */
export function nearestEuler(e, ref) {
  /** @type {[number, number, number]} */
  let best = [e[0], e[1], e[2]];
  let bestDistance = Infinity;
  for (const c of [[e[0], e[1], e[2]], [e[0] + 180, 180 - e[1], e[2] + 180]]) {
    /** @type {[number, number, number]} */
    const shifted = [0, 0, 0];
    let distance = 0;
    for (let ch = 0; ch < 3; ch++) {
      shifted[ch] = c[ch] + 360 * Math.round((ref[ch] - c[ch]) / 360);
      distance += Math.abs(shifted[ch] - ref[ch]);
    }
    if (distance < bestDistance - 1e-9) { best = shifted; bestDistance = distance; }
  }
  return best;
}

/**
 * Quaternions (a series in time) as continuous Euler angles: each the nearest (nearestEuler)
 * to the one before, so no channel jumps by 360.
 * @param {ArrayLike<number>[]} quats
 * @returns {[number, number, number][]}
 */
export function unwrappedEulers(quats) {
  /** @type {[number, number, number][]} */
  const out = [];
  for (const q of quats) out.push(out.length ? nearestEuler(quatToEuler(q), out[out.length - 1]) : quatToEuler(q));
  return out;
}

/**
 * The index range [lo, hi) of the sorted `xs` within [a, b].
 * @param {ArrayLike<number>} xs non-decreasing
 * @param {number} a
 * @param {number} b
 * @returns {[number, number]}
 */
export function rangeOf(xs, a, b) {
  const first = (/** @type {number} */ v) => {
    let lo = 0;
    let hi = xs.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (xs[mid] < v) lo = mid + 1;
      else hi = mid;
    }
    return lo;
  };
  const lo = first(a);
  let hi = first(b);
  while (hi < xs.length && xs[hi] <= b) hi += 1;
  return [lo, hi];
}

/**
 * The point nearest (x, y) within `radius` of it among points sorted by x, or -1: a binary
 * search for the x range, then a scan of it.
 * @param {ArrayLike<number>} xs non-decreasing
 * @param {ArrayLike<number>} ys
 * @param {number} x
 * @param {number} y
 * @param {number} radius
 * @returns {{index: number, distance: number}}
 * @example nearestPoint([0, 10, 20], [0, 0, 5], 19, 4, 3)   // {index: 2, distance: 1.41}
 */
export function nearestPoint(xs, ys, x, y, radius) {
  const [lo, hi] = rangeOf(xs, x - radius, x + radius);
  let index = -1;
  let best = radius * radius;
  for (let i = lo; i < hi; i++) {
    const d = (xs[i] - x) ** 2 + (ys[i] - y) ** 2;
    if (d <= best) { best = d; index = i; }
  }
  return { index, distance: Math.sqrt(best) };
}
