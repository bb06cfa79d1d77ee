// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import * as ik from '../../../src/sketchanim/studio/web/js/ik.js';
import * as walk from '../../../src/sketchanim/studio/web/js/walk.js';
import { valuesAt } from '../../../src/sketchanim/studio/web/js/evaluate.js';
import { LEAD, RATE, Rigs, chainMotion, changedFrom, goalSampler, slerp } from '../../../src/sketchanim/studio/web/js/rigs.js';

const LENGTHS = [0.5, 0.4, 0.3, 0.25, 0.2, 0, 0, 0];
const LIMITS = Array(8).fill(150);
const HINGES = [0, 1, 1, 1, 0, 0, 0, 0];

/** A cubic goal path over [0, 2] s: a sweep in front of the chain, rising and falling. */
const GOAL = { path: 'arm.goal', order: 4, knots: [0, 0, 0, 0, 0.7, 1.3, 2, 2, 2, 2],
  coef: [[0.5, 1.1, 0], [0.8, 1.2, 0.3], [0.2, 1.4, 0.6], [-0.4, 0.9, 0.4], [-0.6, 0.6, 0], [-0.3, 0.8, -0.3]] };
/** A walker's marker on the floor over [0, 3] s: a curve of about 3 m. */
const MARKER = { path: 'bob.goal', order: 4, knots: [0, 0, 0, 0, 1, 2, 3, 3, 3, 3],
  coef: [[0, 0, 0], [0.3, 0, 0.2], [1, 0, 0.9], [1.6, 0, 1.8], [2.2, 0, 2], [2.5, 0, 2.2]] };

/**
 * A page of rigs: values and curves by path, and the paths performed live.
 * @param {Record<string, any>} values
 * @param {Record<string, any>} curves
 */
function pageOf(values, curves = {}) {
  const live = new Set();
  const scene = {
    curveOf: (/** @type {string} */ p) => curves[p] ?? null,
    valueOf: (/** @type {string} */ p) => values[p],
    live: (/** @type {string} */ p) => live.has(p),
  };
  return { rigs: new Rigs(scene), values, curves, live };
}

const chainValues = () => ({ 'arm.position': [0.2, 0, -0.1], 'arm.goal': [0.7, 1.1, -0.1], 'arm.lengths': LENGTHS, 'arm.limits': LIMITS, 'arm.hinges': HINGES });

/** The goals at ticks 0..n-1 of a curve less a base, as the caller of ik.solve samples them. */
/**
 * What the solver is given for ticks 0..n-1, as anim/rigs.py gives it: LEAD ticks on the goal at
 * time 0, then the goal at each tick (less the base); tick k is step LEAD + k.
 * @param {import("../../../src/sketchanim/studio/web/js/evaluate.js").Curve} curve
 * @param {number} n
 * @param {number[]} [base]
 */
function sampled(curve, n, base = [0, 0, 0]) {
  const v = valuesAt(curve, Float64Array.from({ length: LEAD + n }, (_, j) => Math.max(j - LEAD, 0) / RATE));
  for (let i = 0; i < v.length; i++) v[i] -= base[i % 3];
  return v;
}

/** @param {ArrayLike<number>} a @param {ArrayLike<number>} b */
function maxDiff(a, b) {
  assert.equal(a.length, b.length);
  let m = 0;
  for (let i = 0; i < a.length; i++) m = Math.max(m, Math.abs(a[i] - b[i]));
  return m;
}

test('a chain\'s pose on the ticks is ik.solve\'s on the goal sampled there, less the base', () => {
  const { rigs } = pageOf(chainValues(), { 'arm.goal': GOAL });
  rigs.keep([{ name: 'arm', kind: 'chain' }]);
  const n = Math.round(2.5 * RATE);           // past the curve's end: the goal held
  const chain = ik.chainFromSlots(LENGTHS, LIMITS, HINGES);
  const solved = ik.solve(chain, sampled(GOAL, n, [0.2, 0, -0.1]));
  const J = chain.lengths.length * 4;
  for (const k of [0, 1, 7, 119, 120, 241, n - 1]) {
    const pose = /** @type {import('../../../src/sketchanim/studio/web/js/rigs.js').Pose} */ (rigs.poseAt('arm', k / RATE, 0));
    assert.equal(pose.root, null);
    assert.ok(maxDiff(pose.rotations, solved.subarray((LEAD + k) * J, (LEAD + k + 1) * J)) <= 1e-12, `tick ${k}`);
  }
});

