// @ts-check
/**
 * What an input resolves, in the units of the attribute it moves, and the take tolerance
 * made from it. A pointer resolves a pixel: at the grabbed point's depth one pixel is
 * `pixelWorld` scene units; a turn gizmo turns `turnPerPixel` degrees per pixel; a slider
 * moves `sliderPerPixel` of its value. A colour picker resolves its step (1/255 of a
 * channel), a gamepad its stick's step (see gamepad.js). A take's tolerance is
 * `DEFAULT_STEPS` of these steps unless the animator set another (in steps, or in the
 * attribute's own units). Pure functions: the page's inputs call them when a take starts.
 */

/**
 * Steps of the input a take is kept within by default: 2 px for a pointer. Measured with
 * benchmarks/bench_takes.py: a 2 s drag with 1 px of hand jitter gives 4.5 samples per
 * control point at 2 px (2.6 at 1.5 px, 1.5 at 1 px), its curve within 2 px of the hand;
 * the pointer itself reports whole pixels, so half a pixel of every sample is rounding.
 */
export const DEFAULT_STEPS = 2;

/** A colour picker's step: one of the 255 levels of an 8-bit channel. */
export const PICKER_STEP = 1 / 255;

/** Radians a three.js TransformControls rotation turns per scene unit the pointer moves, times the distance to the object. */
const GIZMO_TURN = 20;

/**
 * @typedef {object} Resolution  What one input step is in an attribute's units.
 * @property {number} step   the attribute's units per step (> 0)
 * @property {string} input  what a step is: 'px', 'step'
 */

/**
 * @typedef {object} ToleranceSetting  The animator's tolerance for an attribute.
 * @property {number} amount  > 0
 * @property {'px' | 'units'} unit  input steps (pixels for a pointer), or the attribute's units
 */

/**
 * Scene units one pixel spans at `depth` in front of a perspective camera.
 * @param {number} fov    the camera's vertical field of view, degrees
 * @param {number} height the view's height, CSS pixels
 * @param {number} depth  distance along the view direction, scene units
 * @returns {number}
 * @example pixelWorld(90, 200, 1) // 0.01: the view spans 2 units over 200 px at depth 1
 */
export function pixelWorld(fov, height, depth) {
  if (!(fov > 0 && fov < 180 && height > 0 && depth > 0)) {
    throw new RangeError(`pixelWorld: needs 0 < fov < 180, height > 0, depth > 0 (got ${fov}, ${height}, ${depth})`);
  }
  return (2 * depth * Math.tan((fov * Math.PI) / 360)) / height;
}

/**
 * Degrees a rotation gizmo (three.js TransformControls: 20 / distance radians per
 * scene unit of pointer travel) turns per pixel.
 * @param {number} pixel    scene units per pixel at the object (pixelWorld)
 * @param {number} distance the object's distance from the camera, scene units
 * @returns {number}
 * @example turnPerPixel(0.01, 10) // 20 * 0.01 / 10 rad = 1.146 degrees
 */
export function turnPerPixel(pixel, distance) {
  return ((GIZMO_TURN * pixel) / distance) * (180 / Math.PI);
}

/**
 * A slider's value per pixel of its track.
 * @param {number} lo
 * @param {number} hi
 * @param {number} width the track's width, CSS pixels
 * @returns {number}
 * @example sliderPerPixel(0, 5, 250) // 0.02
 */
export function sliderPerPixel(lo, hi, width) {
  if (!(hi > lo && width > 0)) throw new RangeError(`sliderPerPixel: needs hi > lo, width > 0 (got ${lo}, ${hi}, ${width})`);
  return (hi - lo) / width;
}

/**
 * A take's tolerance for an attribute: `setting` (the animator's), else `DEFAULT_STEPS`
 * of the input's steps; and how many steps that is.
 * @param {Resolution} resolution
 * @param {ToleranceSetting | null | undefined} setting
 * @returns {{tol: number, steps: number}}
 * @example takeTolerance({step: 0.015, input: 'px'}, null) // {tol: 0.03, steps: 2}
 */
export function takeTolerance(resolution, setting) {
  const step = resolution.step;
  if (!(step > 0 && Number.isFinite(step))) throw new RangeError(`takeTolerance: a step must be > 0 and finite (got ${step})`);
  if (setting && setting.unit === 'units') return { tol: setting.amount, steps: setting.amount / step };
  const steps = setting ? setting.amount : DEFAULT_STEPS;
  return { tol: steps * step, steps };
}

/**
 * A tolerance as the page shows it: "tol 2 px = 0.03" ("tol 0.03" without steps: NaN).
 * @param {{tol: number, steps: number}} t
 * @param {string} input what a step is ('px', 'step')
 * @param {string} [unit] the attribute's unit ('°' for degrees)
 * @returns {string}
 * @example formatTolerance({tol: 0.03, steps: 2}, 'px') // 'tol 2 px = 0.03'
 */
export function formatTolerance(t, input, unit = '') {
  const steps = Number(t.steps.toPrecision(2));
  const tol = Number(t.tol.toPrecision(2));
  if (!Number.isFinite(steps)) return `tol ${tol}${unit}`;
  return `tol ${steps} ${input}${input === 'px' ? '' : steps === 1 ? '' : 's'} = ${tol}${unit}`;
}
