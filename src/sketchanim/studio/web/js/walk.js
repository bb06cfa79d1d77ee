// @ts-check
/**
 * A humanoid walking along a performed ground path: the page's copy of
 * src/sketchanim/motion/walk.py, operation for operation (so the two agree to 1e-6 rad;
 * tests/motion/test_walk.py runs tests/studio/js/walk_path.mjs to check it). The walker's
 * goal is a ground marker (its y the ground height under it); the figure faces along the
 * path, its step length and cadence following the path's speed (Boulic's relative cycle
 * length 1.346 sqrt(v / H)), its feet planted during stance and stepping when a foot drifts
 * past a threshold, one leg at a time, running above the walk-run speed, falling behind
 * the marker beyond the fastest run. docs/walker.md describes the model. The figure is
 * humanoid.js's (re-exported here), the leg IK twobone.js's.
 *
 * A deterministic simulation at RATE ticks a second (ik.js's, re-exported) from the start of the animation:
 * `start` stands the figure at the first marker (tick 0), `advance` steps it one tick, so
 * the pose is a pure function of the marker's curve; `walk` is `advance` in a loop. Pure:
 * no three.js. Conventions: y up, heading 0 faces +z (heading a faces (sin a, 0, cos a)),
 * the left side on +x; rotations local, scalar-last quaternions, world = parent * local,
 * a joint's local transform T(offset) R(rotation).
 */

import { humanoid, rig } from './humanoid.js';
import { RATE } from './ik.js';
import { twoBone, localFrame, frameQuaternion } from './twobone.js';

export { humanoid, rig, RATE };

/** @typedef {import('./humanoid.js').Vec} Vec */
/** @typedef {import('./humanoid.js').Skeleton} Skeleton */
/** @typedef {import('./humanoid.js').Rig} Rig */
/** @typedef {import('./twobone.js').Frame} Frame */

/** Boulic's relative cycle length per square root of relative velocity. */
export const CYCLE = 1.346;
/** Below this relative velocity (1/s) the cycle's timing is held at its value here. */
export const RV_SLOW = 1.0;
/** The walk-run speed, relative. */
export const RV_RUN = 2.3;
/** The fastest run, relative: beyond RV_FASTEST * H m/s the figure falls behind. */
export const RV_FASTEST = 7.5;
/** A run's stance length, in leg lengths. */
export const RUN_CONTACT = 0.8;
/** The velocity's smoothing time constant, seconds. */
export const SMOOTHING = 0.15;
/** Fastest turn, rad/s. */
export const TURN_RATE = 3.0;
/** While the body turns, the feet step at least at the cadence of this relative speed. */
export const RV_TURN = 2.0;
/** Slowest speed the body turns to face, relative. */
export const RV_FACE = 0.1;
/** Least drift (leg lengths) that makes a planted foot step, and the yaw drift (rad). */
export const DRIFT_MIN = 0.09;
export const DRIFT_YAW = 0.35;
/** The least drift (leg lengths) once the body is still: the stop steps. */
export const DRIFT_SETTLE = 0.04;
/** Shortest time a foot stays planted, seconds. */
export const STANCE_MIN = 0.1;
/** A foot drifted this far past its threshold lifts once the other is planted (running: lifted) STANCE_MIN. */
export const OVERDUE = 1.1;
/** Where a foot lands: this fraction of its stance's travel short of centred under its hip. */
export const LAND_SHIFT = 0.15;
/** The most a planted foot's heel rises (rad, pivoting on the toe). */
export const HEEL_MAX = 0.9;
/** Swing clearance at mid-swing, leg lengths. */
export const CLEARANCE = 0.08;
/** The pelvis's usual height, the legs' reach fraction, the lowest it goes. */
export const CROUCH = 0.98;
export const REACH = 0.995;
export const FLOOR = 0.7;
/** How far (leg lengths) a run sinks the hips at mid-stance. */
export const RUN_SINK = 0.05;
/** Arm swing (rad per leg length of foot separation), its bound, elbow bends. */
export const ARM_SWING = 0.7;
export const ARM_MAX = 0.8;
export const ELBOW_WALK = 0.25;
export const ELBOW_RUN = 1.4;
/** Forward lean of the spine: at rest, per m/s, at most (rad). */
export const LEAN_REST = 0.03;
export const LEAN_SPEED = 0.03;
export const LEAN_MAX = 0.3;
/** The lift tick of a foot that has not stepped yet. */
export const NEVER = -1000000;

