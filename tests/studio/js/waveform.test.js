// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { columnPeaks, peakPyramid } from '../../../src/sketchanim/studio/web/js/waveform.js';
import { RATES, syncStep } from '../../../src/sketchanim/studio/web/js/sound.js';

/** A deterministic noise of `n` samples in -1..1. @param {number} n */
function noise(n) {
  const out = new Float32Array(n);
  let x = 12345;
  for (let i = 0; i < n; i++) {
    x = (x * 1103515245 + 12345) % 2147483648;
    out[i] = (x / 2147483648) * 2 - 1;
  }
  return out;
}

/** The true extremes of `samples` over [a, b) samples. @param {Float32Array} samples @param {number} a @param {number} b */
function extremes(samples, a, b) {
  let lo = Infinity;
  let hi = -Infinity;
  for (let i = Math.max(0, a); i < Math.min(samples.length, b); i++) {
    lo = Math.min(lo, samples[i]);
    hi = Math.max(hi, samples[i]);
  }
  return [lo, hi];
}

test('each level holds the extremes of its bins; the top level those of the whole sound', () => {
  const samples = noise(10_000);
  const p = peakPyramid(samples, 1000, 64);
  const top = p.levels[p.levels.length - 1];
  assert.equal(top.min.length, 1);
  assert.deepEqual([top.min[0], top.max[0]], extremes(samples, 0, samples.length));
  for (const level of p.levels) {
    for (let b = 0; b < level.min.length; b += 7) {
      assert.deepEqual([level.min[b], level.max[b]], extremes(samples, b * level.span, (b + 1) * level.span));
    }
  }
});

test('columns aligned with bins read their exact extremes, at every zoom', () => {
  const samples = noise(1 << 16);
  const rate = 1000;
  const p = peakPyramid(samples, rate, 64);
  for (const columns of [1, 4, 16, 64, 256, 1024]) {
    const { min, max } = columnPeaks(p, 0, samples.length / rate, columns);
    const per = samples.length / columns;
    for (let c = 0; c < columns; c += Math.max(1, columns / 8)) {
      assert.deepEqual([min[c], max[c]], extremes(samples, c * per, (c + 1) * per), `${columns} columns, column ${c}`);
    }
  }
});

test('any column covers the true extremes of its time and reads at most a few bins (coarsest level that fits)', () => {
  const samples = noise(44_100 * 3);
  const rate = 44_100;
  const p = peakPyramid(samples, rate);
  for (const [t0, t1, columns] of [[0.1, 2.7, 333], [1.234, 1.3, 900], [0, 3, 7], [2.9, 3.5, 50]]) {
    const { min, max, level } = columnPeaks(p, t0, t1, columns);
    const per = ((t1 - t0) * rate) / columns;
    assert.ok(p.levels[level].span <= Math.max(per, 64) && (level + 1 === p.levels.length || p.levels[level + 1].span > per));
    for (let c = 0; c < columns; c++) {
      const [lo, hi] = extremes(samples, Math.floor(t0 * rate + c * per), Math.ceil(t0 * rate + (c + 1) * per));
      if (lo === Infinity) {
        assert.ok(min[c] > max[c], 'a column past the end is empty');
        continue;
      }
      assert.ok(min[c] <= lo && max[c] >= hi, `column ${c} of ${columns} over ${t0}..${t1}`);
    }
  }
});

test('before the sound a column is empty', () => {
  const p = peakPyramid(noise(1000), 1000);
  const { min, max } = columnPeaks(p, -2, -1, 10);
  assert.ok(min.every((m, i) => m > max[i]));
});

test('ten minutes of sound: a view of the whole reads the coarse levels (fast at any zoom)', () => {
  const rate = 48_000;
  const p = peakPyramid(new Float32Array(rate * 600), rate);
  const start = performance.now();
  for (let i = 0; i < 100; i++) columnPeaks(p, 0, 600, 1600);
  const { level } = columnPeaks(p, 0, 600, 1600);
  assert.ok(p.levels[level].span > 64 * 100, 'a whole-sound view does not read the finest bins');
  assert.ok(performance.now() - start < 2000);
});

const BASE = { time: 2, playing: true, speed: 1, offset: 1, duration: 5, position: 1, paused: false, frame: 1 / 24 };

test('the audio follows the transport: kept within a frame, re-seeked past it', () => {
  assert.deepEqual(syncStep(BASE), { action: 'keep', at: 1, rate: 1, drift: 0 });
  assert.equal(syncStep({ ...BASE, position: 1 + 0.9 / 24 }).action, 'keep');
  assert.equal(syncStep({ ...BASE, position: 1 + 1.1 / 24 }).action, 'seek');
  assert.equal(syncStep({ ...BASE, position: 1 - 1.1 / 24 }).action, 'seek');
  assert.deepEqual(syncStep({ ...BASE, speed: 0.5, paused: true }), { action: 'play', at: 1, rate: 0.5, drift: null });
});

test('paused, backwards, too fast or slow, or outside the sound: silent', () => {
  assert.equal(syncStep({ ...BASE, playing: false }).action, 'pause');
  assert.equal(syncStep({ ...BASE, speed: -1 }).action, 'pause');
  assert.equal(syncStep({ ...BASE, speed: RATES[1] * 2 }).action, 'pause');
  assert.equal(syncStep({ ...BASE, speed: RATES[0] / 2 }).action, 'pause');
  assert.equal(syncStep({ ...BASE, time: 0.5 }).action, 'pause');
  assert.equal(syncStep({ ...BASE, time: 6.5 }).action, 'pause');
  assert.equal(syncStep({ ...BASE, time: 0.5, paused: true }).action, 'keep');
});
