// @ts-check
/**
 * A gamepad or a 3D mouse (through the browser's Gamepad API) as a 6-degree-of-freedom
 * velocity device, as the paper's Spaceball: the selected object moves and turns at once,
 * relative to the view. Pure functions: the viewport reads navigator.getGamepads() each
 * frame and applies the motion.
 *
 * Quaternions are scalar-last [x, y, z, w], as the model and three.js hold them.
 */

/** Axis values below this are rest (sticks do not centre exactly). */
export const DEADZONE = 0.12;
/** Scene units per second at full tilt. */
export const SPEED = 1.5;
/** Radians per second at full tilt. */
export const TURN_RATE = 2;
/** The smallest change of tilt a hand holds on a stick: 1% of full tilt (finer than any
 * stick's converter, 8 bits or more, resolves at rest). */
export const STICK_STEP = 0.01;

/**
 * @typedef {object} PadInput  Velocities in the view's frame (x right, y up, z toward
 *   the viewer), each in -1..1.
 * @property {[number, number, number]} move
 * @property {[number, number, number]} turn
 */

/** @param {number} v */
function dead(v) {
  const a = Math.abs(v);
  return a < DEADZONE ? 0 : (Math.sign(v) * (a - DEADZONE)) / (1 - DEADZONE);
}

/**
 * The motion a device asks for. A device with 6 or more axes is a 3D mouse (axes 0-2
 * translate x, y, z; 3-5 rotate about x, y, z, its own conventions: x right, y toward the
 * user, z down); a standard gamepad moves in the view's plane with the left stick,
 * up and down with the triggers (buttons 6, 7) and turns with the right stick.
 * @param {{axes: readonly number[], buttons: readonly {value: number}[]}} pad
 * @returns {PadInput}
 */
export function readPad(pad) {
  const a = pad.axes.map(dead);
  if (a.length >= 6) return { move: [a[0], -a[2], a[1]], turn: [a[3], -a[5], a[4]] };
  const button = (/** @type {number} */ i) => (pad.buttons[i] ? pad.buttons[i].value : 0);
  const lift = dead(button(7)) - dead(button(6));
  return { move: [a[0] ?? 0, lift, a[1] ?? 0], turn: [-(a[3] ?? 0), -(a[2] ?? 0), 0] };
}

/**
 * Whether the device is asking for any motion.
 * @param {PadInput} input
 */
export function active(input) {
  return input.move.some((v) => v !== 0) || input.turn.some((v) => v !== 0);
}

/**
 * `v` rotated by the unit quaternion `q`.
 * @param {number[]} q
 * @param {number[]} v
 * @returns {[number, number, number]}
 */
export function rotate(q, v) {
  const [x, y, z, w] = q;
  const tx = 2 * (y * v[2] - z * v[1]);
  const ty = 2 * (z * v[0] - x * v[2]);
  const tz = 2 * (x * v[1] - y * v[0]);
  return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
}

/**
 * The product a * b (b applied first).
 * @param {number[]} a
 * @param {number[]} b
 * @returns {[number, number, number, number]}
 */
export function multiply(a, b) {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = b;
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}

/**
 * Move and turn an object for `dt` seconds of device input: the motion is in the view's
 * frame (`view`: the viewing camera's orientation), turning about the object's centre.
 * @param {number[]} position
 * @param {number[]} orientation unit quaternion
 * @param {PadInput} input
 * @param {number} dt seconds
 * @param {number[]} view the camera's orientation
 * @param {{speed?: number, turnRate?: number}} [rates] scene units / s, radians / s at full tilt
 * @returns {{position: number[], orientation: number[]}}
 */
export function applyPad(position, orientation, input, dt, view, rates = {}) {
  const speed = rates.speed ?? SPEED;
  const turnRate = rates.turnRate ?? TURN_RATE;
  const step = rotate(view, input.move);
  const next = position.map((p, i) => p + step[i] * speed * dt);
  const axis = rotate(view, input.turn);
  const angle = Math.hypot(...axis) * turnRate * dt;
  if (angle === 0) return { position: next, orientation: orientation.slice() };
  const s = Math.sin(angle / 2) / Math.hypot(...axis);
  const q = multiply([axis[0] * s, axis[1] * s, axis[2] * s, Math.cos(angle / 2)], orientation);
  const n = Math.hypot(...q);
  return { position: next, orientation: q.map((v) => v / n) };
}

/**
 * What a stick resolves, over the speed it maps to: the distance (scene units) and the
 * turn (degrees) one `STICK_STEP` of tilt makes in a second.
 * @param {{speed?: number, turnRate?: number}} [rates] as applyPad's
 * @returns {{position: number, orientation: number}}
 * @example padResolution() // {position: 0.015, orientation: 1.146} (1.5 units/s, 2 rad/s at full tilt)
 */
export function padResolution(rates = {}) {
  return { position: (rates.speed ?? SPEED) * STICK_STEP, orientation: ((rates.turnRate ?? TURN_RATE) * STICK_STEP * 180) / Math.PI };
}
