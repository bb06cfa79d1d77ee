// @ts-check
/**
 * Articulated-chain inverse kinematics in the page: a port of motion/ik.py, operation for
 * operation (the same floating-point operations in the same order, no library trigonometry),
 * so the page's pose of a chain agrees with the model's to the bit (tests/motion/test_ik.py
 * runs both on random chains and goal paths and asks for 1e-6 rad).
 *
 * A chain's frame: its base at the origin; at rest (every local rotation identity) it points
 * straight up +y; joint i sits at the start of segment i, its segment along its local +y;
 * a hinge turns about its local x axis only, a ball freely; a joint's limit is the most its
 * rotation angle may be. Poses are J local rotations, quaternions (x, y, z, w), end to end.
 *
 * The pose is simulated at RATE ticks per second from the start pose (`rest`): each tick
 * (`step`) runs damped least squares on the 3 x m position Jacobian, the damping of each
 * singular direction from its singular value (Maciejewski), with a bias toward the rest pose
 * in the null space, joints held at their limits and the limits clamped after every update,
 * the error clamped per iteration (Buss) and the tick's target at most the goal's own step
 * plus a catch-up speed from the effector (docs/rigs.md says why each, and what is promised).
 */

/** Ticks per second of every derived pose. */
export const RATE = 120;

/** Iterations of damped least squares per tick. */
const ITERATIONS = 3;
/** Jacobi sweeps over the 3 x 3 J J^T (4 are machine precision for a 3 x 3). */
const SWEEPS = 4;
/** An off-diagonal entry this small against its diagonal ones is not rotated away. */
const NEGLIGIBLE = 1e-18;
/** The rest pose's bend (radians) shared by the joints after the base: never straight. */
const CURL = 0.2;
/** How fast (reaches per second) the effector may move beyond the goal's own step. */
const CATCH_UP = 2;
/** The error clamp per iteration, in reaches. */
const STEP = 0.1;
/** The most a joint turns per iteration (radians). */
const MAX_TURN = 0.1;
/** Singular values below this (in reaches) are damped. */
const EPS = 0.05;
/** The damping at a zero singular value (in reaches). */
const DAMPING = 0.05;
/** The rest bias's gain per iteration. */
const BIAS = 0.05;
/** Goals from 1 to 1 + BAND reaches out turn the rest bias from the rest bend to straight. */
const BAND = 0.05;
/** The share of the damping the bias's projection keeps while the goal is in reach. */
const PROJECTED = 1e-4;
/** Bisection steps pulling a tick back that would move the effector beyond its allowance. */
const BACKOFF = 12;

/**
 * @typedef {object} Chain
 * @property {number[]} lengths  Segment lengths (2..8, each > 0).
 * @property {number[]} limits   Each joint's largest rotation angle, radians in (0, pi].
 * @property {boolean[]} hinges  Hinge (about local x) or ball, per joint.
 */

/**
 * @typedef {object} Prepared  A chain's constants, computed once per solve.
 * @property {number} n
 * @property {Float64Array} lengths
 * @property {Uint8Array} hinge
 * @property {Float64Array} cosLim  cos(limit / 2): the least |w| within the limit.
 * @property {Float64Array} sinLim  sin(limit / 2).
 * @property {Float64Array} restX   The rest pose's x component (a bend about x).
 * @property {Float64Array} restW
 * @property {number} reach
 * @property {Float64Array} pos     Scratch: joint positions ((n + 1) * 3).
 * @property {Float64Array} world   Scratch: world rotations (n * 4).
 * @property {Float64Array} turn    Scratch: each joint's update (n * 3).
 * @property {Float64Array} bias    Scratch: each joint's rest bias (n * 3, world).
 * @property {Float64Array} cols    Scratch: a hinge's Jacobian column, a ball's lever r = E - P (n * 3).
 * @property {Float64Array} a       Scratch: J J^T (3 x 3).
 * @property {Float64Array} v       Scratch: its eigenvectors (columns).
 * @property {Float64Array} back    Scratch: a pose pulled back.
 * @property {Float64Array} trial   Scratch: a pose updated, before the limits.
 * @property {Uint8Array} skip      Scratch: the joints an iteration holds at their limit.
 * @property {Float64Array} local   Scratch: a turn in a parent's frame.
 */

