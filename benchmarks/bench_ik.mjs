// @ts-check
// The page's chain IK timed in node for benchmarks/bench_ik.py: reads a JSON file of cases
// ({chains: [{lengths, limits, hinges}], goals: [...] ticks * 3, repeats}) and prints, for each
// chain, the seconds (wall clock, and the process's CPU time) of every repeat of `solve` over
// the goals and the wall seconds of as many `step` calls (the page's live path, which prepares
// the chain each call), after one warm-up run of each.
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { solve, step, rest } from '../src/sketchanim/studio/web/js/ik.js';

const spec = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const goals = Float64Array.from(spec.goals);
const ticks = goals.length / 3;
const out = spec.chains.map((/** @type {import('../src/sketchanim/studio/web/js/ik.js').Chain} */ chain) => {
  const solves = [], cpus = [], steps = [];
  for (let r = 0; r <= spec.repeats; r++) {
    const cpu = process.cpuUsage();
    let clock = performance.now();
    solve(chain, goals);
    const solved = (performance.now() - clock) / 1e3;
    const used = process.cpuUsage(cpu);
    const cpuSolved = (used.user + used.system) / 1e6;
    let pose = rest(chain);
    clock = performance.now();
    for (let k = 0; k < ticks; k++) {
      const b = k === 0 ? 0 : 3 * (k - 1);
      pose = step(chain, pose, goals.subarray(3 * k, 3 * k + 3), goals.subarray(b, b + 3));
    }
    const stepped = (performance.now() - clock) / 1e3;
    if (r > 0) { solves.push(solved); cpus.push(cpuSolved); steps.push(stepped); }
  }
  return { solve: solves, cpu: cpus, step: steps };
});
process.stdout.write(JSON.stringify(out));
