// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { loopPasses, spanText, takeName } from '../../../src/sketchanim/studio/web/js/layers.js';

/** @param {Partial<import('../../../src/sketchanim/studio/web/js/messages.js').TakeSpanInfo>} t */
const take = (t) => ({ start: 0, end: 1, mode: 'replace', n: 10, smoothing: 0, ...t });

test('a take is called by its name, else by its place from 1', () => {
  assert.equal(takeName(take({ name: 'wobble' }), 0), 'wobble');
  assert.equal(takeName(take({ name: '' }), 4), 'take 5');
});

test('a span reads in frames at the project frame rate and in seconds', () => {
  assert.equal(spanText(take({ start: 1, end: 1.97 }), 24), 'f 24–47 · 1.00–1.97 s');
  assert.equal(spanText(take({ start: 1, end: 2 }), 29.97), 'f 30–60 · 1.00–2.00 s');
});

test('passes of one loop recording are numbered among themselves, a pass of several takes once', () => {
  const takes = [take({}), take({ loop: 'a', loop_pass: 0 }), take({ loop: 'b', loop_pass: 0 }), take({ loop: 'a', loop_pass: 1 }),
    take({ loop: null }), take({ loop: 'a', loop_pass: 1 }), take({ loop: 'a', loop_pass: 3 })];
  const passes = loopPasses(takes);
  assert.deepEqual([...passes.entries()].sort((x, y) => x[0] - y[0]), [
    [1, { pass: 1, of: 3, first: true }], [2, { pass: 1, of: 1, first: true }], [3, { pass: 2, of: 3, first: false }],
    [5, { pass: 2, of: 3, first: false }], [6, { pass: 3, of: 3, first: false }]]);
});
