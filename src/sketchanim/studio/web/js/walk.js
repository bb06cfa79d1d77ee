// @ts-check
/**
 * A humanoid walking along a performed ground path: the page's copy of
 * src/sketchanim/motion/walk.py, operation for operation (so the two agree to 1e-6 rad;
 * tests/motion/test_walk.py runs tests/studio/js/walk_path.mjs to check it). The walker's
 * goal is a ground marker (its y the ground height under it); the figure faces along the
 * path, its step length and cadence following the path's speed (Boulic's relative cycle
 * length 1.346 sqrt(v / H)), its feet planted during stance and stepping when a foot drifts
 * past a threshold, one leg at a time, running above the walk-run speed, falling behind
 * the marker beyond the fastest run. docs/walker.md describes the model.
 *
 * A deterministic simulation at RATE ticks a second from the start of the animation:
 * `start` stands the figure at the first marker (tick 0), `advance` steps it one tick, so
 * the pose is a pure function of the marker's curve; `walk` is `advance` in a loop. Pure:
 * no three.js. Conventions: y up, heading 0 faces +z (heading a faces (sin a, 0, cos a)),
 * the left side on +x; rotations local, scalar-last quaternions, world = parent * local,
 * a joint's local transform T(offset) R(rotation).
 */

/** Ticks a second. (The IK module will define the same constant; one will go.) */
export const RATE = 120.0;

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
/** A walking foot drifted this far past its threshold lifts once the other is planted STANCE_MIN. */
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

/** The humanoid's joints, parents before children. */
export const JOINTS = ['hips', 'spine', 'chest', 'neck', 'head',
  'l_shoulder', 'l_upper_arm', 'l_forearm', 'l_hand',
  'r_shoulder', 'r_upper_arm', 'r_forearm', 'r_hand',
  'l_thigh', 'l_shin', 'l_foot', 'l_toe',
  'r_thigh', 'r_shin', 'r_foot', 'r_toe'];
const PARENTS = ['', 'hips', 'spine', 'chest', 'neck',
  'chest', 'l_shoulder', 'l_upper_arm', 'l_forearm',
  'chest', 'r_shoulder', 'r_upper_arm', 'r_forearm',
  'hips', 'l_thigh', 'l_shin', 'l_foot',
  'hips', 'r_thigh', 'r_shin', 'r_foot'];
/** @type {Record<string, Vec>} rest offsets as fractions of the height (left side) */
const OFFSETS = {
  hips: [0, 0.56, 0], spine: [0, 0.06, 0], chest: [0, 0.12, 0], neck: [0, 0.12, 0],
  head: [0, 0.05, 0], l_shoulder: [0.02, 0.09, 0], l_upper_arm: [0.1, 0, 0],
  l_forearm: [0, -0.17, 0], l_hand: [0, -0.15, 0], l_thigh: [0.055, -0.03, 0],
  l_shin: [0, -0.245, 0], l_foot: [0, -0.245, 0], l_toe: [0, -0.04, 0.11],
};

/** @typedef {[number, number, number]} Vec */
/** @typedef {[Vec, Vec, Vec]} Frame  a rotation's columns (its x, y, z axes) */
/**
 * @typedef {object} Skeleton
 * @property {string[]} names
 * @property {number[]} parents   -1 for the root
 * @property {Vec[]} offsets      each joint's rest translation from its parent, [x, y, z]
 */
/**
 * @typedef {object} Rig  What the walk needs of a humanoid skeleton, metres.
 * @property {number} joints
 * @property {number[]} index  hips, spine, l/r upper arm, l/r forearm, l/r thigh, l/r shin, l/r foot
 * @property {[Vec, Vec]} hip  each thigh joint's offset from the hips
 * @property {number} thigh
 * @property {number} shin
 * @property {Vec} toe         the toe's offset from the ankle
 * @property {number} ankle    ankle height above the ground, foot flat
 * @property {number} leg      H: hip joint height above the ground at rest
 * @property {number} pelvis   the hips' rest height above the ground
 */