/**
 * @typedef {object} Foot  Its ankle were the foot flat, yaw, heel pitch; planted since tick
 *   `landed`, or swinging since tick `lifted` from `liftAt` / `liftYaw` / `liftPitch`, the
 *   hips then held down to `liftHeight` by its reach, `progress` of the swing done.
 * @property {Vec} ankle
 * @property {number} yaw
 * @property {number} pitch
 * @property {boolean} planted
 * @property {number} landed
 * @property {number} lifted
 * @property {Vec} liftAt
 * @property {number} liftYaw
 * @property {number} liftPitch
 * @property {number} progress
 * @property {number} liftHeight
 */
/**
 * @typedef {object} WalkState  The walker at one tick (see walk.py's WalkState).
 * @property {Rig} rig
 * @property {number} tick
 * @property {Vec} body            the ground point under the pelvis
 * @property {[number, number]} velocity  smoothed ground velocity (x, z)
 * @property {number} heading
 * @property {[Foot, Foot]} feet   left, right
 * @property {Vec} marker
 * @property {number} behindSince  the tick the body fell behind, -1 on the marker
 * @property {number} behindSpeed
 * @property {Float64Array} rotations  J * 4 local rotations, scalar-last
 * @property {Float64Array} root       the hips' world translation
 * @property {[boolean, boolean]} stance  left, right planted
 */
/**
 * @typedef {object} Gait
 * @property {number} cycle
 * @property {number} stance
 * @property {number} swing
 * @property {boolean} run
 * @property {number} drift
 */
/**
 * @typedef {object} Walk
 * @property {Float64Array} rotations  n * J * 4
 * @property {Float64Array} root       n * 3
 * @property {Uint8Array} stance       n * 2 (left, right; 1 planted)
 * @property {[number, number, number][]} behind  (start s, end s, fastest path speed m/s)
 */

/**
 * @param {ArrayLike<number>} marker
 * @returns {Vec}
 */
function markerOf(marker) {
  if (marker.length !== 3 || ![0, 1, 2].every((i) => Number.isFinite(marker[i]))) {
    throw new Error('marker: must be 3 finite numbers');
  }
  return [+marker[0], +marker[1], +marker[2]];
}

/**
 * The walker standing still at `marker` (x, y, z; y the ground height), facing +z: tick 0.
 * @param {Skeleton} skeleton
 * @param {ArrayLike<number>} marker
 * @returns {WalkState}
 */
export function start(skeleton, marker) {
  const r = rig(skeleton);
  const m = markerOf(marker);
  const feet = /** @type {[Foot, Foot]} */ ([0, 1].map((i) => {
    /** @type {Vec} */
    const a = [m[0] + r.hip[i][0], m[1] + r.ankle, m[2] + r.hip[i][2]];
    return { ankle: a, yaw: 0.0, pitch: 0.0, planted: true, landed: 0, lifted: NEVER, liftAt: a, liftYaw: 0.0,
      liftPitch: 0.0, progress: 0.0, liftHeight: 0.0 };
  }));
  /** @type {WalkState} */
  const state = { rig: r, tick: 0, body: m, velocity: [0.0, 0.0], heading: 0.0, feet, marker: m, behindSince: -1,
    behindSpeed: 0.0, rotations: new Float64Array(r.joints * 4), root: new Float64Array(3), stance: [true, true] };
  return posed(state, 0.0);
}

/**
 * The walker one tick later, the marker there being `marker` (x, y, z).
 * @param {WalkState} state
 * @param {ArrayLike<number>} marker
 * @returns {WalkState}
 */
