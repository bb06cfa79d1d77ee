// @ts-check
/**
 * Where a new object goes: in front of the camera, on the height objects stand at, and
 * clear of every object already there. Pure functions (no three.js, no DOM).
 */

/** @typedef {[number, number, number]} Vec3 */
/** @typedef {{position: Vec3, radius: number}} Occupied  a sphere an object fills */

/** Metres ahead of the camera, along its view direction flattened onto the floor. */
export const AHEAD = 3;
/** The height new objects are placed at (the centre of a unit shape standing on the floor at y = 0). */
export const HEIGHT = 0.5;
/** The room a new object needs around its centre (metres). */
export const RADIUS = 0.5;
/** Metres a blocked spot moves sideways at each try (right, left, twice as far right, ...). */
export const STEP = 0.5;
/** Tries sideways before the spot straight ahead is taken all the same. */
export const TRIES = 64;

/**
 * A spot ~AHEAD m in front of the camera at height HEIGHT, moved sideways (right, left,
 * further right, further left, by STEP) until a sphere of RADIUS there is clear of every
 * occupied sphere. Looking straight down or up, "ahead" is the camera's −z.
 * @param {Vec3} cameraPosition
 * @param {Vec3} cameraDirection where the camera looks (need not be unit length)
 * @param {Occupied[]} occupied
 * @returns {Vec3}
 *
 * @example
 * placeInFront([0, 1.6, 6], [0, -0.2, -1], []);                                // [0, 0.5, 3]
 * placeInFront([0, 1.6, 6], [0, -0.2, -1], [{position: [0, 0.5, 3], radius: 0.6}]);  // [1.5, 0.5, 3]: moved right
 */
export function placeInFront(cameraPosition, cameraDirection, occupied) {
  let [dx, , dz] = cameraDirection;
  let len = Math.hypot(dx, dz);
  if (len < 1e-6) { dx = 0; dz = -1; len = 1; }
  dx /= len; dz /= len;
  const ahead = [cameraPosition[0] + AHEAD * dx, cameraPosition[2] + AHEAD * dz];
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