/**
 * A chain from the scene's encoding (anim/scene.py KINDS.chain): 8 slots each; the chain is
 * the leading slots of positive length (2 to 8); limits in degrees; a hinge where > 0.5.
 * @param {ArrayLike<number>} lengths
 * @param {ArrayLike<number>} limits  Degrees.
 * @param {ArrayLike<number>} hinges  1 hinge, 0 ball.
 * @returns {Chain}
 */
export function chainFromSlots(lengths, limits, hinges) {
  const slots = lengths.length;
  if (limits.length !== slots || hinges.length !== slots) {
    throw new Error(`limits, hinges: need ${slots} slots as lengths has, got ${limits.length} and ${hinges.length}`);
  }
  for (const [name, values] of /** @type {[string, ArrayLike<number>][]} */ ([['lengths', lengths], ['limits', limits], ['hinges', hinges]])) {
    for (let i = 0; i < slots; i++) {
      if (!Number.isFinite(values[i]) || values[i] < 0) throw new Error(`${name}: slot ${i} is ${values[i]}, not a finite number >= 0`);
    }
  }
  let n = 0;
  while (n < slots && lengths[n] > 0) n++;
  if (n < 2 || n > 8) throw new Error(`lengths: a chain is 2 to 8 leading positive lengths, got ${n}`);
  const out = { lengths: /** @type {number[]} */ ([]), limits: /** @type {number[]} */ ([]), hinges: /** @type {boolean[]} */ ([]) };
  for (let i = 0; i < n; i++) {
    if (!(limits[i] > 0 && limits[i] <= 180)) throw new Error(`limits: joint ${i} is ${limits[i]} degrees, not in (0, 180]`);
    out.lengths.push(lengths[i]);
    out.limits.push(limits[i] * Math.PI / 180);
    out.hinges.push(hinges[i] > 0.5);
  }
  return out;
}

/**
 * A chain's constants and scratch space.
 * @param {Chain} chain
 * @returns {Prepared}
 */
function prepare(chain) {
  const n = chain.lengths.length;
  if (n < 2 || n > 8 || chain.limits.length !== n || chain.hinges.length !== n) {
    throw new Error(`chain: 2 to 8 joints with a limit and a hinge flag each, got ${n}, ${chain.limits.length}, ${chain.hinges.length}`);
  }
  const p = {
    n, lengths: new Float64Array(chain.lengths), hinge: new Uint8Array(n), cosLim: new Float64Array(n),
    sinLim: new Float64Array(n), restX: new Float64Array(n), restW: new Float64Array(n), reach: 0,
    pos: new Float64Array((n + 1) * 3), world: new Float64Array(n * 4), turn: new Float64Array(n * 3),
    bias: new Float64Array(n * 3), cols: new Float64Array(n * 3), a: new Float64Array(9), v: new Float64Array(9),
    back: new Float64Array(n * 4), trial: new Float64Array(n * 4), skip: new Uint8Array(n), local: new Float64Array(3),
  };
  for (let i = 0; i < n; i++) {
    const limit = chain.limits[i];
    if (!(chain.lengths[i] > 0) || !(limit > 0 && limit <= Math.PI)) {
      throw new Error(`chain: joint ${i} has length ${chain.lengths[i]} and limit ${limit}, need > 0 and (0, pi]`);
    }
    p.hinge[i] = chain.hinges[i] ? 1 : 0;
    [p.cosLim[i], p.sinLim[i]] = halfTurn(limit);
    // The rest bend as an update turns a joint (below): by 2 atan(bend / 2), nearly bend.
    const h = 0.5 * (i === 0 ? 0 : Math.min(CURL / (n - 1), 0.5 * limit));
    const hn = Math.sqrt(h * h + 1);
    p.restX[i] = h / hn;
    p.restW[i] = 1 / hn;
    p.reach += chain.lengths[i];
  }
  return p;
}

/**
 * cos and sin of half an angle in [0, pi], by their Taylor series to 1e-16 (arithmetic alone,
 * so that the page and the model, whose libraries' cos may differ in the last bit, agree to
 * the bit: a chain at a bifurcation, folding toward a goal behind it, would amplify that bit).
 * @param {number} angle
 * @returns {[number, number]}
 */
