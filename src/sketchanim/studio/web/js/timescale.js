// @ts-check
/** The time axis the timeline and the curve view share. */

/**
 * The seconds shown: the tracks' span, the loop and the playhead, at least 5 s from 0.
 * @param {[number, number]} span
 * @param {[number, number] | null} loop
 * @param {number} time
 * @returns {[number, number]}
 */
export function viewRange(span, loop, time) {
  const lo = Math.min(0, span[0], loop ? loop[0] : 0, time);
  const hi = Math.max(5, span[1], loop ? loop[1] : 0, time);
  const pad = (hi - lo) * 0.04;
  return [lo === 0 ? 0 : lo - pad, hi + pad];
}

/**
 * A round tick step (1, 2 or 5 times a power of ten) at least `minPixels` apart.
 * @param {number} pixelsPerSecond
 * @param {number} [minPixels]
 */
export function tickStep(pixelsPerSecond, minPixels = 60) {
  const raw = minPixels / Math.max(pixelsPerSecond, 1e-9);
  const p = 10 ** Math.floor(Math.log10(raw));
  return [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw) ?? 10 * p;
}

/**
 * Transport time as m:ss.cc.
 * @param {number} t seconds
 */
export function formatTime(t) {
  const sign = t < 0 ? '-' : '';
  const a = Math.abs(t);
  const m = Math.floor(a / 60);
  const s = a - 60 * m;
  return `${sign}${m}:${s.toFixed(2).padStart(5, '0')}`;
}