test('between ticks the pose is continuous: it goes from one tick\'s to the next', () => {
  const { rigs } = pageOf(chainValues(), { 'arm.goal': GOAL });
  rigs.keep([{ name: 'arm', kind: 'chain' }]);
  const k = 90;
  const a = /** @type {any} */ (rigs.poseAt('arm', k / RATE, 0)).rotations;
  const b = /** @type {any} */ (rigs.poseAt('arm', (k + 1) / RATE, 0)).rotations;
  let previous = a;
  for (let i = 1; i <= 10; i++) {
    const mid = /** @type {any} */ (rigs.poseAt('arm', (k + i / 10) / RATE, 0)).rotations;
    assert.ok(maxDiff(mid, previous) <= maxDiff(a, b) / 5 + 1e-12, `a jump between ${i - 1}/10 and ${i}/10 of a tick`);
    for (let o = 0; o < mid.length; o += 4) assert.ok(Math.abs(Math.hypot(...mid.subarray(o, o + 4)) - 1) < 1e-12);
    previous = mid;
  }
  assert.ok(maxDiff(previous, b) <= 1e-9);
});

test('slerp: the ends, the middle, the short way round', () => {
  const out = new Float64Array(4);
  const q = [0, Math.sin(0.4), 0, Math.cos(0.4)];
  slerp([0, 0, 0, 1], 0, q, 0, 0, out, 0);
  assert.ok(maxDiff(out, [0, 0, 0, 1]) < 1e-15);
  slerp([0, 0, 0, 1], 0, q, 0, 1, out, 0);
  assert.ok(maxDiff(out, q) < 1e-15);
  slerp([0, 0, 0, 1], 0, q, 0, 0.5, out, 0);
  assert.ok(maxDiff(out, [0, Math.sin(0.2), 0, Math.cos(0.2)]) < 1e-15);
  slerp([0, 0, 0, 1], 0, q.map((x) => -x), 0, 0.5, out, 0);          // -q is q: half way is the same rotation
  assert.ok(maxDiff(out, [0, Math.sin(0.2), 0, Math.cos(0.2)]) < 1e-15);
});

test('the cache grows as playback passes its end, and goes when the curve, the base or a length changes', () => {
  const page = pageOf(chainValues(), { 'arm.goal': GOAL });
  const { rigs } = page;
  rigs.keep([{ name: 'arm', kind: 'chain' }]);
  rigs.poseAt('arm', 0.1, 0);
  const rig = /** @type {any} */ (rigs.rigs.get('arm'));
  const cache = rig.cache;
  assert.ok(cache.count >= 13 && cache.count < 13 + RATE / 2, `${cache.count} ticks cached for 0.1 s`);
  rigs.poseAt('arm', 1.0, 0);
  assert.equal(rig.cache, cache);
  assert.ok(cache.count >= RATE + 2);
  const before = /** @type {any} */ (rigs.poseAt('arm', 1.0, 0)).rotations;
  page.curves['arm.goal'] = { ...GOAL, coef: GOAL.coef.map((r) => [r[0], r[1] - 0.3, r[2]]) };
  const moved = /** @type {any} */ (rigs.poseAt('arm', 1.0, 0)).rotations;
  assert.notEqual(rig.cache, cache);
  assert.ok(maxDiff(before, moved) > 1e-3, 'a new goal curve left the pose');
  const c2 = rig.cache;
  page.values['arm.position'] = [0.2, 0.1, -0.1];
  rigs.poseAt('arm', 1.0, 0);
  assert.notEqual(rig.cache, c2);
  const c3 = rig.cache;
  page.values['arm.lengths'] = [0.5, 0.4, 0.3, 0, 0, 0, 0, 0];
  assert.equal(/** @type {any} */ (rigs.poseAt('arm', 1.0, 0)).rotations.length, 12);
  assert.notEqual(rig.cache, c3);
  page.values['arm.lengths'] = [0.5, 0, 0, 0, 0, 0, 0, 0];           // one segment: no chain
  assert.equal(rigs.poseAt('arm', 1.0, 0), null);
  assert.match(rig.error, /./);
});

test('a goal without a curve: held from LEAD ticks before 0, the chain on it at time 0', () => {
  const values = chainValues();
  const { rigs } = pageOf(values);
  rigs.keep([{ name: 'arm', kind: 'chain' }]);
  const chain = ik.chainFromSlots(LENGTHS, LIMITS, HINGES);
  const n = 20 * RATE;
  const goals = new Float64Array((LEAD + n) * 3);
  for (let j = 0; j < LEAD + n; j++) goals.set([0.5, 1.1, 0], j * 3);
  const J = chain.lengths.length * 4;
  const solved = ik.solve(chain, goals);
  for (const k of [0, 156, n - 1]) {
    const pose = /** @type {any} */ (rigs.poseAt('arm', k / RATE, 0)).rotations;
    assert.ok(maxDiff(pose, solved.subarray((LEAD + k) * J, (LEAD + k + 1) * J)) <= 1e-12, `tick ${k}`);
  }
  const tip = ik.points(chain, /** @type {any} */ (rigs.poseAt('arm', 0, 0)).rotations).slice(-3);
  assert.ok(Math.hypot(tip[0] - 0.5, tip[1] - 1.1, tip[2]) < 1e-3, `the tip is not on its goal at 0: ${tip}`);
});

