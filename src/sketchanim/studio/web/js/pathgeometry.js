// @ts-check
/**
 * The arithmetic of the 3D view's motion paths and onion skin, without three.js: the range
 * of time a path shows, the frames in it, which control
 * points act on a range, a curve with points moved, and the times of the onion skin's ghosts.
 */

/** @typedef {import('./evaluate.js').Curve} Curve */

/** Seconds a motion path shows either side of the playhead (when no loop range is set). */
export const AROUND = 2;

/**
 * The frame (of `fps` frames per second) nearest `time`.
 * @param {number} time
 * @param {number} fps
 * @example
 * frameAt(1.02, 24);   // 24
 */
export function frameAt(time, fps) {
  return Math.round(time * fps);
}

/**
 * The range of time a motion path shows: the loop range when one is set, else `around`
 * seconds (whole frames) either side of the playhead's frame; cut to the curve's span
 * [start, end] (the curve holds outside it). Null when none of the span is in range.
 * @param {number} time  the playhead
 * @param {number} fps
 * @param {[number, number] | null} loop
 * @param {number} start
 * @param {number} end
 * @param {number} [around]
 * @returns {[number, number] | null}
 * @example
 * pathRange(1, 24, null, 0, 10);       // [0, 3]
 * pathRange(1, 24, [0.5, 1.5], 0, 10); // [0.5, 1.5]
 */
export function pathRange(time, fps, loop, start, end, around = AROUND) {
  const f = frameAt(time, fps);
  const reach = Math.round(around * fps);
  const [a, b] = loop && loop[1] > loop[0] ? loop : [(f - reach) / fps, (f + reach) / fps];
  const t0 = Math.max(a, start);
  const t1 = Math.min(b, end);
  return t1 > t0 ? [t0, t1] : null;
}

/**
 * The times of the frames (k / fps) in [t0, t1], ends included (to a nanosecond).
 * @param {number} t0
 * @param {number} t1
 * @param {number} fps
 * @returns {number[]}
 * @example
 * framesIn(0.01, 0.1, 24);   // [1/24, 2/24]
 */
export function framesIn(t0, t1, fps) {
  const first = Math.ceil(t0 * fps - 1e-9);
  const last = Math.floor(t1 * fps + 1e-9);
  return Array.from({ length: Math.max(0, last - first + 1) }, (_, i) => (first + i) / fps);
}

/**
 * Times from t0 to t1 at most `step` apart, evenly spaced, both ends included.
 * @param {number} t0
 * @param {number} t1
 * @param {number} step
 * @returns {number[]}
 * @example
 * spanTimes(0, 1, 0.4);   // [0, 1/3, 2/3, 1]
 */
export function spanTimes(t0, t1, step) {
  const n = Math.max(1, Math.ceil((t1 - t0) / step - 1e-9));
  return Array.from({ length: n + 1 }, (_, i) => (i === n ? t1 : t0 + ((t1 - t0) * i) / n));
}

/**
 * The control points acting on some of (t0, t1): point i of a curve of order k acts on
 * (knots[i], knots[i + k]) only.
 * @param {Curve} curve
 * @param {number} t0
 * @param {number} t1
 * @returns {number[]} their indices into `coef`
 * @example
 * pointsActing({path: 'a', order: 2, knots: [0, 0, 1, 2, 2], coef: [[0], [1], [0]]}, 1.5, 2);   // [1, 2]
 */
export function pointsActing(curve, t0, t1) {
  const k = curve.order;
  /** @type {number[]} */
  const acting = [];
  for (let i = 0; i < curve.coef.length; i++) {
    if (curve.knots[i] < t1 && curve.knots[i + k] > t0) acting.push(i);
  }
  return acting;
}

/**
 * A copy of `curve` with control points moved (the rows not moved shared with `curve`).
 * @template {Curve} C
 * @param {C} curve
 * @param {Map<number, number[]>} moved  new values, by index into `coef`
 * @returns {C}
 * @example
 * const line = {path: 'a.position', order: 2, knots: [0, 0, 1, 1], coef: [[0, 0, 0], [1, 1, 1]]};
 * withPoints(line, new Map([[1, [5, 5, 5]]])).coef;   // [[0, 0, 0], [5, 5, 5]]
 */
export function withPoints(curve, moved) {
  return { ...curve, coef: curve.coef.map((row, i) => moved.get(i) ?? row) };
}

/**
 * The times of the onion skin's ghosts: `count` frames `every` frames apart before the
 * playhead's frame (nearest first) and as many after it.
 * @param {number} time
 * @param {number} fps
 * @param {number} count
 * @param {number} every
 * @returns {{before: number[], after: number[]}}
 * @example
 * ghostTimes(1, 24, 2, 4);   // {before: [20/24, 16/24], after: [28/24, 32/24]}
 */
export function ghostTimes(time, fps, count, every) {
  const f = frameAt(time, fps);
  const at = (/** @type {number} */ sign) => Array.from({ length: count }, (_, j) => (f + sign * every * (j + 1)) / fps);
  return { before: at(-1), after: at(1) };
}