export function advance(state, marker) {
  const m = markerOf(marker);
  const r = state.rig;
  const tick = state.tick + 1;
  const dt = 1.0 / RATE;
  const bx = state.body[0], bz = state.body[2];
  const dx = m[0] - bx, dz = m[2] - bz;
  const gap = Math.sqrt(dx * dx + dz * dz);
  const most = RV_FASTEST * r.leg * dt;
  let nx, nz;
  if (gap > most) {
    nx = bx + dx * (most / gap);
    nz = bz + dz * (most / gap);
  } else {
    nx = m[0];
    nz = m[2];
  }
  /** @type {Vec} */
  const body = [nx, m[1], nz];
  const px = m[0] - state.marker[0], pz = m[2] - state.marker[2];
  const pathSpeed = Math.sqrt(px * px + pz * pz) * RATE;
  let since, fastest;
  if (gap > most) {
    since = state.behindSince >= 0 ? state.behindSince : tick;
    fastest = state.behindSince >= 0 ? Math.max(state.behindSpeed, pathSpeed) : pathSpeed;
  } else {
    since = -1;
    fastest = 0.0;
  }
  const a = dt / SMOOTHING;
  const vx = state.velocity[0] + a * ((nx - bx) * RATE - state.velocity[0]);
  const vz = state.velocity[1] + a * ((nz - bz) * RATE - state.velocity[1]);
  const speed = Math.sqrt(vx * vx + vz * vz);
  let heading = state.heading;
  let turning = speed <= RV_FACE * r.leg;
  if (speed > RV_FACE * r.leg) {
    const turn = wrap(Math.atan2(vx, vz) - heading);
    const step = TURN_RATE * dt;
    heading = wrap(heading + Math.min(Math.max(turn, -step), step));
    turning = Math.abs(turn) > DRIFT_YAW;
  }
  for (const f of state.feet) turning = turning || (f.planted && Math.abs(wrap(heading - f.yaw)) > DRIFT_YAW);
  const g = gait(speed, r.leg, turning ? RV_TURN * r.leg : 0.0);
  /** @type {WalkState} */
  const moved = { ...state, tick, body, velocity: [vx, vz], heading, marker: m, behindSince: since, behindSpeed: fastest };
  moved.feet = stepFeet(moved, g);
  return posed(moved, speed);
}

/**
 * Boulic's walking cycle at `speed` m/s for legs `leg` m long, timed at least as at `pace`
 * m/s (as walk.py's gait).
 * @param {number} speed
 * @param {number} leg
 * @param {number} [pace]
 * @returns {Gait}
 */
export function gait(speed, leg, pace = 0.0) {
  const slow = RV_SLOW * leg;
  let v = speed > slow ? speed : slow;
  v = pace > v ? pace : v;
  const cycle = CYCLE * Math.sqrt(leg / v);
  let stance, run;
  if (speed > RV_RUN * leg) {
    stance = RUN_CONTACT * leg / v;
    run = true;
  } else {
    stance = 0.752 * cycle - 0.143;
    run = false;
  }
  const drift = speed * stance;
  const least = (speed > RV_FACE * leg ? DRIFT_MIN : DRIFT_SETTLE) * leg;
  return { cycle, stance, swing: cycle - stance, run, drift: drift > least ? drift : least };
}

/**
 * `angle` brought into [-pi, pi).
 * @param {number} angle
 */
function wrap(angle) {
  return angle - 2.0 * Math.PI * Math.floor((angle + Math.PI) / (2.0 * Math.PI));
}

/**
 * Where foot `side` would be centred under its hip, the body `ahead` s on: [x, z].
 * @param {WalkState} state
 * @param {number} side
 * @param {number} ahead
 * @returns {[number, number]}
 */
function restSpot(state, side, ahead) {
  const [hx, , hz] = state.rig.hip[side];
  const s = Math.sin(state.heading), c = Math.cos(state.heading);
  return [state.body[0] + c * hx + s * hz + state.velocity[0] * ahead,
    state.body[2] - s * hx + c * hz + state.velocity[1] * ahead];
}

