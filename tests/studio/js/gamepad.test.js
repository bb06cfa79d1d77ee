// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { readPad, active, applyPad, rotate, multiply } from '../../../src/sketchanim/studio/web/js/gamepad.js';

const close = (/** @type {number[]} */ a, /** @type {number[]} */ b) => a.every((v, i) => Math.abs(v - b[i]) < 1e-12);
const still = { axes: [0.05, -0.05, 0, 0], buttons: [] };

test('sticks at rest ask for nothing', () => {
  assert.equal(active(readPad(still)), false);
});

test('the left stick moves in the view plane, relative to the view', () => {
  const input = readPad({ axes: [1, 0, 0, 0], buttons: [] });
  assert.deepEqual(input.move, [1, 0, 0]);
  const yaw90 = [0, Math.SQRT1_2, 0, Math.SQRT1_2];        // a camera turned 90 degrees left
  const out = applyPad([0, 0, 0], [0, 0, 0, 1], input, 0.5, yaw90, { speed: 2 });
  assert.ok(close(out.position, [0, 0, -1]));
  assert.deepEqual(out.orientation, [0, 0, 0, 1]);
});

test('turning at a rate for a time turns by their product, staying unit', () => {
  const input = { move: /** @type {[number, number, number]} */ ([0, 0, 0]), turn: /** @type {[number, number, number]} */ ([0, 1, 0]) };
  let q = [0, 0, 0, 1];
  for (let i = 0; i < 60; i++) q = applyPad([0, 0, 0], q, input, 1 / 60, [0, 0, 0, 1], { turnRate: Math.PI / 2 }).orientation;
  assert.ok(close(q, [0, Math.SQRT1_2, 0, Math.SQRT1_2]));
  assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-12);
});

test('a 3D mouse (6 axes) moves and turns at once', () => {
  const input = readPad({ axes: [0, 0, -1, 0, 0, 1], buttons: [] });
  assert.deepEqual(input.move, [0, 1, 0]);
  assert.deepEqual(input.turn, [0, -1, 0]);
});

test('rotate and multiply agree with each other', () => {
  const a = [0.1, 0.2, 0.3, 0.9];
  const n = Math.hypot(...a);
  const q = a.map((v) => v / n);
  const v = [1, -2, 0.5];
  const conj = [-q[0], -q[1], -q[2], q[3]];
  const viaMul = multiply(multiply(q, [...v, 0]), conj).slice(0, 3);
  assert.ok(close(rotate(q, v), viaMul));
});