test('a walker\'s pose on the ticks is walk.walk\'s on its marker sampled there; its root lerps', () => {
  const { rigs } = pageOf({ 'bob.goal': [0, 0, 0], 'bob.height': [1.75] }, { 'bob.goal': MARKER });
  rigs.keep([{ name: 'bob', kind: 'walker' }]);
  const n = Math.round(3.2 * RATE);
  const skeleton = walk.humanoid(1.75);
  const walked = walk.walk(skeleton, sampled(MARKER, n));
  const J = skeleton.names.length * 4;
  for (const k of [0, 1, 100, 250, n - 2]) {
    const pose = /** @type {any} */ (rigs.poseAt('bob', k / RATE, 0));
    assert.ok(maxDiff(pose.rotations, walked.rotations.subarray((LEAD + k) * J, (LEAD + k + 1) * J)) <= 1e-12, `tick ${k}`);
    assert.ok(maxDiff(pose.root, walked.root.subarray((LEAD + k) * 3, (LEAD + k) * 3 + 3)) <= 1e-12, `root at tick ${k}`);
  }
  const mid = /** @type {any} */ (rigs.poseAt('bob', 100.25 / RATE, 0)).root;
  const at = (LEAD + 100) * 3;
  const lerp = [0, 1, 2].map((c) => 0.75 * walked.root[at + c] + 0.25 * walked.root[at + 3 + c]);
  assert.ok(maxDiff(mid, lerp) <= 1e-12);
  assert.deepEqual(walked.behind, []);
  assert.deepEqual(rigs.behindUntil('bob', (n - 1) / RATE), []);
});

test('live: the figure steps from the pose shown toward the live goal, one step a tick, the goal interpolated', () => {
  const page = pageOf(chainValues(), { 'arm.goal': GOAL });
  const { rigs } = page;
  rigs.keep([{ name: 'arm', kind: 'chain' }]);
  const t = 0.5;
  const k = Math.floor(t * RATE);
  rigs.poseAt('arm', t, 1000);
  const motion = chainMotion(LENGTHS, LIMITS, HINGES);
  const goals = sampled(GOAL, k + 1, [0.2, 0, -0.1]);
  const K = LEAD + k;                                   // tick k's step
  page.live.add('arm.goal');
  page.values['arm.goal'] = [0.9, 0.6, 0.2];          // the hand moved: 100 ms is 12 ticks
  const first = /** @type {any} */ (rigs.poseAt('arm', t, 1000));       // the first live frame: no time passed
  let state = motion.first(goals.subarray(0, 3));
  for (let i = 1; i <= K; i++) state = motion.next(state, goals.subarray(i * 3, i * 3 + 3));
  assert.ok(maxDiff(first.rotations, state.pose) <= 1e-12, 'the live figure starts from the pose of its tick');
  const shown = /** @type {any} */ (rigs.poseAt('arm', t + 0.1, 1100));
  const from = goals.subarray(K * 3, K * 3 + 3);
  const to = [0.7, 0.6, 0.3];
  for (let i = 1; i <= 12; i++) state = motion.next(state, Float64Array.from([0, 1, 2], (c) => from[c] + ((to[c] - from[c]) * i) / 12));
  assert.ok(maxDiff(shown.rotations, state.pose) <= 1e-12);
  const rest = /** @type {any} */ (rigs.poseAt('arm', t + 0.1, 1104));  // half a tick: no step yet
  assert.deepEqual([...rest.rotations], [...shown.rotations]);
  page.live.delete('arm.goal');
  const played = /** @type {any} */ (rigs.poseAt('arm', t, 1200));
  assert.ok(maxDiff(played.rotations, first.rotations) <= 1e-9, 'released: the curve\'s pose again');
});

test('goal sampler: a constant less a base curve', () => {
  const base = { path: 'arm.position', order: 2, knots: [0, 0, 1, 1], coef: [[0, 0, 0], [1, 0, 0]] };
  const at = goalSampler([1, 1, 1], base);
  assert.deepEqual([...at(RATE / 2, new Float64Array(3))], [0.5, 1, 1]);
});