/**
 * The highest the hips can be with foot `side`'s ankle at `ankle` in reach.
 * @param {WalkState} state
 * @param {number} side
 * @param {Vec} ankle
 */
function reachHeight(state, side, ankle) {
  const r = state.rig;
  const [hx, hy, hz] = r.hip[side];
  const s = Math.sin(state.heading), c = Math.cos(state.heading);
  const dx = state.body[0] + c * hx + s * hz - ankle[0];
  const dz = state.body[2] - s * hx + c * hz - ankle[2];
  const reach = REACH * (r.thigh + r.shin);
  const flat = reach * reach - (dx * dx + dz * dz);
  if (flat <= 0.0) return -Infinity;
  return ankle[1] + Math.sqrt(flat) - hy;
}

/** @param {WalkState} state */
function floorOf(state) {
  return state.body[1] + FLOOR * state.rig.pelvis;
}

/**
 * The feet one tick on (as walk.py's _step_feet).
 * @param {WalkState} state
 * @param {Gait} g
 * @returns {[Foot, Foot]}
 */
function stepFeet(state, g) {
  const feet = [...state.feet];
  const land = g.stance * (0.5 - LAND_SHIFT);
  for (const i of [0, 1]) {
    const f = feet[i];
    if (f.planted) continue;
    const done = f.progress + 1.0 / (RATE * g.swing);
    if (done >= 1.0) {
      const spot = restSpot(state, i, land);
      feet[i] = { ...f, ankle: [spot[0], state.body[1] + state.rig.ankle, spot[1]], yaw: state.heading, pitch: 0.0,
        planted: true, landed: state.tick };
    } else {
      feet[i] = { ...f, progress: done };
    }
  }
  const ratios = [0.0, 0.0];
  const later = [0.0, 0.0];
  for (const i of [0, 1]) {
    const f = feet[i];
    if (f.planted) {
      const spot = restSpot(state, i, land);
      const ex = f.ankle[0] - spot[0], ez = f.ankle[2] - spot[1];
      const yaw = Math.abs(wrap(state.heading - f.yaw)) / DRIFT_YAW;
      let ratio = Math.sqrt(ex * ex + ez * ez) / g.drift;
      ratios[i] = ratio > yaw ? ratio : yaw;
      const fx = ex - state.velocity[0] * g.cycle / 2.0, fz = ez - state.velocity[1] * g.cycle / 2.0;
      ratio = Math.sqrt(fx * fx + fz * fz) / g.drift;
      later[i] = ratio > yaw ? ratio : yaw;
    }
  }
  const order = ratios[1] > ratios[0] ? [1, 0] : [0, 1];
  for (const i of order) {
    const f = feet[i], other = feet[1 - i];
    if (!f.planted) continue;
    const forced = reachHeight(state, i, ankleOf(state.rig, f)) < floorOf(state);
    const wants = (ratios[i] >= 1.0 || (later[1 - i] >= 1.0 && ratios[i] >= ratios[1 - i])) &&
      (state.tick - f.landed) / RATE >= STANCE_MIN;
    const free = ((other.planted || g.run) && (state.tick - other.lifted) / RATE >= g.cycle / 2.0) ||
      (ratios[i] >= OVERDUE && ((other.planted && (state.tick - other.landed) / RATE >= STANCE_MIN) ||
        (g.run && (state.tick - other.lifted) / RATE >= STANCE_MIN)));
    if (forced || (wants && free)) {
      const ankle = ankleOf(state.rig, f);
      feet[i] = { ...f, planted: false, lifted: state.tick, liftAt: ankle, liftYaw: f.yaw, liftPitch: f.pitch,
        progress: 0.0, liftHeight: reachHeight(state, i, ankle) };
    }
  }
  for (const i of [0, 1]) {
    if (!feet[i].planted) feet[i] = swung(state, i, feet[i], g);
  }
  return [feet[0], feet[1]];
}