/**
 * @typedef {object} Foot  Its ankle were the foot flat, yaw, heel pitch; planted since tick
 *   `landed`, or swinging since tick `lifted` from `liftAt` / `liftYaw` / `liftPitch`, the
 *   hips then held down to `liftHeight` by its reach.
 * @property {Vec} ankle
 * @property {number} yaw
 * @property {number} pitch
 * @property {boolean} planted
 * @property {number} landed
 * @property {number} lifted
 * @property {Vec} liftAt
 * @property {number} liftYaw
 * @property {number} liftPitch
 * @property {number} swing
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
 * A humanoid of `height` metres (as walk.py's humanoid): offsets are [x, y, z] per joint.
 * @param {number} [height]
 * @returns {Skeleton}
 *
 * @example
 * humanoid(1.75).names.length;   // 21
 */
export function humanoid(height = 1.75) {
  if (!(Number.isFinite(height) && height >= 0.2 && height <= 5.0)) throw new Error(`height: must be 0.2 to 5 m, got ${height}`);
  const offsets = JOINTS.map((name) => {
    const right = name.startsWith('r_');
    const [x, y, z] = OFFSETS[right ? `l_${name.slice(2)}` : name];
    return /** @type {Vec} */ ([(right ? -x : x) * height, y * height, z * height]);
  });
  return { names: [...JOINTS], parents: PARENTS.map((p) => (p ? JOINTS.indexOf(p) : -1)), offsets };
}

/**
 * @param {Skeleton} skeleton
 * @param {string} name
 */
function indexOf(skeleton, name) {
  const i = skeleton.names.indexOf(name);
  if (i < 0) throw new Error(`joint: no joint named '${name}'`);
  return i;
}

/**
 * The walk's view of `skeleton` (humanoid's joint names, shins and ankles straight down).
 * @param {Skeleton} skeleton
 * @returns {Rig}
 */
export function rig(skeleton) {
  const names = ['hips', 'spine', 'l_upper_arm', 'r_upper_arm', 'l_forearm', 'r_forearm',
    'l_thigh', 'r_thigh', 'l_shin', 'r_shin', 'l_foot', 'r_foot'];
  const index = names.map((n) => indexOf(skeleton, n));
  const o = skeleton.offsets;
  for (const n of ['l_shin', 'r_shin', 'l_foot', 'r_foot']) {
    const [x, y, z] = o[indexOf(skeleton, n)];
    if (x !== 0 || z !== 0 || !(y < 0)) throw new Error(`skeleton: joint '${n}' must be straight below its parent at rest`);
  }
  const lt = o[indexOf(skeleton, 'l_toe')], rt = o[indexOf(skeleton, 'r_toe')];
  if (-lt[0] !== rt[0] || lt[1] !== rt[1] || lt[2] !== rt[2] || lt[1] >= 0) {
    throw new Error('skeleton: the toes must mirror each other, below the ankles');
  }
  const rest = restPositions(skeleton);
  const ground = rest[indexOf(skeleton, 'l_toe')][1];
  return {
    joints: skeleton.names.length, index,
    hip: [[...o[index[6]]], [...o[index[7]]]],
    thigh: -o[index[8]][1], shin: -o[index[10]][1], toe: [...lt],
    ankle: -lt[1], leg: rest[index[6]][1] - ground, pelvis: rest[index[0]][1] - ground,
  };
}

/**
 * World positions with every rotation the identity.
 * @param {Skeleton} skeleton
 * @returns {Vec[]}
 */