function halfTurn(angle) {
  const x = 0.5 * angle, x2 = x * x;
  let c = 1, s = x, tc = 1, ts = x;
  for (let k = 1; k <= 12; k++) {
    tc = -tc * x2 / ((2 * k - 1) * (2 * k));
    ts = -ts * x2 / ((2 * k) * (2 * k + 1));
    c += tc;
    s += ts;
  }
  return [c, s];
}

/**
 * The start pose: a slight bend about x at each joint after the base (about 0.2 rad in all, at most
 * half a joint's limit), so that the chain is never straight at rest, where the Jacobian is
 * singular along the chain; the rest bias relaxes toward it.
 * @param {Chain} chain
 * @returns {Float64Array} n * 4 local rotations (x, y, z, w).
 */
export function rest(chain) {
  const p = prepare(chain);
  const q = new Float64Array(p.n * 4);
  for (let i = 0; i < p.n; i++) {
    q[4 * i] = p.restX[i];
    q[4 * i + 3] = p.restW[i];
  }
  return q;
}

/**
 * Forward kinematics into p.pos (base, joints, effector) and p.world (world rotations).
 * @param {Prepared} p
 * @param {Float64Array} q
 */
function forward(p, q) {
  const pos = p.pos, world = p.world;
  let wx = 0, wy = 0, wz = 0, ww = 1;
  pos[0] = 0; pos[1] = 0; pos[2] = 0;
  for (let i = 0; i < p.n; i++) {
    const lx = q[4 * i], ly = q[4 * i + 1], lz = q[4 * i + 2], lw = q[4 * i + 3];
    const nx = ww * lx + wx * lw + wy * lz - wz * ly;
    const ny = ww * ly - wx * lz + wy * lw + wz * lx;
    const nz = ww * lz + wx * ly - wy * lx + wz * lw;
    const nw = ww * lw - wx * lx - wy * ly - wz * lz;
    wx = nx; wy = ny; wz = nz; ww = nw;
    world[4 * i] = wx; world[4 * i + 1] = wy; world[4 * i + 2] = wz; world[4 * i + 3] = ww;
    const len = p.lengths[i];
    // The segment (0, len, 0) rotated: the second column of the rotation matrix.
    pos[3 * i + 3] = pos[3 * i] + len * (2 * (wx * wy - ww * wz));
    pos[3 * i + 4] = pos[3 * i + 1] + len * (1 - 2 * (wx * wx + wz * wz));
    pos[3 * i + 5] = pos[3 * i + 2] + len * (2 * (wy * wz + ww * wx));
  }
}

/**
 * Rotate (x, y, z) by the quaternion at q[k..k+3] (inverse: by its conjugate) into out[o..o+2].
 * @param {Float64Array} q
 * @param {number} k
 * @param {boolean} inverse
 * @param {number} x
 * @param {number} y
 * @param {number} z
 * @param {Float64Array} out
 * @param {number} o
 */
function rotate(q, k, inverse, x, y, z, out, o) {
  const s = inverse ? -1 : 1;
  const ux = s * q[k], uy = s * q[k + 1], uz = s * q[k + 2], w = q[k + 3];
  const cx = uy * z - uz * y, cy = uz * x - ux * z, cz = ux * y - uy * x;
  out[o] = x + 2 * (w * cx + (uy * cz - uz * cy));
  out[o + 1] = y + 2 * (w * cy + (uz * cx - ux * cz));
  out[o + 2] = z + 2 * (w * cz + (ux * cy - uy * cx));
}

/**
 * The eigen-decomposition of the symmetric 3 x 3 p.a by cyclic Jacobi (SWEEPS sweeps):
 * eigenvalues on p.a's diagonal, eigenvectors the columns of p.v.
 * @param {Prepared} p
 */