/**
 * Where `f`'s ankle is: a swinging foot's as it is, a planted one's with its heel risen.
 * @param {Rig} r
 * @param {Foot} f
 * @returns {Vec}
 */
function ankleOf(r, f) {
  if (!f.planted || f.pitch === 0.0) return f.ankle;
  const [, ty, tz] = r.toe;
  const s = Math.sin(f.pitch), c = Math.cos(f.pitch);
  const up = -ty * c + tz * s;
  const back = -tz * c - ty * s;
  return [f.ankle[0] + Math.sin(f.yaw) * (tz + back), f.ankle[1] + ty + up, f.ankle[2] + Math.cos(f.yaw) * (tz + back)];
}

/**
 * How far (rad) planted foot `f`'s heel must rise, pivoting on the toe, for the hip joint
 * at `hip` to reach its ankle (as walk.py's _heel).
 * @param {Rig} r
 * @param {Foot} f
 * @param {Vec} hip
 */
function heel(r, f, hip) {
  const [, ty, tz] = r.toe;
  const s = Math.sin(f.yaw), c = Math.cos(f.yaw);
  const toe = [f.ankle[0] + s * tz, f.ankle[1] + ty, f.ankle[2] + c * tz];
  const wx = hip[0] - toe[0], wy = hip[1] - toe[1], wz = hip[2] - toe[2];
  const wf = wx * s + wz * c;
  if (wf <= 0.0) return 0.0;
  const reach = REACH * (r.thigh + r.shin);
  const rho2 = ty * ty + tz * tz;
  const k = (reach * reach - (wx * wx + wy * wy + wz * wz) - rho2) / (2.0 * Math.sqrt(rho2));
  const a = Math.sqrt(wf * wf + wy * wy);
  if (k >= a) return 0.0;
  const turn = k > -a ? Math.acos(k / a) : Math.PI;
  const pitch = turn - Math.atan2(wy, wf) - Math.atan2(-ty, tz);
  return pitch < 0.0 ? 0.0 : pitch > HEEL_MAX ? HEEL_MAX : pitch;
}

/**
 * The swinging foot this tick (as walk.py's _swung).
 * @param {WalkState} state
 * @param {number} side
 * @param {Foot} f
 * @param {Gait} g
 * @returns {Foot}
 */
function swung(state, side, f, g) {
  const s = f.progress;
  const spot = restSpot(state, side, (1.0 - s) * g.swing + g.stance * (0.5 - LAND_SHIFT));
  const e = s * s * (3.0 - 2.0 * s);
  const [lx, ly, lz] = f.liftAt;
  const y = state.body[1] + state.rig.ankle;
  return { ...f,
    ankle: [lx + (spot[0] - lx) * e, ly + (y - ly) * e + CLEARANCE * state.rig.leg * 4.0 * s * (1.0 - s),
      lz + (spot[1] - lz) * e],
    yaw: f.liftYaw + wrap(state.heading - f.liftYaw) * e,
    pitch: f.liftPitch * (1.0 - e) };
}

/**
 * `state` with its pose (as walk.py's _posed).
 * @param {WalkState} state
 * @param {number} speed
 * @returns {WalkState}
 */
