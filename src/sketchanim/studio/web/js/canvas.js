// @ts-check
/**
 * A 2D canvas sized to its box at the screen's pixel ratio, ready to draw in CSS pixels.
 * @param {HTMLCanvasElement} c
 * @returns {{g: CanvasRenderingContext2D, w: number, h: number}}
 */
export function fitCanvas(c) {
  const w = c.clientWidth;
  const h = c.clientHeight;
  const dpr = window.devicePixelRatio || 1;
  if (c.width !== Math.round(w * dpr) || c.height !== Math.round(h * dpr)) {
    c.width = Math.round(w * dpr);
    c.height = Math.round(h * dpr);
  }
  const g = /** @type {CanvasRenderingContext2D} */ (c.getContext('2d'));
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  return { g, w, h };
}