function jacobi(p) {
  const a = p.a, v = p.v;
  v.fill(0);
  v[0] = 1; v[4] = 1; v[8] = 1;
  for (let sweep = 0; sweep < SWEEPS; sweep++) {
    for (let pair = 0; pair < 3; pair++) {
      const i = pair === 2 ? 1 : 0, j = pair === 0 ? 1 : 2, r = 3 - i - j;
      const aij = a[3 * i + j];
      // Negligible already (the same test in the model): the rotation would change nothing.
      if (Math.abs(aij) <= NEGLIGIBLE * (Math.abs(a[3 * i + i]) + Math.abs(a[3 * j + j]))) continue;
      const theta = (a[3 * j + j] - a[3 * i + i]) / (2 * aij);
      let t = 1 / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
      if (theta < 0) t = -t;
      const c = 1 / Math.sqrt(t * t + 1), s = t * c;
      a[3 * i + i] -= t * aij;
      a[3 * j + j] += t * aij;
      a[3 * i + j] = 0; a[3 * j + i] = 0;
      const ari = a[3 * r + i], arj = a[3 * r + j];
      a[3 * r + i] = c * ari - s * arj; a[3 * i + r] = a[3 * r + i];
      a[3 * r + j] = s * ari + c * arj; a[3 * j + r] = a[3 * r + j];
      for (let k = 0; k < 3; k++) {
        const vki = v[3 * k + i], vkj = v[3 * k + j];
        v[3 * k + i] = c * vki - s * vkj;
        v[3 * k + j] = s * vki + c * vkj;
      }
    }
  }
}

/**
 * Hold joint i of q within its limit: a rotation angle past it is brought back to it about
 * the same axis (a hinge's x component keeps its sign). Joints start each tick with w >= 0
 * (rotation angles up to pi), so a w pushed below cos(limit / 2), even below 0 (an update that
 * carried a limit near pi past pi), is brought back on the side the joint came from.
 * @param {Prepared} p
 * @param {Float64Array} q
 * @param {number} i
 */
function clampJoint(p, q, i) {
  const k = 4 * i;
  const w = q[k + 3];
  const c = p.cosLim[i];
  if (w >= c) return;
  const x = q[k], y = q[k + 1], z = q[k + 2];
  const f = p.sinLim[i] / Math.sqrt(x * x + y * y + z * z);
  q[k] = x * f; q[k + 1] = y * f; q[k + 2] = z * f;
  q[k + 3] = c;
}

/**
 * The damped least-squares update of every joint not skipped (p.turn: a hinge's angle, a
 * ball's world rotation vector; skipped joints their bias alone), for the error (dx, dy, dz), with p.cols,
 * p.bias and p.lever as `iterate` left them. Returns the factor that holds every joint's
 * turn to MAX_TURN.
 * @param {Prepared} p
 * @param {number} dx
 * @param {number} dy
 * @param {number} dz
 * @param {Uint8Array} skip
 * @param {number} keep  As `iterate`'s.
 * @returns {number}
 */
