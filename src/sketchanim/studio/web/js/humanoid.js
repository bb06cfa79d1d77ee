// @ts-check
/**
 * The walker's figure: a humanoid skeleton generated in code, in a human's proportions,
 * and the measures of it the walk uses (`rig`). The page's copy of
 * src/sketchanim/motion/humanoid.py, operation for operation. It stands on y = 0 facing
 * +z, its left side on +x; offsets are [x, y, z] per joint.
 */

/** @typedef {[number, number, number]} Vec */
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

/**
 * A humanoid of `height` metres (as humanoid.py's humanoid): offsets are [x, y, z] per joint.
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