function posed(state, speed) {
  const r = state.rig;
  const b = state.body;
  const s = Math.sin(state.heading), c = Math.cos(state.heading);
  let run = (speed - 0.8 * RV_RUN * r.leg) / (0.4 * RV_RUN * r.leg);
  run = run < 0.0 ? 0.0 : run > 1.0 ? 1.0 : run;
  let top = b[1] + r.pelvis - (1.0 - CROUCH) * (r.thigh + r.shin);
  let sink = 0.0;
  for (const f of state.feet) {
    if (run > 0.0 && f.planted) {
      let u = (state.tick - f.landed) / RATE * speed / (RUN_CONTACT * r.leg);
      u = u < 1.0 ? 4.0 * u * (1.0 - u) : 0.0;
      sink = u > sink ? u : sink;
    }
  }
  top = top - RUN_SINK * r.leg * run * sink;
  let y = top;
  const feet = [...state.feet];
  for (const i of [0, 1]) {
    const f = feet[i];
    if (f.planted) {
      const [hx, hy, hz] = r.hip[i];
      feet[i] = { ...f, pitch: heel(r, f, [b[0] + c * hx + s * hz, top + hy, b[2] - s * hx + c * hz]) };
    }
  }
  const low = floorOf(state);
  for (const i of [0, 1]) {
    const f = feet[i];
    let h;
    if (f.planted) {
      h = reachHeight(state, i, ankleOf(r, f));
    } else {
      let e = 2.0 * f.progress;
      if (e < 1.0) {
        h = f.liftHeight;
        e = e * e * (3.0 - 2.0 * e);
      } else {
        h = reachHeight(state, i, ankleOf(r, f));
        e = 2.0 - e;
        e = e < 0.0 ? 0.0 : e * e * (3.0 - 2.0 * e);
      }
      h = h < low ? low : h;
      h = h > top ? top : h;
      h = h + (top - h) * e;
    }
    h = h < low ? low : h;
    y = h < y ? h : y;
  }
  const q = new Float64Array(r.joints * 4);
  for (let j = 0; j < r.joints; j++) q[j * 4 + 3] = 1.0;
  /** @param {number} j @param {number[]} v */
  const put = (j, v) => { q.set(v, j * 4); };
  const half = 0.5 * state.heading;
  put(r.index[0], [0.0, Math.sin(half), 0.0, Math.cos(half)]);
  /** @type {Frame} */
  const hips = [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]];
  const forward = [0.0, 0.0];
  for (const i of [0, 1]) {
    const f = feet[i];
    const [hx, hy, hz] = r.hip[i];
    /** @type {Vec} */
    const joint = [b[0] + c * hx + s * hz, y + hy, b[2] - s * hx + c * hz];
    // The knee bends toward the foot's forward and the body's (the body's alone if opposite).
    let px = Math.sin(f.yaw) + s, pz = Math.cos(f.yaw) + c;
    if (px * px + pz * pz < 0.01) {
      px = s;
      pz = c;
    }
    const [thigh, shin] = twoBone(joint, ankleOf(r, f), r.thigh, r.shin, [px, 0.0, pz]);
    put(r.index[6 + i], frameQuaternion(localFrame(hips, thigh)));
    put(r.index[8 + i], frameQuaternion(localFrame(thigh, shin)));
    put(r.index[10 + i], frameQuaternion(localFrame(shin, footFrame(f.yaw, f.pitch))));
    forward[i] = (f.ankle[0] - b[0]) * s + (f.ankle[2] - b[2]) * c;
  }
  let lean = LEAN_REST + LEAN_SPEED * speed;
  lean = lean > LEAN_MAX ? LEAN_MAX : lean;
  put(r.index[1], [Math.sin(0.5 * lean), 0.0, 0.0, Math.cos(0.5 * lean)]);
  const elbow = ELBOW_WALK + (ELBOW_RUN - ELBOW_WALK) * run;
  for (const i of [0, 1]) {
    let swing = ARM_SWING * (forward[1 - i] - forward[i]) / r.leg;
    swing = swing > ARM_MAX ? ARM_MAX : swing < -ARM_MAX ? -ARM_MAX : swing;
    put(r.index[2 + i], [-Math.sin(0.5 * swing), 0.0, 0.0, Math.cos(0.5 * swing)]);
    put(r.index[4 + i], [-Math.sin(0.5 * elbow), 0.0, 0.0, Math.cos(0.5 * elbow)]);
  }
  return { ...state, feet: [feet[0], feet[1]], rotations: q, root: new Float64Array([b[0], y, b[2]]),
    stance: [feet[0].planted, feet[1].planted] };
}

/**
 * A foot's world frame: at `yaw`, its heel risen `pitch` (rad).
 * @param {number} yaw
 * @param {number} pitch
 * @returns {Frame}
 */