function dls(p, dx, dy, dz, skip, keep) {
  const n = p.n, bias = p.bias, cols = p.cols, turn = p.turn, a = p.a, reach = p.reach;
  a.fill(0);
  let jx = 0, jy = 0, jz = 0;          // J z: the rest bias's effector motion
  for (let i = 0; i < n; i++) {
    const cx = cols[3 * i], cy = cols[3 * i + 1], cz = cols[3 * i + 2];
    const bx = bias[3 * i], by = bias[3 * i + 1], bz = bias[3 * i + 2];
    if (p.hinge[i]) {
      if (!skip[i]) {
        a[0] += cx * cx; a[1] += cx * cy; a[2] += cx * cz;
        a[4] += cy * cy; a[5] += cy * cz; a[8] += cz * cz;
      }
      jx += bx * cx; jy += bx * cy; jz += bx * cz;
    } else {
      if (!skip[i]) {
        // Its three world-axis columns w x r (r = cols) give |r|^2 I - r r^T.
        const rr = cx * cx + cy * cy + cz * cz;
        a[0] += rr - cx * cx; a[1] -= cx * cy; a[2] -= cx * cz;
        a[4] += rr - cy * cy; a[5] -= cy * cz; a[8] += rr - cz * cz;
      }
      jx += by * cz - bz * cy; jy += bz * cx - bx * cz; jz += bx * cy - by * cx;
    }
  }
  a[3] = a[1]; a[6] = a[2]; a[7] = a[5];
  jacobi(p);
  const v = p.v;
  const eps2 = EPS * reach * EPS * reach, damp2 = DAMPING * reach * DAMPING * reach;
  // The bias's own motion is taken out with less damping (PROJECTED of it) while the goal is
  // in reach, so that it does not pull a reachable goal's effector off it; with all of it
  // beyond, so that the bias straightens a chain the error alone barely can (it is singular).
  const projected = PROJECTED + (1 - PROJECTED) * (1 - keep);
  let yx = 0, yy = 0, yz = 0;
  for (let m = 0; m < 3; m++) {
    const s = Math.max(a[4 * m], 0);
    const lambda2 = s < eps2 ? damp2 * (1 - s / eps2) : 0;
    const ux = v[m], uy = v[3 + m], uz = v[6 + m];
    const g = (ux * dx + uy * dy + uz * dz) / (s + lambda2) - (ux * jx + uy * jy + uz * jz) / (s + projected * lambda2);
    yx += g * ux; yy += g * uy; yz += g * uz;
  }
  let most = 0;
  for (let i = 0; i < n; i++) {
    const cx = cols[3 * i], cy = cols[3 * i + 1], cz = cols[3 * i + 2];
    if (skip[i]) {
      // A joint held at its limit still relaxes by its bias (toward rest: inward), the
      // others making up for its motion.
      const bx = bias[3 * i], by = bias[3 * i + 1], bz = bias[3 * i + 2];
      turn[3 * i] = bx; turn[3 * i + 1] = by; turn[3 * i + 2] = bz;
      most = Math.max(most, Math.sqrt(bx * bx + by * by + bz * bz));
    } else if (p.hinge[i]) {
      const d = bias[3 * i] + (cx * yx + cy * yy + cz * yz);
      turn[3 * i] = d;
      most = Math.max(most, Math.abs(d));
    } else {
      // J^T y for a ball: r x y.
      const ox = bias[3 * i] + (cy * yz - cz * yy);
      const oy = bias[3 * i + 1] + (cz * yx - cx * yz);
      const oz = bias[3 * i + 2] + (cx * yy - cy * yx);
      turn[3 * i] = ox; turn[3 * i + 1] = oy; turn[3 * i + 2] = oz;
      most = Math.max(most, Math.sqrt(ox * ox + oy * oy + oz * oz));
    }
  }
  return most > MAX_TURN ? MAX_TURN / most : 1;
}

/**
 * Joint i of q turned by scale * p.turn (not yet held to its limit) into out[4i..4i+3].
 * @param {Prepared} p
 * @param {Float64Array} q
 * @param {number} i
 * @param {number} scale
 * @param {Float64Array} out
 */
function turned(p, q, i, scale, out) {
  const k = 4 * i, turn = p.turn;
  const x = q[k], y = q[k + 1], z = q[k + 2], w = q[k + 3];
  if (p.hinge[i]) {
    const h = 0.5 * scale * turn[3 * i];
    const hn = Math.sqrt(h * h + 1);
    const hx = h / hn, hw = 1 / hn;
    const nx = hx * w + hw * x, nw = hw * w - hx * x;
    const norm = Math.sqrt(nx * nx + nw * nw);
    out[k] = nx / norm; out[k + 1] = 0; out[k + 2] = 0; out[k + 3] = nw / norm;
    return;
  }
  // The world turn in the parent's frame, then applied on the left of the local rotation.
  let ox = scale * turn[3 * i], oy = scale * turn[3 * i + 1], oz = scale * turn[3 * i + 2];
  if (i > 0) {
    rotate(p.world, k - 4, true, ox, oy, oz, p.local, 0);
    ox = p.local[0]; oy = p.local[1]; oz = p.local[2];
  }
  const hx0 = 0.5 * ox, hy0 = 0.5 * oy, hz0 = 0.5 * oz;
  const hn = Math.sqrt(hx0 * hx0 + hy0 * hy0 + hz0 * hz0 + 1);
  const hx = hx0 / hn, hy = hy0 / hn, hz = hz0 / hn, hw = 1 / hn;
  const nx = hw * x + hx * w + hy * z - hz * y;
  const ny = hw * y - hx * z + hy * w + hz * x;
  const nz = hw * z + hx * y - hy * x + hz * w;
  const nw = hw * w - hx * x - hy * y - hz * z;
  const norm = Math.sqrt(nx * nx + ny * ny + nz * nz + nw * nw);
  out[k] = nx / norm; out[k + 1] = ny / norm; out[k + 2] = nz / norm; out[k + 3] = nw / norm;
}

