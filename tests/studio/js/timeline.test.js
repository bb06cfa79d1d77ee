// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { changes, hitTake, layoutRows, rowAt, scaleFactor, snapDelta, GROUP_HEIGHT, LANE_HEIGHT } from '../../../src/sketchanim/studio/web/js/timelinelanes.js';
import { beginDrag, dragTo, mapping, moved, released, selectedRange } from '../../../src/sketchanim/studio/web/js/retimehandles.js';

/** @typedef {import('../../../src/sketchanim/studio/web/js/messages.js').Track} Track */

/** @param {[number, number][]} spans @returns {Track} a curve with takes over `spans` */
const curve = (spans) => ({ path: 'box.position', kind: 'curve', dim: 3, order: 4, rotation: false, tol: 0.005,
  knots: [0, 0, 0, 0, 3, 3, 3, 3], coef: [[0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]], start: 0, end: 3,
  takes: spans.map(([start, end]) => ({ start, end, mode: 'replace', n: 10, smoothing: 0 })) });

const OBJECTS = [{ name: 'box', attributes: [{ name: 'position' }, { name: 'visible' }] },
  { name: 'cone', attributes: [{ name: 'position' }] }, { name: 'ball', attributes: [{ name: 'position' }] }];
const TRACKS = new Map(/** @type {[string, Track][]} */ ([['box.position', curve([[0, 3]])],
  ['box.visible', { path: 'box.visible', kind: 'steps', times: [0, 1], values: [true, false] }],
  ['ball.position', curve([[0, 3]])]]));

test('rows: a header per animated object, its lanes in attribute order; none for an object without tracks', () => {
  const rows = layoutRows(OBJECTS, TRACKS, new Set());
  assert.deepEqual(rows.map((r) => (r.kind === 'lane' ? r.path : `[${r.object}]`)),
    ['[box]', 'box.position', 'box.visible', '[ball]', 'ball.position']);
  assert.deepEqual(rows.map((r) => r.y), [0, GROUP_HEIGHT, GROUP_HEIGHT + LANE_HEIGHT, GROUP_HEIGHT + 2 * LANE_HEIGHT,
    2 * GROUP_HEIGHT + 2 * LANE_HEIGHT]);
  assert.equal(rowAt(rows, GROUP_HEIGHT + 1)?.kind, 'lane');
  assert.equal(rowAt(rows, 1e6), null);
});

test('a folded object keeps its header, with the count of its lanes, and none of them', () => {
  const rows = layoutRows(OBJECTS, TRACKS, new Set(['box']));
  assert.deepEqual(rows.map((r) => r.kind), ['group', 'group', 'lane']);
  const box = rows[0];
  assert.ok(box.kind === 'group' && box.folded && box.count === 2);
  assert.equal(rows[1].y, GROUP_HEIGHT);
});

test('a press hits the latest take there, its right edge the retime handle, else the lane', () => {
  const track = curve([[0, 3], [1, 2]]);
  assert.deepEqual(hitTake(track, 1.5, 0.01), { what: 'take', take: 1 });
  assert.deepEqual(hitTake(track, 1.98, 0.01), { what: 'scale', take: 1 });
  assert.deepEqual(hitTake(track, 0.5, 0.01), { what: 'take', take: 0 });
  assert.deepEqual(hitTake(track, 2.99, 0.01), { what: 'scale', take: 0 });
  assert.deepEqual(hitTake(track, 3.5, 0.01), { what: 'lane', take: -1 });
  assert.deepEqual(hitTake(/** @type {Track} */ (TRACKS.get('box.visible')), 0.5, 0.01), { what: 'lane', take: -1 });
});

test('snapping moves by whole frames; a stretch cannot turn a span around', () => {
  assert.equal(snapDelta(0.53, 24, true) * 24, 13);
  assert.equal(snapDelta(0.53, 24, false), 0.53);
  assert.equal(scaleFactor(1, 3, 5), 2);
  assert.equal(scaleFactor(1, 3, 0.5), null);
});