test('a marker faster than the fastest run: the spans behind are walk.walk\'s', () => {
  // 14 m in 1.2 s (11.7 m/s), then held: the walker falls behind, and catches up after
  const dash = { path: 'bob.goal', order: 2, knots: [0, 0, 0.5, 1.7, 1.7], coef: [[0, 0, 0], [0, 0, 0], [14, 0, 0]] };
  const { rigs } = pageOf({ 'bob.goal': [0, 0, 0], 'bob.height': [1.75] }, { 'bob.goal': dash });
  rigs.keep([{ name: 'bob', kind: 'walker' }]);
  const spans = /** @type {[number, number, number][]} */ (rigs.behindUntil('bob', 8));
  const count = /** @type {any} */ (rigs.rigs.get('bob')).cache.count;
  const walked = walk.walk(walk.humanoid(1.75), sampled(dash, count));
  assert.ok(walked.behind.length >= 1, 'the dash did not outrun the walker');
  assert.equal(spans.length, walked.behind.length);          // walk's times count from the lead's start
  spans.forEach((span, i) => assert.ok(maxDiff(span, walked.behind[i].map((x, c) => (c < 2 ? x - LEAD / RATE : x))) < 1e-12));
  assert.ok(spans[0][0] > 0.5 && spans[0][0] < 1.7 && spans[0][2] > 11, JSON.stringify(spans));
});

test('a later control point moved: the ticks before it are kept, the rest solved again, as a fresh solve', () => {
  const page = pageOf(chainValues(), { 'arm.goal': GOAL });
  const { rigs } = page;
  rigs.keep([{ name: 'arm', kind: 'chain' }]);
  rigs.poseAt('arm', 1.9, 0);
  const before = /** @type {any} */ (rigs.rigs.get('arm')).cache;
  const moved = { ...GOAL, coef: GOAL.coef.map((r, i) => (i === 4 ? [r[0], r[1] + 0.4, r[2]] : r)) };   // acts from 0.7 s
  assert.equal(changedFrom(GOAL, moved), 0.7);
  page.curves['arm.goal'] = moved;
  const at = /** @type {any} */ (rigs.poseAt('arm', 1.9, 0));
  const after = /** @type {any} */ (rigs.rigs.get('arm')).cache;
  assert.notEqual(after, before);
  assert.equal(after.rotations[LEAD + RATE / 2], before.rotations[LEAD + RATE / 2], 'a tick before the change was solved again');
  assert.notEqual(after.rotations[LEAD + RATE], before.rotations[LEAD + RATE]);
  const n = Math.round(1.9 * RATE) + 1;
  const chain = ik.chainFromSlots(LENGTHS, LIMITS, HINGES);
  const solved = ik.solve(chain, sampled(moved, n, [0.2, 0, -0.1]));
  const J = chain.lengths.length * 4;
  assert.ok(maxDiff(at.rotations, solved.subarray((LEAD + n - 1) * J, (LEAD + n) * J)) <= 1e-12);
  for (const k of [0, 59, 83, 84, 120, 200]) {
    assert.ok(maxDiff(after.rotations[LEAD + k], solved.subarray((LEAD + k) * J, (LEAD + k + 1) * J)) <= 1e-12, `tick ${k}`);
  }
  assert.equal(changedFrom(GOAL, { ...GOAL, coef: GOAL.coef.map((r, i) => (i === 1 ? [9, 9, 9] : r)) }), -Infinity);  // acts from the start
  assert.equal(changedFrom(GOAL, GOAL), Infinity);
});

test('a walker\'s kept ticks keep its behind spans; the walk goes on as walk.walk', () => {
  const dash = { path: 'bob.goal', order: 2, knots: [0, 0, 0.5, 1.7, 4, 4], coef: [[0, 0, 0], [0, 0, 0], [14, 0, 0], [14, 0, 2]] };
  const page = pageOf({ 'bob.goal': [0, 0, 0], 'bob.height': [1.75] }, { 'bob.goal': dash });
  const { rigs } = page;
  rigs.keep([{ name: 'bob', kind: 'walker' }]);
  rigs.behindUntil('bob', 5);
  const moved = { ...dash, coef: [...dash.coef.slice(0, 3), [12, 0, -2]] };                 // acts from 1.7 s
  page.curves['bob.goal'] = moved;
  const spans = /** @type {[number, number, number][]} */ (rigs.behindUntil('bob', 5));
  const cache = /** @type {any} */ (rigs.rigs.get('bob')).cache;
  const walked = walk.walk(walk.humanoid(1.75), sampled(moved, cache.count));
  assert.ok(spans.length === walked.behind.length && spans.length >= 1);
  spans.forEach((span, i) => assert.ok(maxDiff(span, walked.behind[i].map((x, c) => (c < 2 ? x - LEAD / RATE : x))) < 1e-12));
  const J = walk.humanoid(1.75).names.length * 4;
  for (const k of [0, 200, 203, 204, 400, cache.count - 1]) {
    assert.ok(maxDiff(cache.rotations[LEAD + k], walked.rotations.subarray((LEAD + k) * J, (LEAD + k + 1) * J)) <= 1e-12, `tick ${k}`);
  }
});
