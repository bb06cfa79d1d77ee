// @ts-check
/**
 * Where a new object goes: where the camera looks, at the height objects stand at, and
 * clear of every object already there. Pure functions (no three.js, no DOM).
 */

/** @typedef {[number, number, number]} Vec3 */
/** @typedef {{position: Vec3, radius: number}} Occupied  a sphere an object fills */

/** Metres ahead of the camera, along its view direction flattened onto the floor, when its line of sight does not meet the height of interest in NEAR..FAR. */
export const AHEAD = 3;
/** The height of interest: new objects are placed at it (the centre of a unit shape standing on the floor at y = 0). */
export const HEIGHT = 0.5;
/** Metres along the line of sight within which where it meets the height of interest is taken (what one looks at). */
export const NEAR = 1;
export const FAR = 15;
/** The room a new object needs around its centre (metres). */
export const RADIUS = 0.5;
/** Metres a blocked spot moves sideways at each try (right, left, twice as far right, ...). */
export const STEP = 0.5;
/** Tries sideways before the spot straight ahead is taken all the same. */
export const TRIES = 64;

/**
 * Where a new object goes: where the camera's line of sight meets the height of interest
 * (HEIGHT), if it does between NEAR and FAR metres from the camera (what one looks at, so the
 * object is in view), else AHEAD m in front of the camera along the view direction flattened
 * onto the floor, at HEIGHT; moved sideways (right, left, further right, further left, by
 * STEP) until a sphere of RADIUS there is clear of every occupied sphere. Looking straight
 * down or up (no flattened direction), "ahead" is the world's −z.
 * @param {Vec3} cameraPosition
 * @param {Vec3} cameraDirection where the camera looks (need not be unit length)
 * @param {Occupied[]} occupied
 * @returns {Vec3}
 *
 * @example
 * placeInFront([0, 1.6, 6], [0, -0.2, -1], []);                                  // [0, 0.5, 0.5]: the line of sight at y = 0.5
 * placeInFront([0, 1.6, 6], [0, 0, -1], []);                                     // [0, 0.5, 3]: level, AHEAD m on
 * placeInFront([0, 1.6, 6], [0, 0, -1], [{position: [0, 0.5, 3], radius: 0.6}]);   // [1.5, 0.5, 3]: moved right
 */
export function placeInFront(cameraPosition, cameraDirection, occupied) {
  const ahead = sightPoint(cameraPosition, cameraDirection);
  let [dx, , dz] = cameraDirection;
  let len = Math.hypot(dx, dz);
  if (len < 1e-6) { dx = 0; dz = -1; len = 1; }
  dx /= len; dz /= len;
  const right = [-dz, dx];                      // y up: the camera's right on the floor
  for (let i = 0; i < TRIES; i++) {
    const side = sideways(i) * STEP;
    /** @type {Vec3} */
    const spot = [ahead[0] + side * right[0], HEIGHT, ahead[1] + side * right[1]];
    if (clear(spot, occupied)) return [tidy(spot[0]), HEIGHT, tidy(spot[2])];
  }
  return [tidy(ahead[0]), HEIGHT, tidy(ahead[1])];
}

/**
 * The x and z of where the line of sight meets y = HEIGHT within NEAR..FAR metres, else of
 * the point AHEAD m on along the view direction flattened onto the floor.
 * @param {Vec3} p
 * @param {Vec3} d
 * @returns {[number, number]}
 */
function sightPoint(p, d) {
  const norm = Math.hypot(...d);
  const t = norm > 0 && d[1] !== 0 ? ((HEIGHT - p[1]) / d[1]) * norm : -1;     // metres along the line of sight
  if (t >= NEAR && t <= FAR) return [p[0] + (t * d[0]) / norm, p[2] + (t * d[2]) / norm];
  const flat = Math.hypot(d[0], d[2]);
  return flat < 1e-6 ? [p[0], p[2] - AHEAD] : [p[0] + (AHEAD * d[0]) / flat, p[2] + (AHEAD * d[2]) / flat];
}

/**
 * The i-th sideways offset in steps: 0, 1, −1, 2, −2, ...
 * @param {number} i
 */
function sideways(i) {
  const n = Math.ceil(i / 2);
  return i % 2 === 1 ? n : -n;
}

/**
 * Whether a sphere of RADIUS at `spot` overlaps none of `occupied`.
 * @param {Vec3} spot
 * @param {Occupied[]} occupied
 */
function clear(spot, occupied) {
  return occupied.every(({ position: p, radius }) => Math.hypot(spot[0] - p[0], spot[1] - p[1], spot[2] - p[2]) >= radius + RADIUS);
}

/** @param {number} x rounded to the millimetre (no −0) */
function tidy(x) {
  return Math.round(x * 1000) / 1000 + 0;
}
