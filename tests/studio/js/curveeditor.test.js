// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { basisAt, eulerToQuat, greville, keyKnots, nearestEuler, nearestPoint, quatToEuler, rangeOf, response, unwrappedEulers, valueAndSlope }
  from '../../../src/sketchanim/studio/web/js/curvegeometry.js';
import { sliderOf, toleranceAt } from '../../../src/sketchanim/studio/web/js/tolerancebar.js';

const KNOTS = [0, 0, 0, 0, 0.3, 0.5, 0.5, 1.2, 2, 2, 2, 2];
const ORDER = 4;
const COEF = [[0, 1], [1, -1], [0.5, 2], [2, 0], [-1, 1], [0.3, 0.3], [1, 1], [0, 2]];

/** @param {number} a @param {number} b @param {number} [eps] */
const close = (a, b, eps = 1e-9) => assert.ok(Math.abs(a - b) <= eps, `${a} != ${b}`);

test('Greville abscissae are the means of the k-1 inner knots', () => {
  assert.deepEqual(Array.from(greville([0, 0, 0, 0, 1, 1, 1, 1], 4)), [0, 1 / 3, 2 / 3, 1]);
  const g = greville(KNOTS, ORDER);
  assert.equal(g.length, COEF.length);
  close(g[3], (0.3 + 0.5 + 0.5) / 3);
});

test('keys sit at the ends and at each distinct interior knot, once for a double knot', () => {
  assert.deepEqual(Array.from(keyKnots(KNOTS, ORDER)), [3, 4, 5, 7, 8]);
  assert.deepEqual(Array.from(keyKnots([0, 0, 1, 1], 2)), [1, 2]);
});

test('the basis sums to one, its slopes to zero, and value and slope match finite differences', () => {
  for (const t of [0, 0.1, 0.3, 0.45, 0.5, 0.9, 1.2, 1.7, 2]) {
    const b = basisAt(KNOTS, ORDER, t);
    close(b.value.reduce((s, v) => s + v, 0), 1);
    close(b.slope.reduce((s, v) => s + v, 0), 0, 1e-9);
  }
  for (const t of [0.1, 0.4, 0.8, 1.5]) {
    const h = 1e-6;
    const { slope } = valueAndSlope(KNOTS, ORDER, COEF, t);
    const up = valueAndSlope(KNOTS, ORDER, COEF, t + h).value;
    const down = valueAndSlope(KNOTS, ORDER, COEF, t - h).value;
    slope.forEach((s, ch) => close(s, (up[ch] - down[ch]) / (2 * h), 1e-5));
  }
  const linear = basisAt([0, 0, 1, 1], 2, 0.25);
  assert.deepEqual([linear.first, ...linear.value, ...linear.slope], [0, 0.75, 0.25, -1, 1]);
});

test('the least change moves the curve by 1 at every given time, and only near them', () => {
  for (const slope of [false, true]) {
    for (const times of [[0.5], [0.3, 0.5, 1.2], [0, 0.3, 0.5, 1.2, 2]]) {
      const u = response(KNOTS, ORDER, times, slope);
      const moved = COEF.map((row, j) => [row[0] + u[j], row[1]]);
      for (const t of times) {
        const before = valueAndSlope(KNOTS, ORDER, COEF, t);
        const after = valueAndSlope(KNOTS, ORDER, moved, t);
        const which = slope ? 'slope' : 'value';
        close(after[which][0] - before[which][0], 1, 1e-9);
        close(after[which][1], before[which][1]);
      }
    }
  }
  const one = response(KNOTS, ORDER, [0.3]);
  const b = basisAt(KNOTS, ORDER, 0.3);
  const norm = b.value.reduce((s, v) => s + v * v, 0);
  one.forEach((v, j) => close(v, j >= b.first && j < b.first + ORDER ? b.value[j - b.first] / norm : 0));
});

test('Euler angles turn into quaternions and back', () => {
  const q = [Math.SQRT1_2, 0, 0, Math.SQRT1_2];
  quatToEuler(q).forEach((v, i) => close(v, [90, 0, 0][i], 1e-9));
  for (const e of [[10, 20, 30], [-120, 45, 170], [0, -80, 5]]) {
    const back = quatToEuler(eulerToQuat(e));
    back.forEach((v, i) => close(v, e[i], 1e-7));
    close(Math.hypot(...eulerToQuat(e)), 1, 1e-12);
  }
});

test('unwrapped Euler angles never jump by 360', () => {
  const quats = Array.from({ length: 200 }, (_, i) => eulerToQuat([i * 5, 20 * Math.sin(i / 10), -i * 3]));
  const eulers = unwrappedEulers(quats);
  for (let i = 1; i < eulers.length; i++) for (let ch = 0; ch < 3; ch++) assert.ok(Math.abs(eulers[i][ch] - eulers[i - 1][ch]) < 20);
  close(eulers[199][0], 995, 1e-6);
  assert.deepEqual(nearestEuler([-179, 0, 0], [179, 0, 0]), [181, 0, 0]);
  const twin = nearestEuler([0, 170, 0], [180, 10, 180]);
  twin.forEach((v, i) => close(v, [180, 10, 180][i], 1e-9));
});

test('hit tests search the sorted x range only', () => {
  assert.deepEqual(rangeOf([0, 1, 1, 2, 5], 1, 2), [1, 4]);
  const hit = nearestPoint([0, 10, 20], [0, 0, 5], 19, 4, 3);
  assert.equal(hit.index, 2);
  close(hit.distance, Math.SQRT2);
  assert.equal(nearestPoint([0, 10, 20], [0, 0, 5], 15, 0, 3).index, -1);
});

test('the tolerance slider is logarithmic around the attribute default', () => {
  assert.equal(sliderOf(0.005, 0.005), 500);
  assert.equal(toleranceAt(750, 0.005), 0.05);
  assert.equal(toleranceAt(sliderOf(0.0123, 0.005), 0.005), 0.0123);
  assert.equal(sliderOf(1e9, 0.005), 1000);
});