/**
 * One damped least-squares iteration of q (in place) toward the target (tx, ty, tz). A joint
 * the update would take past its limit is held (moved by its rest bias alone) and the update
 * solved again without it (once), so the others make up for it rather than pushing it in vain.
 * @param {Prepared} p
 * @param {Float64Array} q
 * @param {number} tx
 * @param {number} ty
 * @param {number} tz
 * @param {number} keep  How much of the rest bend the bias keeps (1: all, 0: straight).
 */
function iterate(p, q, tx, ty, tz, keep) {
  const n = p.n, pos = p.pos, world = p.world, bias = p.bias, cols = p.cols, skip = p.skip, trial = p.trial;
  forward(p, q);
  const ex = pos[3 * n], ey = pos[3 * n + 1], ez = pos[3 * n + 2];
  let dx = tx - ex, dy = ty - ey, dz = tz - ez;
  const dn = Math.sqrt(dx * dx + dy * dy + dz * dz);
  if (dn > STEP * p.reach) {
    const f = STEP * p.reach / dn;
    dx *= f; dy *= f; dz *= f;
  }
  for (let i = 0; i < n; i++) {
    const rx = ex - pos[3 * i], ry = ey - pos[3 * i + 1], rz = ez - pos[3 * i + 2];
    const k = 4 * i;
    // The base points the chain: it is not biased upright when the goal is out of reach.
    const gain = i === 0 ? -BIAS * keep : -BIAS;
    skip[i] = 0;
    if (p.hinge[i]) {
      const wx = world[k], wy = world[k + 1], wz = world[k + 2], ww = world[k + 3];
      // The hinge's world axis: the first column of its world rotation; its column a x r.
      const ax = 1 - 2 * (wy * wy + wz * wz), ay = 2 * (wx * wy + ww * wz), az = 2 * (wx * wz - ww * wy);
      cols[3 * i] = ay * rz - az * ry; cols[3 * i + 1] = az * rx - ax * rz; cols[3 * i + 2] = ax * ry - ay * rx;
      bias[3 * i] = gain * (2 * q[k] - keep * 2 * p.restX[i]);
      bias[3 * i + 1] = 0; bias[3 * i + 2] = 0;
    } else {
      cols[3 * i] = rx; cols[3 * i + 1] = ry; cols[3 * i + 2] = rz;
      const lx = gain * (2 * q[k] - keep * 2 * p.restX[i]);
      const ly = gain * (2 * q[k + 1]);
      const lz = gain * (2 * q[k + 2]);
      if (i === 0) {
        // Out of reach, a ball base keeps the bias on its twist about its own segment (which
        // does not move a straight chain's effector), so no twist from the swing there stays
        // to make its rotation angle larger than pointing needs, up against its limit.
        const l0 = p.lengths[0];
        const ax = pos[3] / l0, ay = pos[4] / l0, az = pos[5] / l0;
        const twist = -BIAS * (1 - keep) * (2 * q[0] * ax + 2 * q[1] * ay + 2 * q[2] * az);
        bias[0] = lx + twist * ax; bias[1] = ly + twist * ay; bias[2] = lz + twist * az;
      } else {
        rotate(world, k - 4, false, lx, ly, lz, bias, 3 * i);
      }
    }
  }
  let scale = dls(p, dx, dy, dz, skip, keep);
  let held = false;
  for (let i = 0; i < n; i++) {
    turned(p, q, i, scale, trial);
    if (trial[4 * i + 3] < p.cosLim[i]) {
      skip[i] = 1;
      held = true;
    }
  }
  if (held) {
    scale = dls(p, dx, dy, dz, skip, keep);
    for (let i = 0; i < n; i++) turned(p, q, i, scale, trial);
  }
  for (let i = 0; i < n; i++) {
    for (let c = 0; c < 4; c++) q[4 * i + c] = trial[4 * i + c];
    clampJoint(p, q, i);
  }
}

