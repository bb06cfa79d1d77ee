// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { pack, evaluate, valueOf, stepValue, sampleCurve } from '../../../src/sketchanim/studio/web/js/evaluate.js';

const line = { path: 'box.position', order: 2, knots: [0, 0, 2, 2], coef: [[0, 0, 0], [2, 4, 6]] };

test('a linear curve interpolates and holds its ends', () => {
  const p = pack([line]);
  assert.deepEqual([...evaluate(p, 1)], [1, 2, 3]);
  assert.deepEqual([...evaluate(p, -5)], [0, 0, 0]);
  assert.deepEqual([...evaluate(p, 9)], [2, 4, 6]);
  assert.deepEqual(p.span, [0, 2]);
});

test('a cubic Bezier segment matches its Bernstein form', () => {
  const c = { path: 'x.float', order: 4, knots: [0, 0, 0, 0, 1, 1, 1, 1], coef: [[0], [1], [3], [2]] };
  const p = pack([c]);
  for (const t of [0, 0.25, 0.5, 0.9, 1]) {
    const u = 1 - t;
    const want = 3 * u * u * t * 1 + 3 * u * t * t * 3 + t * t * t * 2;
    assert.ok(Math.abs(evaluate(p, t)[0] - want) < 1e-15);
  }
});

test('orientations are normalised, several curves go end to end', () => {
  const q = { path: 'box.orientation', order: 2, knots: [0, 0, 1, 1], coef: [[0, 0, 0, 2], [0, 0, 2, 0]], rotation: true };
  const p = pack([line, q]);
  evaluate(p, 0.5);
  const v = valueOf(p, 1);
  assert.ok(Math.abs(Math.hypot(...v) - 1) < 1e-15);
  assert.ok(Math.abs(v[2] - Math.SQRT1_2) < 1e-15);
  assert.deepEqual([...valueOf(p, 0)], [0.5, 1, 1.5]);
  assert.deepEqual([...p.oofs], [0, 3, 7]);
});

test('a curve whose rows do not fit its knots is refused, naming it', () => {
  assert.throws(() => pack([{ ...line, coef: [[0, 0, 0]] }]), /box\.position/);
});

test('steps hold from their time on', () => {
  const s = { path: 'lamp.on', times: [1, 2, 2], values: [false, true, false] };
  assert.equal(stepValue(s, 0.5), null);
  assert.equal(stepValue(s, 1), false);
  assert.equal(stepValue(s, 2), false);
  assert.equal(stepValue(s, 9), false);
  assert.equal(stepValue(s, 1.5), false);
});

test('sampleCurve samples evenly over the range', () => {
  const { times, values } = sampleCurve(line, 0, 2, 5);
  assert.deepEqual([...times], [0, 0.5, 1, 1.5, 2]);
  assert.deepEqual([...values[1]], [0, 1, 2, 3, 4]);
});

test('a bounded track never leaves its bounds, whatever its coefficients', () => {
  // A colour channel whose control points overshoot (the curve peaks at 1.125), and an
  // intensity dipping below 0: played clamped to [0, 1] and [0, inf).
  const knots = [0, 0, 0, 0, 1, 1, 1, 1];
  const colour = { path: 'lamp.color', order: 4, knots, coef: [[0.9], [1.2], [1.2], [0.9]], bounds: [0, 1] };
  const dip = { path: 'lamp.intensity', order: 4, knots, coef: [[0.1], [-0.2], [-0.2], [0.1]], bounds: [0, null] };
  const free = { path: 'x.float', order: 4, knots, coef: [[0.9], [1.2], [1.2], [0.9]] };
  const p = pack([colour, dip, free]);
  let top = 0;
  for (let i = 0; i <= 1000; i++) {
    const v = evaluate(p, i / 1000);
    assert.ok(v[0] >= 0 && v[0] <= 1, `colour ${v[0]} at ${i / 1000}`);
    assert.ok(v[1] >= 0, `intensity ${v[1]} at ${i / 1000}`);
    top = Math.max(top, v[2]);
  }
  assert.ok(Math.abs(top - 1.125) < 1e-3);                        // unbounded: not clamped
  assert.equal(evaluate(p, 0.5)[0], 1);
  assert.equal(evaluate(p, 0.5)[1], 0);
});
