// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { AHEAD, FAR, HEIGHT, RADIUS, placeInFront } from '../../../src/sketchanim/studio/web/js/placement.js';

/** @typedef {import('../../../src/sketchanim/studio/web/js/placement.js').Vec3} Vec3 */

/** @param {Vec3} a @param {Vec3} b */
const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

test('an empty scene: where the line of sight meets the height of interest', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, -0.2, -1], []), [0, HEIGHT, 0.5]);
  // the studio's view camera, looking at the box
  const spot = placeInFront([4.5, 3.5, 7], [-4.5, -3, -7], []);
  assert.deepEqual(spot, [0, HEIGHT, 0]);
  assert.deepEqual(placeInFront([1, 10, 2], [0, -1, 0], []), [1, HEIGHT, 2], 'looking straight down: under the camera');
});

test('level, looking up, or the floor too far: AHEAD metres on along the view flattened onto the floor', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, 0, -1], []), [0, HEIGHT, 6 - AHEAD]);
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, 0.3, -1], []), [0, HEIGHT, 6 - AHEAD]);
  const far = placeInFront([0, 1.6, 6], [0, -0.01, -1], []);          // meets y = 0.5 some 110 m on
  assert.ok(FAR < 110);
  assert.deepEqual(far, [0, HEIGHT, 6 - AHEAD]);
  const spot = placeInFront([4.5, 3.5, 7], [-4.5, 0.2, -7], []);
  assert.ok(Math.abs(Math.hypot(spot[0] - 4.5, spot[2] - 7) - AHEAD) < 1e-3);
  assert.ok(Math.abs((spot[0] - 4.5) * 7 - (spot[2] - 7) * 4.5) < 1e-2, 'on the line of sight seen from above');
});

test('a blocked spot moves sideways, to the right first, until it is clear', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, 0, -1], [{ position: [0, 0.5, 3], radius: 0.6 }]), [1.5, HEIGHT, 3]);
  /** @type {{position: Vec3, radius: number}[]} */
  const blockRight = [{ position: [0, 0.5, 3], radius: 0.6 }, { position: [1.5, 0.5, 3], radius: 0.6 }];
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, 0, -1], blockRight), [-1.5, HEIGHT, 3]);
});

test('the spot is clear of every occupied sphere in a crowded row', () => {
  /** @type {{position: Vec3, radius: number}[]} */
  const row = Array.from({ length: 9 }, (_, i) => ({ position: [i - 4, 0.5, 3], radius: 0.7 }));
  const spot = placeInFront([0, 1.6, 6], [0, 0, -1], row);
  for (const o of row) assert.ok(distance(spot, o.position) >= o.radius + RADIUS, `${spot} inside ${o.position}`);
  assert.equal(spot[2], 3);
});

test('objects far above or below the height of interest do not block it', () => {
  assert.deepEqual(placeInFront([0, 1.6, 6], [0, 0, -1], [{ position: [0, 4, 3], radius: 0.5 }]), [0, HEIGHT, 3]);
});
