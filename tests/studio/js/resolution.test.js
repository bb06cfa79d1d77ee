// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { DEFAULT_STEPS, formatTolerance, pixelWorld, sliderPerPixel, takeTolerance, turnPerPixel } from '../../../src/sketchanim/studio/web/js/resolution.js';
import { padResolution } from '../../../src/sketchanim/studio/web/js/gamepad.js';

test('a pixel at a depth: the view height at that depth over its pixels', () => {
  assert.ok(Math.abs(pixelWorld(90, 200, 1) - 0.01) < 1e-15);
  // the studio's default view: 45 degrees, the box 10.4 units away, a 400 px high canvas
  assert.ok(Math.abs(pixelWorld(45, 400, 10.42) - 0.02158) < 1e-5);
  // twice as deep, twice the size; twice the pixels, half
  for (const [fov, h, d] of [[30, 300, 2], [60, 720, 7.5], [100, 1080, 0.3]]) {
    assert.ok(Math.abs(pixelWorld(fov, h, 2 * d) - 2 * pixelWorld(fov, h, d)) < 1e-12);
    assert.ok(Math.abs(pixelWorld(fov, 2 * h, d) - pixelWorld(fov, h, d) / 2) < 1e-12);
  }
});

test('a pixel where there is none is refused, naming the inputs', () => {
  assert.throws(() => pixelWorld(45, 0, 1), /height > 0/);
  assert.throws(() => pixelWorld(180, 400, 1), /fov/);
  assert.throws(() => pixelWorld(45, 400, -1), /depth/);
  assert.throws(() => sliderPerPixel(1, 1, 100), /hi > lo/);
});

test("the gizmo's turn per pixel is TransformControls' 20 / distance radians per unit", () => {
  assert.ok(Math.abs(turnPerPixel(0.01, 10) - (0.02 * 180) / Math.PI) < 1e-12);
  // at the default view a pixel turns about 2.4 degrees at any distance (the pixel grows with it)
  const d = 10.42;
  assert.ok(Math.abs(turnPerPixel(pixelWorld(45, 400, d), d) - turnPerPixel(pixelWorld(45, 400, 2 * d), 2 * d)) < 1e-12);
});

test('a slider: its range over its width', () => {
  assert.equal(sliderPerPixel(0, 5, 250), 0.02);
  assert.equal(sliderPerPixel(10, 120, 220), 0.5);
});

test("a take's tolerance: DEFAULT_STEPS steps, the animator's steps, or the animator's units", () => {
  const px = { step: 0.015, input: 'px' };
  assert.deepEqual(takeTolerance(px, null), { tol: DEFAULT_STEPS * 0.015, steps: DEFAULT_STEPS });
  assert.deepEqual(takeTolerance(px, { amount: 4, unit: 'px' }), { tol: 0.06, steps: 4 });
  const t = takeTolerance(px, { amount: 0.003, unit: 'units' });
  assert.equal(t.tol, 0.003);
  assert.ok(Math.abs(t.steps - 0.2) < 1e-12);
  assert.throws(() => takeTolerance({ step: 0, input: 'px' }, null), /step/);
  assert.throws(() => takeTolerance({ step: NaN, input: 'px' }, null), /step/);
});

test('a tolerance as the page shows it', () => {
  assert.equal(formatTolerance({ tol: 0.0300001, steps: 2 }, 'px'), 'tol 2 px = 0.03');
  assert.equal(formatTolerance({ tol: 2.29, steps: 1 }, 'step', '°'), 'tol 1 step = 2.3°');
  assert.equal(formatTolerance({ tol: 0.04, steps: 2.5 }, 'step'), 'tol 2.5 steps = 0.04');
  assert.equal(formatTolerance({ tol: 0.05, steps: NaN }, ''), 'tol 0.05');
});

test("a stick's step over the speed it maps to", () => {
  const r = padResolution();
  assert.ok(Math.abs(r.position - 0.015) < 1e-12);
  assert.ok(Math.abs(r.orientation - (0.02 * 180) / Math.PI) < 1e-12);
  assert.ok(Math.abs(padResolution({ speed: 3 }).position - 0.03) < 1e-12);
});