/**
 * One tick of a prepared chain from pose to out (may be the same array).
 * @param {Prepared} p
 * @param {ArrayLike<number>} pose
 * @param {number} gx
 * @param {number} gy
 * @param {number} gz
 * @param {number} gx0  The goal a tick before.
 * @param {number} gy0
 * @param {number} gz0
 * @param {Float64Array} out
 */
function advance(p, pose, gx, gy, gz, gx0, gy0, gz0, out) {
  const n = p.n, reach = p.reach, pos = p.pos, back = p.back;
  // Unit quaternions with w >= 0: a joint's coordinates (twice the vector part) and its limit
  // test (w >= cos(limit / 2)) read the rotation angle from 0 to pi.
  for (let k = 0; k < 4 * n; k += 4) {
    const x = pose[k], y = pose[k + 1], z = pose[k + 2], w = pose[k + 3];
    const f = (w < 0 ? -1 : 1) / Math.sqrt(x * x + y * y + z * z + w * w);
    back[k] = x * f; back[k + 1] = y * f; back[k + 2] = z * f; back[k + 3] = w * f;
  }
  forward(p, back);
  const sx = pos[3 * n], sy = pos[3 * n + 1], sz = pos[3 * n + 2];
  const mx = gx - gx0, my = gy - gy0, mz = gz - gz0;
  const allowance = Math.sqrt(mx * mx + my * my + mz * mz) + CATCH_UP * reach / RATE;
  let dx = gx - sx, dy = gy - sy, dz = gz - sz;
  const dn = Math.sqrt(dx * dx + dy * dy + dz * dz);
  if (dn > allowance) {
    const f = allowance / dn;
    dx *= f; dy *= f; dz *= f;
  }
  let tx = sx + dx, ty = sy + dy, tz = sz + dz;
  // A target out of reach is brought onto the reach's sphere (no nearer to the effector: the
  // ball is convex), where the straight chain pointing at it ends: the error the solver sees
  // is then one it can remove, not one that makes it overshoot straight, over and back.
  const tn = Math.sqrt(tx * tx + ty * ty + tz * tz);
  if (tn > reach) {
    const f = reach / tn;
    tx *= f; ty *= f; tz *= f;
  }
  const far = (Math.sqrt(gx * gx + gy * gy + gz * gz) - reach) / (BAND * reach);
  const keep = 1 - Math.min(Math.max(far, 0), 1);
  for (let k = 0; k < 4 * n; k++) out[k] = back[k];
  for (let it = 0; it < ITERATIONS; it++) iterate(p, out, tx, ty, tz, keep);
  pullBack(p, out, sx, sy, sz, allowance);
}

/**
 * Where the tick moved the effector farther than its allowance from (sx, sy, sz) (which
 * the solver's second-order motion may do), bring the pose back toward the tick's start
 * (p.back) along each joint's shortest arc, by bisection, to within the allowance.
 * @param {Prepared} p
 * @param {Float64Array} out
 * @param {number} sx
 * @param {number} sy
 * @param {number} sz
 * @param {number} allowance
 */
function pullBack(p, out, sx, sy, sz, allowance) {
  const n = p.n, pos = p.pos, back = p.back;
  forward(p, out);
  const fx = pos[3 * n] - sx, fy = pos[3 * n + 1] - sy, fz = pos[3 * n + 2] - sz;
  if (Math.sqrt(fx * fx + fy * fy + fz * fz) <= allowance) return;
  const end = new Float64Array(out);
  let low = 0, high = 1;
  for (let b = 0; b < BACKOFF; b++) {
    const t = 0.5 * (low + high);
    blend(p, back, end, t, out);
    forward(p, out);
    const ox = pos[3 * n] - sx, oy = pos[3 * n + 1] - sy, oz = pos[3 * n + 2] - sz;
    if (Math.sqrt(ox * ox + oy * oy + oz * oz) <= allowance) low = t; else high = t;
  }
  blend(p, back, end, low, out);
}

/**
 * Each joint's rotation a fraction t of the way from `from` to `to` (normalised linear
 * interpolation, on the shorter arc: it stays within the limits both are within).
 * @param {Prepared} p
 * @param {Float64Array} from
 * @param {Float64Array} to
 * @param {number} t
 * @param {Float64Array} out
 */