test('steps are drawn where the value changes', () => {
  assert.deepEqual(changes([0, 1, 2, 3], ['a', 'a', 'b', 'a']), [{ t: 0, value: 'a' }, { t: 2, value: 'b' }, { t: 3, value: 'a' }]);
});

test('a take dragged moves by whole frames, and its release is one take.edit shift', () => {
  const drag = dragTo(beginDrag('take', ['box.position'], 1, 1.5, 1, 2), 2.03, 24, true);
  assert.equal(drag.by * 24, 13);
  assert.equal(moved(drag, 1), 1 + 13 / 24);
  assert.deepEqual(released(drag), { type: 'take.edit', path: 'box.position', take: 1, op: 'shift', by: 13 / 24 });
  assert.equal(released(dragTo(drag, 1.5, 24, true)), null, 'back where it was: nothing is sent');
});

test("a take's handle stretches it about its start (or the pivot given), its new end on a frame", () => {
  const drag = dragTo(beginDrag('scale', ['box.position'], 0, 2, 1, 2), 3.01, 24, true);
  assert.deepEqual(released(drag), { type: 'take.edit', path: 'box.position', take: 0, op: 'scale', factor: 2, pivot: 1 });
  const about = dragTo(beginDrag('scale', ['box.position'], 0, 2, 1, 2, 0), 4, 24, false);
  assert.deepEqual(mapping(about), { factor: 2, pivot: 0, shift: 0 });
  assert.deepEqual(mapping(dragTo(about, -1, 24, false)), { factor: 1, pivot: 0, shift: 0 }, 'past the pivot: no stretch');
});

test('whole tracks move and stretch with track.retime; a range selection sends nothing', () => {
  const move = dragTo(beginDrag('track', ['a.x', 'b.x'], -1, 1, 0, 3), 1.5, 24, false);
  assert.deepEqual(released(move), { type: 'track.retime', paths: ['a.x', 'b.x'], shift: 0.5 });
  const stretch = dragTo(beginDrag('range-scale', ['a.x'], -1, 2, 1, 2), 2.5, 24, false);
  assert.deepEqual(released(stretch), { type: 'track.retime', paths: ['a.x'], factor: 1.5, pivot: 1 });
  const select = dragTo(beginDrag('select', ['a.x'], -1, 2, 2, 2), 1, 24, true);
  assert.deepEqual(selectedRange(select), [1, 2]);
  assert.equal(released(select), null);
  assert.equal(selectedRange(beginDrag('select', ['a.x'], -1, 2, 2, 2)), null);
});

test("Delete with a range selected in the timeline deletes the range, not the selected object", async () => {
  const { studio } = await import('./fake_studio.mjs');
  const { s, c } = studio();
  /** @type {string[]} */
  const commands = [];
  s.signals.on('command', (x) => commands.push(x));
  s.select('box');
  s.selectRange({ paths: ['box.position'], t0: 0.5, t1: 1 });
  s.deleteSelection();
  assert.deepEqual(commands, ['delete-range']);
  assert.equal(c.of('object.remove').length, 0);
  s.cutRange(['box.position'], 0.5, 1);
  s.copyRange('box.position', 0.5, 1);
  assert.deepEqual(c.of('track.cut'), [{ type: 'track.cut', paths: ['box.position'], t0: 0.5, t1: 1 }]);
  assert.deepEqual(c.of('track.copy'), [{ type: 'track.copy', path: 'box.position', t0: 0.5, t1: 1 }]);
  /** @type {any[]} */
  const pieces = [];
  s.signals.on('piece', (m) => pieces.push(m));
  const piece = { type: /** @type {'track.piece'} */ ('track.piece'), path: 'box.on', length: 1,
    piece: { path: 'box.on', kind: /** @type {'steps'} */ ('steps'), times: [0.5], values: [true] } };
  c.receive(piece);
  assert.deepEqual(pieces, [piece]);
  s.selectRange(null);
  s.deleteSelection();
  assert.equal(c.of('object.remove').length, 1, 'no range: the selected object goes');
});
