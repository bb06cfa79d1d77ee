// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { RATE, RV_FASTEST, humanoid, rig, gait, start, advance, walk, worldPoints } from '../../../src/sketchanim/studio/web/js/walk.js';

const FIGURE = humanoid(1.75);
const J = FIGURE.names.length;

/**
 * Standing `rest` s, then along +z at `speed` m/s, easing in over 0.5 s (as tests/walk_paths.py's straight).
 * @param {number} speed
 * @param {number} seconds
 * @param {number} [rest]
 */
function straight(speed, seconds, rest = 0.5) {
  const n = Math.round(seconds * RATE);
  const out = new Float64Array(n * 3);
  let z = 0;
  for (let k = 0; k < n; k++) {
    z += speed * Math.min(Math.max((k / RATE - rest) / 0.5, 0), 1) / RATE;
    out[k * 3 + 2] = z;
  }
  return out;
}

/** @param {number[]} a */
const median = (a) => { const s = [...a].sort((x, y) => x - y); return s.length ? s[Math.floor(s.length / 2)] : 0; };

/**
 * Each toe's speeds (m/s) at 60 Hz inside stance spans, and each foot's lift ticks.
 * @param {import('../../../src/sketchanim/studio/web/js/walk.js').Walk} w
 */
function measure(w) {
  const points = worldPoints(FIGURE, w.rotations, w.root);
  const n = w.root.length / 3;
  const toes = [FIGURE.names.indexOf('l_toe'), FIGURE.names.indexOf('r_toe')];
  return [0, 1].map((side) => {
    /** @type {number[]} */
    const speeds = [];
    /** @type {number[]} */
    const lifts = [];
    for (let k = 0; k + 2 < n; k += 2) {
      if (w.stance[k * 2 + side] && w.stance[(k + 1) * 2 + side] && w.stance[(k + 2) * 2 + side]) {
        const a = (k * J + toes[side]) * 3, b = ((k + 2) * J + toes[side]) * 3;
        speeds.push(Math.hypot(points[b] - points[a], points[b + 1] - points[a + 1], points[b + 2] - points[a + 2]) * 60);
      }
    }
    for (let k = 1; k < n; k++) if (w.stance[(k - 1) * 2 + side] && !w.stance[k * 2 + side]) lifts.push(k);
    return { speeds, lifts };
  });
}

test('the humanoid stands on its toes, its offsets [x, y, z] per joint', () => {
  assert.equal(J, 21);
  assert.equal(FIGURE.names[0], 'hips');
  const rest = worldPoints(FIGURE, new Float64Array(J * 4).map((_, i) => (i % 4 === 3 ? 1 : 0)), new Float64Array(FIGURE.offsets[0]));
  const toe = FIGURE.names.indexOf('l_toe');
  assert.ok(Math.abs(rest[toe * 3 + 1]) < 1e-12);
  for (let j = 0; j < J; j++) assert.ok(rest[j * 3 + 1] >= -1e-12);
  assert.ok(Math.abs(rig(FIGURE).leg - 0.53 * 1.75) < 1e-12);
});

test('worldPoints is world = parent * local, local = T(offset) R(rotation)', () => {
  const s = { names: ['a', 'b', 'c'], parents: [-1, 0, 1], offsets: /** @type {[number, number, number][]} */ ([[0, 0, 0], [1, 0, 0], [1, 0, 0]]) };
  const h = Math.SQRT1_2;
  const q = new Float64Array([0, 0, h, h, 0, 0, h, h, 0, 0, 0, 1]);    // a quarter turn about z at a and at b
  const p = worldPoints(s, q, new Float64Array([0, 0, 5]));
  assert.deepEqual(Array.from(p).map((v) => Math.round(v * 1e12) / 1e12 + 0), [0, 0, 5, 0, 1, 5, -1, 1, 5]);
});

test('a straight walk keeps planted toes still, at Boulic\'s cadence', () => {
  const v = 1.4;
  const w = walk(FIGURE, straight(v, 8));
  const g = gait(v, rig(FIGURE).leg);
  for (const { speeds, lifts } of measure(w)) {
    assert.ok(median(speeds) <= 0.02, `median toe slide ${median(speeds)}`);
    const steady = lifts.filter((k) => k > 3 * RATE);
    const beats = steady.slice(1).map((k, i) => (k - steady[i]) / RATE);
    assert.ok(Math.abs(median(beats) / g.cycle - 1) < 0.03, `cycle ${median(beats)} vs ${g.cycle}`);
  }
  assert.deepEqual(w.behind, []);
});

test('start then advance tick by tick is walk', () => {
  const path = straight(1.1, 3);
  const w = walk(FIGURE, path);
  let s = start(FIGURE, path.subarray(0, 3));
  for (let k = 1; k < path.length / 3; k++) s = advance(s, path.subarray(k * 3, k * 3 + 3));
  assert.deepEqual(Array.from(s.rotations), Array.from(w.rotations.subarray(w.rotations.length - J * 4)));
  assert.deepEqual(Array.from(s.root), Array.from(w.root.subarray(w.root.length - 3)));
});

test('standing still: both feet planted, no step, the pose unchanged', () => {
  const w = walk(FIGURE, new Float64Array(3 * 240).map((_, i) => (i % 3 === 1 ? 0.2 : 0)));
  assert.ok(w.stance.every((x) => x === 1));
  assert.deepEqual(Array.from(w.rotations.subarray(0, J * 4)), Array.from(w.rotations.subarray(w.rotations.length - J * 4)));
});

test('a path faster than the fastest run: behind says so and the toes still hold', () => {
  const w = walk(FIGURE, straight(9.5, 4));
  assert.equal(w.behind.length, 1);
  const [begin, end, speed] = w.behind[0];
  assert.ok(begin > 0.5 && begin < 1.0 && Math.abs(end - (w.root.length / 3 - 1) / RATE) < 1e-12);
  assert.ok(Math.abs(speed - 9.5) < 1e-6);
  for (const { speeds } of measure(w)) assert.ok(median(speeds) <= 0.02);
  const fastest = RV_FASTEST * rig(FIGURE).leg;
  for (let k = 1; k < w.root.length / 3; k++) {
    const d = Math.hypot(w.root[k * 3] - w.root[k * 3 - 3], w.root[k * 3 + 2] - w.root[k * 3 - 1]) * RATE;
    assert.ok(d <= fastest * (1 + 1e-9));
  }
});

test('bad input throws, naming the field', () => {
  assert.throws(() => humanoid(-1), /height/);
  assert.throws(() => walk(FIGURE, new Float64Array(4)), /markers/);
  assert.throws(() => advance(start(FIGURE, [0, 0, 0]), [0, NaN, 0]), /marker/);
  assert.throws(() => walk({ names: ['hips'], parents: [-1], offsets: [[0, 0, 0]] }, new Float64Array(3)), /joint/);
});
