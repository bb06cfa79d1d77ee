// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { AHEAD, HEIGHT, RADIUS, placeInFront } from '../../../src/sketchanim/studio/web/js/placement.js';

/** @typedef {import('../../../src/sketchanim/studio/web/js/placement.js').Vec3} Vec3 */

/** @param {Vec3} a @param {Vec3} b */
const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

test('an empty scene: AHEAD metres in front of the camera along the floor, at the height of interest', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, -0.2, -1], []), [0, HEIGHT, 6 - AHEAD]);
  const spot = placeInFront([4.5, 3.5, 7], [-4.5, -3, -7], []);
  assert.equal(spot[1], HEIGHT);
  const ahead = Math.hypot(spot[0] - 4.5, spot[2] - 7);
  assert.ok(Math.abs(ahead - AHEAD) < 1e-3, `ahead ${ahead}`);
  const dir = [-4.5 / Math.hypot(4.5, 7), -7 / Math.hypot(4.5, 7)];      // on the camera's line of sight (seen from above)
  assert.ok(Math.abs((spot[0] - 4.5) * dir[1] - (spot[2] - 7) * dir[0]) < 1e-3);
});

test('a blocked spot moves sideways, to the right first, until it is clear', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, -0.2, -1], [{ position: [0, 0.5, 3], radius: 0.6 }]), [1.5, HEIGHT, 3]);
  const blockRight = [{ position: /** @type {Vec3} */ ([0, 0.5, 3]), radius: 0.6 }, { position: /** @type {Vec3} */ ([1.5, 0.5, 3]), radius: 0.6 }];
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, -0.2, -1], blockRight), [-1.5, HEIGHT, 3]);
});

test('the spot is clear of every occupied sphere in a crowded row', () => {
  /** @type {{position: Vec3, radius: number}[]} */
  const row = Array.from({ length: 9 }, (_, i) => ({ position: [i - 4, 0.5, 3], radius: 0.7 }));
  const spot = placeInFront([0, 1.6, 6], [0, 0, -1], row);
  for (const o of row) assert.ok(distance(spot, o.position) >= o.radius + RADIUS, `${spot} inside ${o.position}`);
  assert.equal(spot[2], 3);
});

test('looking straight down, ahead is the camera\'s -z', () => {
  assert.deepEqual(placeInFront([1, 10, 2], [0, -1, 0], []), [1, HEIGHT, 2 - AHEAD]);
});

test('objects far above or below the floor do not block it', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, 0, -1], [{ position: [0, 4, 3], radius: 0.5 }]), [0, HEIGHT, 3]);
});
