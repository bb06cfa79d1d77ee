// @ts-check
// The page's side of benchmarks/bench_walk.py: reads a JSON of cases (name, marker rows at
// 120 Hz) and prints, as JSON, each case's time per tick of one walker (advance, ms) and
// the page's per-frame costs for `walkers` walkers: live (each advancing the ticks of a
// 60 Hz frame, then its joints' world positions), playback from walks computed once
// (one frame's rotations copied and its world positions), and one walker's whole path
// re-simulated (what an edit of its goal costs).
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { RATE, humanoid, start, advance, walk, worldPoints } from '../src/sketchanim/studio/web/js/walk.js';

const input = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const figure = humanoid(1.75);
const J = figure.names.length;
/** @param {number[][]} rows */
const flat = (rows) => new Float64Array(rows.flat());

/** @type {Record<string, number[]>} */
const perTick = {};
for (const c of input.cases) {
  const m = flat(c.markers);
  for (let warm = 0; warm < 2; warm++) walk(figure, m);
  let s = start(figure, m.subarray(0, 3));
  const out = [];
  for (let k = 1; k < m.length / 3; k++) {
    const t0 = performance.now();
    s = advance(s, m.subarray(k * 3, k * 3 + 3));
    out.push(performance.now() - t0);
  }
  perTick[c.name] = out;
}

const paths = input.walkers.map(flat);
const ticksPerFrame = Math.round(RATE / 60);
let states = paths.map((/** @type {Float64Array} */ m) => start(figure, m.subarray(0, 3)));
const live = [];
const frames = Math.floor((paths[0].length / 3 - 1) / ticksPerFrame);
for (let f = 0; f < frames; f++) {
  const t0 = performance.now();
  states = states.map((/** @type {import('../src/sketchanim/studio/web/js/walk.js').WalkState} */ s, /** @type {number} */ i) => {
    for (let k = 0; k < ticksPerFrame; k++) {
      const at = (s.tick + 1) * 3;
      s = advance(s, paths[i].subarray(at, at + 3));
    }
    worldPoints(figure, s.rotations, s.root);
    return s;
  });
  live.push(performance.now() - t0);
}

const t0 = performance.now();
const walks = paths.map((/** @type {Float64Array} */ m) => walk(figure, m));
const simulate = (performance.now() - t0) / paths.length;
const playback = [];
const rotations = new Float64Array(J * 4);
for (let f = 0; f < frames; f++) {
  const k = f * ticksPerFrame;
  const t1 = performance.now();
  for (const w of walks) {
    rotations.set(w.rotations.subarray(k * J * 4, (k + 1) * J * 4));
    worldPoints(figure, rotations, w.root.subarray(k * 3, k * 3 + 3));
  }
  playback.push(performance.now() - t1);
}
process.stdout.write(JSON.stringify({ perTick, live, playback, simulate, seconds: paths[0].length / 3 / RATE }));
