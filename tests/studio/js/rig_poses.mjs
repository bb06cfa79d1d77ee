// @ts-check
// Reads a dump written by tests/studio/test_rig_poses.py (a rig's structure, its goal's and a
// chain's base's curves or values, times) and prints the page's pose of the rig at each time, as
// rigs.js computes it for the viewport (PoseCache.at). Not a node --test file: pytest runs it.
import { readFileSync } from 'node:fs';
import { chainMotion, goalSampler, PoseCache, walkerMotion } from '../../../src/sketchanim/studio/web/js/rigs.js';

const dump = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const motion = dump.kind === 'chain' ? chainMotion(dump.lengths, dump.limits, dump.hinges) : walkerMotion(dump.height);
const cache = new PoseCache(motion, goalSampler(dump.goal, dump.base));
const out = dump.times.map((/** @type {number} */ t) => {
  const pose = cache.at(t);
  return { rotations: Array.from(pose.rotations), root: pose.root ? Array.from(pose.root) : null };
});
process.stdout.write(JSON.stringify(out));
