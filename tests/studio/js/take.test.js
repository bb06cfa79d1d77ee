// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { TakeSampler } from '../../../src/sketchanim/studio/web/js/take.js';

test('samples go out in batches, each once, in order', () => {
  const take = new TakeSampler('t1', ['box.position', 'box.orientation'], [3, 4], 50);
  const row = [0, 0, 0, 0, 0, 0, 1];
  assert.ok(take.add(0, row, 0));
  assert.equal(take.batch(10), null);              // not due yet
  assert.ok(take.add(1 / 60, row, 16.7));
  const b = take.batch(60);
  assert.deepEqual(b?.t, [0, 1 / 60]);
  assert.equal(b?.take, 't1');
  assert.equal(take.batch(200, true), null);       // nothing left
  take.add(2 / 60, row, 33);
  assert.deepEqual(take.batch(34, true)?.t, [2 / 60]);
});

test('samples that do not move forward in time, are the wrong width or not finite are refused', () => {
  const take = new TakeSampler('t', ['lamp.intensity'], [1]);
  assert.ok(take.add(1, [1], 0));
  assert.equal(take.add(1, [2], 1), false);
  assert.equal(take.add(0.5, [2], 2), false);
  assert.equal(take.add(2, [NaN], 3), false);
  assert.equal(take.add(2, [1, 2], 3), false);
  assert.equal(take.dropped, 4);
  assert.equal(take.last, 1);
});

test('one path of a row', () => {
  const take = new TakeSampler('t', ['a.position', 'a.scale'], [3, 3]);
  take.add(0, [1, 2, 3, 4, 5, 6], 0);
  assert.deepEqual(take.channel('a.scale').values, [[4, 5, 6]]);
  assert.deepEqual(take.channel('nope').values, []);
});