function restPositions(skeleton) {
  /** @type {Vec[]} */
  const out = [];
  skeleton.parents.forEach((p, j) => {
    const o = skeleton.offsets[j];
    out.push(p >= 0 ? [o[0] + out[p][0], o[1] + out[p][1], o[2] + out[p][2]] : [o[0] + 0.0, o[1] + 0.0, o[2] + 0.0]);
  });
  return out;
}

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
      liftPitch: 0.0, swing: 0.0, liftHeight: 0.0 };
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
    if (!f.planted && (state.tick - f.lifted) / RATE >= f.swing) {
      const spot = restSpot(state, i, land);
      feet[i] = { ...f, ankle: [spot[0], state.body[1] + state.rig.ankle, spot[1]], yaw: state.heading, pitch: 0.0,
        planted: true, landed: state.tick };
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
      (other.planted && ratios[i] >= OVERDUE && (state.tick - other.landed) / RATE >= STANCE_MIN);
    if (forced || (wants && free)) {
      const ankle = ankleOf(state.rig, f);
      feet[i] = { ...f, planted: false, lifted: state.tick, liftAt: ankle, liftYaw: f.yaw, liftPitch: f.pitch,
        swing: g.swing, liftHeight: reachHeight(state, i, ankle) };
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
  const gone = (state.tick - f.lifted) / RATE;
  let s = gone / f.swing;
  s = s > 1.0 ? 1.0 : s;
  let left = f.swing - gone;
  left = left < 0.0 ? 0.0 : left;
  const spot = restSpot(state, side, left + g.stance * (0.5 - LAND_SHIFT));
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
  const top = b[1] + r.pelvis - (1.0 - CROUCH) * (r.thigh + r.shin);
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
      let e = 2.0 * (state.tick - f.lifted) / RATE / f.swing;
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
    const [thigh, shin, foot] = leg(r, joint, ankleOf(r, f), f.yaw, f.pitch, state.heading);
    put(r.index[6 + i], quat(local(hips, thigh)));
    put(r.index[8 + i], quat(local(thigh, shin)));
    put(r.index[10 + i], quat(local(shin, foot)));
    forward[i] = (f.ankle[0] - b[0]) * s + (f.ankle[2] - b[2]) * c;
  }
  let lean = LEAN_REST + LEAN_SPEED * speed;
  lean = lean > LEAN_MAX ? LEAN_MAX : lean;
  put(r.index[1], [Math.sin(0.5 * lean), 0.0, 0.0, Math.cos(0.5 * lean)]);
  let run = (speed - 0.8 * RV_RUN * r.leg) / (0.4 * RV_RUN * r.leg);
  run = run < 0.0 ? 0.0 : run > 1.0 ? 1.0 : run;
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
 * Two-bone analytic IK: the world frames of the thigh, the shin and the foot (as walk.py's _leg).
 * @param {Rig} r
 * @param {Vec} hip
 * @param {Vec} ankle
 * @param {number} yaw
 * @param {number} pitch
 * @param {number} heading
 * @returns {[Frame, Frame, Frame]}
 */
function leg(r, hip, ankle, yaw, pitch, heading) {
  const dx = ankle[0] - hip[0], dy = ankle[1] - hip[1], dz = ankle[2] - hip[2];
  let d = Math.sqrt(dx * dx + dy * dy + dz * dz);
  const l1 = r.thigh, l2 = r.shin;
  const longest = (l1 + l2) * (1.0 - 1e-9);
  const shortest = Math.abs(l1 - l2) + 1e-6 * (l1 + l2);
  let ux, uy, uz;
  if (d > 1e-12) {
    ux = dx / d; uy = dy / d; uz = dz / d;
  } else {
    ux = 0.0; uy = -1.0; uz = 0.0;
  }
  d = d > longest ? longest : d < shortest ? shortest : d;
  let px = Math.sin(yaw) + Math.sin(heading), pz = Math.cos(yaw) + Math.cos(heading);
  if (px * px + pz * pz < 0.01) {
    px = Math.sin(heading);
    pz = Math.cos(heading);
  }
  const along = px * ux + pz * uz;
  let nx = px - along * ux, ny = -along * uy, nz = pz - along * uz;
  let n = Math.sqrt(nx * nx + ny * ny + nz * nz);
  if (n < 1e-9) {
    nx = 0.0; ny = 1.0; nz = 0.0; n = 1.0;
  }
  nx = nx / n; ny = ny / n; nz = nz / n;
  const c1 = (l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d);
  const c2 = (l2 * l2 + d * d - l1 * l1) / (2.0 * l2 * d);
  const s1 = Math.sqrt(Math.max(0.0, 1.0 - c1 * c1));
  const s2 = Math.sqrt(Math.max(0.0, 1.0 - c2 * c2));
  const thigh = bone([ux * c1 + nx * s1, uy * c1 + ny * s1, uz * c1 + nz * s1],
    [nx * c1 - ux * s1, ny * c1 - uy * s1, nz * c1 - uz * s1]);
  const shin = bone([ux * c2 - nx * s2, uy * c2 - ny * s2, uz * c2 - nz * s2],
    [nx * c2 + ux * s2, ny * c2 + uy * s2, nz * c2 + uz * s2]);
  const s = Math.sin(yaw), c = Math.cos(yaw);
  const sp = Math.sin(pitch), cp = Math.cos(pitch);
  return [thigh, shin, [[c, 0.0, -s], [sp * s, cp, sp * c], [cp * s, -sp, cp * c]]];
}

/**
 * The frame of a bone along `down` (its rest -y) with its rest +z on `front`.
 * @param {Vec} down
 * @param {Vec} front
 * @returns {Frame}
 */
function bone(down, front) {
  /** @type {Vec} */
  const y = [-down[0], -down[1], -down[2]];
  const z = front;
  return [[y[1] * z[2] - y[2] * z[1], y[2] * z[0] - y[0] * z[2], y[0] * z[1] - y[1] * z[0]], y, z];
}

/**
 * The child's frame in the parent's: columns parent^T child.
 * @param {Frame} parent
 * @param {Frame} child
 * @returns {Frame}
 */
function local(parent, child) {
  /** @param {number} j @returns {Vec} */
  const col = (j) => /** @type {Vec} */ ([0, 1, 2].map((i) => parent[i][0] * child[j][0] + parent[i][1] * child[j][1] +
    parent[i][2] * child[j][2]));
  return [col(0), col(1), col(2)];
}

/**
 * The unit quaternion [x, y, z, w], w >= 0, of the rotation with columns `m`.
 * @param {Frame} m
 * @returns {number[]}
 */
function quat(m) {
  const [m00, m10, m20] = m[0];
  const [m01, m11, m21] = m[1];
  const [m02, m12, m22] = m[2];
  const tr = m00 + m11 + m22;
  let w, x, y, z, k;
  if (tr > 0.0) {
    k = Math.sqrt(tr + 1.0) * 2.0;
    w = 0.25 * k; x = (m21 - m12) / k; y = (m02 - m20) / k; z = (m10 - m01) / k;
  } else if (m00 > m11 && m00 > m22) {
    k = Math.sqrt(1.0 + m00 - m11 - m22) * 2.0;
    w = (m21 - m12) / k; x = 0.25 * k; y = (m01 + m10) / k; z = (m02 + m20) / k;
  } else if (m11 > m22) {
    k = Math.sqrt(1.0 + m11 - m00 - m22) * 2.0;
    w = (m02 - m20) / k; x = (m01 + m10) / k; y = 0.25 * k; z = (m12 + m21) / k;
  } else {
    k = Math.sqrt(1.0 + m22 - m00 - m11) * 2.0;
    w = (m10 - m01) / k; x = (m02 + m20) / k; y = (m12 + m21) / k; z = 0.25 * k;
  }
  let n = Math.sqrt(x * x + y * y + z * z + w * w);
  if (w < 0.0) n = -n;
  return [x / n, y / n, z / n, w / n];
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
