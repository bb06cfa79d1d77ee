// @ts-check
/**
 * Two-bone analytic inverse kinematics and the frame arithmetic a pose needs: the page's
 * copy of src/sketchanim/motion/twobone.py, operation for operation. A frame is a rotation
 * given by its columns (the world directions of its x, y, z axes); a bone lies along its
 * rest -y.
 */

/** @typedef {[number, number, number]} Vec */
/** @typedef {[Vec, Vec, Vec]} Frame  a rotation's columns (its x, y, z axes) */

/**
 * The world frames of a limb's upper and lower bones from a joint at `root` reaching for
 * `target` (the distance clamped to the limb's reach), the middle joint bending toward
 * `front` (its part off the root-target line; +y, or +z for a limb along y, where it has none).
 * @param {Vec} root
 * @param {Vec} target
 * @param {number} upper
 * @param {number} lower
 * @param {Vec} front
 * @returns {[Frame, Frame]}
 *
 * @example
 * twoBone([0, 1, 0], [0, 0.4, 0], 0.5, 0.5, [0, 0, 1])[0][1];   // [0, 0.6, -0.8]: back up the upper bone
 */
export function twoBone(root, target, upper, lower, front) {
  const dx = target[0] - root[0], dy = target[1] - root[1], dz = target[2] - root[2];
  let d = Math.sqrt(dx * dx + dy * dy + dz * dz);
  const l1 = upper, l2 = lower;
  const longest = (l1 + l2) * (1.0 - 1e-9);
  const shortest = Math.abs(l1 - l2) + 1e-6 * (l1 + l2);
  let ux, uy, uz;
  if (d > 1e-12) {
    ux = dx / d; uy = dy / d; uz = dz / d;
  } else {
    ux = 0.0; uy = -1.0; uz = 0.0;
  }
  d = d > longest ? longest : d < shortest ? shortest : d;
  const [px, py, pz] = front;
  const along = px * ux + py * uy + pz * uz;
  let nx = px - along * ux, ny = py - along * uy, nz = pz - along * uz;
  let n = Math.sqrt(nx * nx + ny * ny + nz * nz);
  if (n < 1e-6) { // the limb points (nearly) along `front`: bend toward +y (or +z)
    const [qx, qy, qz] = Math.abs(uy) < 0.9 ? [0.0, 1.0, 0.0] : [0.0, 0.0, 1.0];
    const on = qx * ux + qy * uy + qz * uz;
    nx = qx - on * ux; ny = qy - on * uy; nz = qz - on * uz;
    n = Math.sqrt(nx * nx + ny * ny + nz * nz);
  }
  nx = nx / n; ny = ny / n; nz = nz / n;
  const c1 = (l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d);
  const c2 = (l2 * l2 + d * d - l1 * l1) / (2.0 * l2 * d);
  const s1 = Math.sqrt(Math.max(0.0, 1.0 - c1 * c1));
  const s2 = Math.sqrt(Math.max(0.0, 1.0 - c2 * c2));
  const first = bone([ux * c1 + nx * s1, uy * c1 + ny * s1, uz * c1 + nz * s1],
    [nx * c1 - ux * s1, ny * c1 - uy * s1, nz * c1 - uz * s1]);
  const second = bone([ux * c2 - nx * s2, uy * c2 - ny * s2, uz * c2 - nz * s2],
    [nx * c2 + ux * s2, ny * c2 + uy * s2, nz * c2 + uz * s2]);
  return [first, second];
}

/**
 * The frame of a bone along `down` (its rest -y) with its rest +z on `front`.
 * @param {Vec} down
 * @param {Vec} front
 * @returns {Frame}
 */
export function bone(down, front) {
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
export function localFrame(parent, child) {
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
export function frameQuaternion(m) {
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
