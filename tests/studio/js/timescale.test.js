// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { viewRange, tickStep, formatTime } from '../../../src/sketchanim/studio/web/js/timescale.js';

test('the view holds the span, the loop and the playhead', () => {
  assert.deepEqual(viewRange([0, 0], null, 0), [0, 5.2]);
  const [a, b] = viewRange([1, 9], [2, 12], -1);
  assert.ok(a < -1 && b > 12);
});

test('ticks are round and far enough apart', () => {
  assert.equal(tickStep(100), 1);
  assert.equal(tickStep(1000), 0.1);
  assert.equal(tickStep(25), 5);
});

test('times read as m:ss.cc', () => {
  assert.equal(formatTime(61.256), '1:01.26');
  assert.equal(formatTime(-0.5), '-0:00.50');
});