function footFrame(yaw, pitch) {
  const s = Math.sin(yaw), c = Math.cos(yaw);
  const sp = Math.sin(pitch), cp = Math.cos(pitch);
  return [[c, 0.0, -s], [sp * s, cp, sp * c], [cp * s, -sp, cp * c]];
}

/**
 * The walk of `skeleton` following `markers` (n * 3: the marker at each tick k / RATE).
 * @param {Skeleton} skeleton
 * @param {Float64Array | number[]} markers
 * @returns {Walk}
 */
export function walk(skeleton, markers) {
  const n = Math.floor(markers.length / 3);
  if (n < 1 || markers.length !== n * 3) throw new Error(`markers: must be n * 3 numbers with n >= 1, got ${markers.length}`);
  let state = start(skeleton, markers.slice(0, 3));
  const j = skeleton.names.length;
  const rotations = new Float64Array(n * j * 4);
  const root = new Float64Array(n * 3);
  const stance = new Uint8Array(n * 2);
  /** @type {[number, number, number][]} */
  const behind = [];
  for (let k = 0; k < n; k++) {
    if (k) {
      const previous = state;
      state = advance(state, markers.slice(k * 3, k * 3 + 3));
      if (previous.behindSince >= 0 && state.behindSince < 0) {
        behind.push([previous.behindSince / RATE, (k - 1) / RATE, previous.behindSpeed]);
      }
    }
    rotations.set(state.rotations, k * j * 4);
    root.set(state.root, k * 3);
    stance[k * 2] = state.stance[0] ? 1 : 0;
    stance[k * 2 + 1] = state.stance[1] ? 1 : 0;
  }
  if (state.behindSince >= 0) behind.push([state.behindSince / RATE, (n - 1) / RATE, state.behindSpeed]);
  return { rotations, root, stance, behind };
}

/**
 * Forward kinematics for tests and drawing: each joint's world position (n * J * 3) from
 * local rotations (n * J * 4, scalar-last) and the root's translation (n * 3), the other
 * joints at their offsets (as kinematics.world_pose with the offsets as translations).
 * @param {Skeleton} skeleton
 * @param {Float64Array} rotations
 * @param {Float64Array} root
 * @returns {Float64Array}
 */
export function worldPoints(skeleton, rotations, root) {
  const j = skeleton.names.length;
  const n = root.length / 3;
  const out = new Float64Array(n * j * 3);
  const world = new Float64Array(j * 4);
  for (let k = 0; k < n; k++) {
    for (let i = 0; i < j; i++) {
      const p = skeleton.parents[i];
      const r = k * j * 4 + i * 4;
      const lx = rotations[r], ly = rotations[r + 1], lz = rotations[r + 2], lw = rotations[r + 3];
      const o = k * j * 3 + i * 3;
      if (p < 0) {
        world.set([lx, ly, lz, lw], i * 4);
        out[o] = root[k * 3]; out[o + 1] = root[k * 3 + 1]; out[o + 2] = root[k * 3 + 2];
        continue;
      }
      const px = world[p * 4], py = world[p * 4 + 1], pz = world[p * 4 + 2], pw = world[p * 4 + 3];
      world[i * 4] = pw * lx + px * lw + py * lz - pz * ly;
      world[i * 4 + 1] = pw * ly - px * lz + py * lw + pz * lx;
      world[i * 4 + 2] = pw * lz + px * ly - py * lx + pz * lw;
      world[i * 4 + 3] = pw * lw - px * lx - py * ly - pz * lz;
      const [vx, vy, vz] = skeleton.offsets[i];
      // v + 2 w (u x v) + 2 u x (u x v), u the parent's vector part
      const tx = 2.0 * (py * vz - pz * vy), ty = 2.0 * (pz * vx - px * vz), tz = 2.0 * (px * vy - py * vx);
      const q = k * j * 3 + p * 3;
      out[o] = out[q] + vx + pw * tx + (py * tz - pz * ty);
      out[o + 1] = out[q + 1] + vy + pw * ty + (pz * tx - px * tz);
      out[o + 2] = out[q + 2] + vz + pw * tz + (px * ty - py * tx);
    }
  }
  return out;
}