function blend(p, from, to, t, out) {
  for (let i = 0; i < p.n; i++) {
    const k = 4 * i;
    const dot = from[k] * to[k] + from[k + 1] * to[k + 1] + from[k + 2] * to[k + 2] + from[k + 3] * to[k + 3];
    const u = dot < 0 ? -t : t;
    const x = (1 - t) * from[k] + u * to[k], y = (1 - t) * from[k + 1] + u * to[k + 1];
    const z = (1 - t) * from[k + 2] + u * to[k + 2], w = (1 - t) * from[k + 3] + u * to[k + 3];
    const norm = Math.sqrt(x * x + y * y + z * z + w * w);
    out[k] = x / norm; out[k + 1] = y / norm; out[k + 2] = z / norm; out[k + 3] = w / norm;
  }
}

/**
 * One tick: the pose after `pose` for the goal (in the chain's base frame), `previous` the
 * goal a tick before (omitted: the goal has not moved). The effector moves at most the
 * goal's own step plus CATCH_UP reaches per second; each joint turns at most
 * ITERATIONS * MAX_TURN; the limits hold.
 * @param {Chain} chain
 * @param {ArrayLike<number>} pose  n * 4 local rotations (x, y, z, w), normalised, either sign.
 * @param {ArrayLike<number>} goal  (x, y, z).
 * @param {ArrayLike<number>} [previous]
 * @returns {Float64Array} n * 4, unit quaternions with w >= 0.
 */
export function step(chain, pose, goal, previous) {
  const p = prepare(chain);
  if (pose.length !== 4 * p.n) throw new Error(`pose: needs ${4 * p.n} numbers, got ${pose.length}`);
  for (let k = 0; k < 4 * p.n; k += 4) {
    const norm = Math.hypot(pose[k], pose[k + 1], pose[k + 2], pose[k + 3]);
    if (!(norm >= 1e-6) || !Number.isFinite(norm)) throw new Error(`pose: joint ${k / 4} is not a rotation (norm ${norm})`);
  }
  const before = previous ?? goal;
  for (const g of [goal, before]) {
    if (g.length !== 3 || ![0, 1, 2].every((c) => Number.isFinite(g[c]))) throw new Error(`goal: needs 3 finite numbers, got ${Array.from(g)}`);
  }
  const out = new Float64Array(4 * p.n);
  advance(p, pose, goal[0], goal[1], goal[2], before[0], before[1], before[2], out);
  return out;
}

/**
 * The pose at every tick of a goal path: tick k's goal goals[3k..3k+2] (base frame), each
 * tick stepped from the one before, the first from the rest pose.
 * @param {Chain} chain
 * @param {ArrayLike<number>} goals  n * 3.
 * @returns {Float64Array} n * J * 4 local rotations.
 */
export function solve(chain, goals) {
  const p = prepare(chain);
  const ticks = Math.floor(goals.length / 3);
  if (goals.length !== 3 * ticks) throw new Error(`goals: needs 3 numbers a tick, got ${goals.length}`);
  for (let k = 0; k < goals.length; k++) {
    if (!Number.isFinite(goals[k])) throw new Error(`goals: tick ${Math.floor(k / 3)} is not finite`);
  }
  const j4 = 4 * p.n;
  const out = new Float64Array(ticks * j4);
  let pose = rest(chain);
  for (let k = 0; k < ticks; k++) {
    const b = k === 0 ? 0 : 3 * (k - 1);
    const here = out.subarray(k * j4, (k + 1) * j4);
    advance(p, pose, goals[3 * k], goals[3 * k + 1], goals[3 * k + 2], goals[b], goals[b + 1], goals[b + 2], here);
    pose = here;
  }
  return out;
}

/**
 * Forward kinematics: the base, each joint and the effector, in the chain's base frame.
 * @param {Chain} chain
 * @param {ArrayLike<number>} pose  n * 4 local rotations.
 * @returns {Float64Array} (n + 1) * 3
 */
export function points(chain, pose) {
  const p = prepare(chain);
  if (pose.length !== 4 * p.n) throw new Error(`pose: needs ${4 * p.n} numbers, got ${pose.length}`);
  forward(p, Float64Array.from(pose));
  return new Float64Array(p.pos);
}
