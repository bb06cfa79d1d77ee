// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { RATE, chainFromSlots, rest, step, solve, points } from '../../../src/sketchanim/studio/web/js/ik.js';

const arm = chainFromSlots([0.5, 0.4, 0.3, 0.25, 0.2, 0, 0, 0], [150, 150, 150, 150, 150, 150, 150, 150], [0, 1, 1, 1, 0, 0, 0, 0]);

/** @param {ArrayLike<number>} pts @param {number} i */
const at = (pts, i) => [pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]];

/** @param {number} ticks @param {number[]} goal */
function held(ticks, goal) {
  const goals = new Float64Array(3 * ticks);
  for (let k = 0; k < ticks; k++) goals.set(goal, 3 * k);
  return goals;
}

test('the scene slots give the leading positive lengths, radians and hinge flags', () => {
  assert.equal(RATE, 120);
  assert.deepEqual(arm.lengths, [0.5, 0.4, 0.3, 0.25, 0.2]);
  assert.deepEqual(arm.hinges, [false, true, true, true, false]);
  assert.ok(Math.abs(arm.limits[0] - 150 * Math.PI / 180) < 1e-15);
  assert.throws(() => chainFromSlots([0.5, 0, 0.3], [90, 90, 90], [0, 0, 0]), /lengths/);
  assert.throws(() => chainFromSlots([0.5, NaN, 0.3], [90, 90, 90], [0, 0, 0]), /lengths/);
  assert.throws(() => chainFromSlots([0.5, 0.4], [90, 0], [0, 0]), /limits/);
});

test('the rest pose stands up +y with a slight bend toward +z', () => {
  const pts = points(arm, rest(arm));
  assert.deepEqual(at(pts, 0), [0, 0, 0]);
  assert.deepEqual(at(pts, 1), [0, 0.5, 0]);
  const tip = at(pts, 5);
  assert.ok(tip[1] > 1.6 && tip[2] > 0.05 && tip[0] === 0, `${tip}`);
});

test('a goal held in reach is reached, a goal straight below too', () => {
  for (const goal of [[0.5, 1.1, 0], [0, -1.2, 0], [-0.3, 0.2, 0.6]]) {
    const poses = solve(arm, held(240, goal));
    const tip = at(points(arm, poses.subarray(239 * 20)), 5);
    assert.ok(Math.hypot(tip[0] - goal[0], tip[1] - goal[1], tip[2] - goal[2]) < 1e-6, `${goal}: ${tip}`);
  }
});

test('a goal out of reach: the chain points at it, nearly straight, never NaN', () => {
  const goal = [3, 1, -2];
  const poses = solve(arm, held(480, goal));
  assert.ok(poses.every(Number.isFinite));
  const tip = at(points(arm, poses.subarray(479 * 20)), 5);
  const d = Math.hypot(...tip), g = Math.hypot(...goal);
  assert.ok(d > 1.64, `${d}`);
  const cos = (tip[0] * goal[0] + tip[1] * goal[1] + tip[2] * goal[2]) / (d * g);
  assert.ok(cos > Math.cos(0.01), `${Math.acos(cos)}`);
});

test('one step moves the effector at most the goal step plus the catch-up', () => {
  const pose = rest(arm);
  const before = at(points(arm, pose), 5);
  const after = at(points(arm, step(arm, pose, [1, 0, 1])), 5);
  const moved = Math.hypot(after[0] - before[0], after[1] - before[1], after[2] - before[2]);
  assert.ok(moved > 0 && moved <= 2 * 1.65 / RATE + 1e-12, `${moved}`);
});

test('limits hold: a hinge limited to 10 degrees stays within them', () => {
  const chain = chainFromSlots([0.5, 0.5, 0.5], [180, 10, 10], [0, 1, 1]);
  const poses = solve(chain, held(240, [0, 0.2, 0.3]));
  for (let k = 0; k < poses.length; k += 4) {
    assert.ok(Math.abs(poses[k + 3]) >= Math.cos(5 * Math.PI / 180) - 1e-12 || k % 12 === 0);
  }
});

test('solve is step after step, the first from rest with the goal as its own previous', () => {
  const goals = new Float64Array(60 * 3);
  for (let k = 0; k < 60; k++) goals.set([0.2 + k / 60, 1 - k / 40, 0.3], 3 * k);
  const solved = solve(arm, goals);
  let pose = rest(arm);
  for (let k = 0; k < 60; k++) {
    pose = step(arm, pose, goals.subarray(3 * k, 3 * k + 3), k ? goals.subarray(3 * k - 3, 3 * k) : undefined);
    assert.deepEqual([...pose], [...solved.subarray(20 * k, 20 * k + 20)]);
  }
});

test('bad goals and poses are refused, naming them', () => {
  assert.throws(() => solve(arm, [0, 1]), /goals/);
  assert.throws(() => solve(arm, [0, 1, NaN]), /goals/);
  assert.throws(() => step(arm, rest(arm), [0, 1]), /goal/);
  assert.throws(() => step(arm, new Float64Array(8), [0, 1, 0]), /pose/);
});
