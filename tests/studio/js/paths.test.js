// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { valuesAt } from '../../../src/sketchanim/studio/web/js/evaluate.js';
import { AROUND, frameAt, framesIn, ghostTimes, pathRange, pointsActing, spanTimes, withPoints }
  from '../../../src/sketchanim/studio/web/js/pathgeometry.js';

/** A cubic with interior knots at 1 and 2 over [0, 3]: 6 control points. */
const cubic = { path: 'box.position', order: 4, knots: [0, 0, 0, 0, 1, 2, 3, 3, 3, 3],
  coef: [[0, 0, 0], [1, 0, 0], [2, 1, 0], [3, 1, 1], [4, 0, 1], [5, 0, 0]] };

test('the range is whole frames either side of the playhead, cut to the curve', () => {
  assert.equal(AROUND, 2);
  assert.deepEqual(pathRange(1.5, 24, null, 0, 3), [0, 3]);              // [-0.5, 3.5] cut to the curve
  const [a, b] = /** @type {[number, number]} */ (pathRange(5.01, 24, null, 0, 100));
  assert.equal(a * 24, 120 - 48);                   // the playhead's frame is 120
  assert.equal(b * 24, 120 + 48);
  assert.equal(pathRange(9, 24, null, 0, 3), null);  // the curve ends before the range
});

test('a loop range is the range, whatever the playhead', () => {
  assert.deepEqual(pathRange(2.9, 30, [0.5, 1.25], 0, 3), [0.5, 1.25]);
  assert.deepEqual(pathRange(2.9, 30, [-1, 1], 0, 3), [0, 1]);
  assert.deepEqual(pathRange(2.9, 30, [1, 1], 0, 3), [27 / 30, 3]);      // an empty loop range: around the playhead (frame 87)
});

test('frames in a range include its ends and count as they should', () => {
  assert.deepEqual(framesIn(0, 1, 4), [0, 0.25, 0.5, 0.75, 1]);
  assert.deepEqual(framesIn(0.01, 0.26, 4), [0.25]);
  assert.equal(framesIn(72 / 24, 168 / 24, 24).length, 97);
  assert.deepEqual(framesIn(0.3, 0.4, 4), []);
  assert.equal(frameAt(1 / 48 + 1e-6, 24), 1);
});

test('span times reach both ends, at most a step apart', () => {
  const t = spanTimes(0.1, 1.05, 0.1);
  assert.equal(t[0], 0.1);
  assert.equal(t.at(-1), 1.05);
  for (let i = 1; i < t.length; i++) assert.ok(t[i] - t[i - 1] <= 0.1 + 1e-12 && t[i] > t[i - 1]);
  assert.deepEqual(spanTimes(0, 1, 0.5), [0, 0.5, 1]);
});

test('values at times are the curve\'s (a clamped cubic passes through its end points)', () => {
  const v = valuesAt(cubic, [0, 3, 1.5]);
  assert.deepEqual([...v.subarray(0, 3)], [0, 0, 0]);
  assert.deepEqual([...v.subarray(3, 6)], [5, 0, 0]);
  assert.ok(Math.abs(v[6] - 2.5) < 1e-12);         // x is linear in the point index: the Greville abscissa
});

test('points acting on a range are those whose span meets it', () => {
  assert.deepEqual(pointsActing(cubic, 0, 3), [0, 1, 2, 3, 4, 5]);
  assert.deepEqual(pointsActing(cubic, 0, 0.5), [0, 1, 2, 3]);      // point i acts on (knots[i], knots[i+4])
  assert.deepEqual(pointsActing(cubic, 2.2, 3), [2, 3, 4, 5]);
  assert.deepEqual(pointsActing(cubic, 1.2, 1.8), [1, 2, 3, 4]);
});

test('moving a point changes the curve only on that point\'s span, and leaves the original alone', () => {
  const moved = withPoints(cubic, new Map([[0, [0, 9, 0]]]));
  assert.deepEqual(cubic.coef[0], [0, 0, 0]);
  assert.deepEqual(moved.coef[0], [0, 9, 0]);
  assert.equal(moved.coef[1], cubic.coef[1]);
  const [before, after] = [valuesAt(cubic, [1.5, 0.5]), valuesAt(moved, [1.5, 0.5])];
  assert.deepEqual([...after.subarray(0, 3)], [...before.subarray(0, 3)]);   // point 0 acts on (0, 1) only
  assert.notDeepEqual([...after.subarray(3, 6)], [...before.subarray(3, 6)]);
});

test('ghost times step whole frames from the playhead\'s frame, nearest first', () => {
  const { before, after } = ghostTimes(1.01, 24, 3, 4);
  assert.deepEqual(before.map((t) => Math.round(t * 24)), [20, 16, 12]);
  assert.deepEqual(after.map((t) => Math.round(t * 24)), [28, 32, 36]);
  assert.deepEqual(ghostTimes(0, 25, 0, 4), { before: [], after: [] });
});
