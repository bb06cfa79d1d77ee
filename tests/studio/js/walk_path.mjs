// @ts-check
// Reads a dump written by tests/motion/test_walk.py (a humanoid's height and the marker at
// each tick, n x 3) and prints the page's walk of it as JSON (rotations n * J * 4, root n * 3,
// stance n * 2, behind, and worldPoints' joint positions n * J * 3). Not a node --test file: pytest runs it with the dump's path.
import { readFileSync } from 'node:fs';
import { humanoid, walk, worldPoints } from '../../../src/sketchanim/studio/web/js/walk.js';

const dump = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const figure = humanoid(dump.height);
const out = walk(figure, new Float64Array(dump.markers.flat()));
process.stdout.write(JSON.stringify({ rotations: Array.from(out.rotations), root: Array.from(out.root),
  stance: Array.from(out.stance), behind: out.behind,
  points: Array.from(worldPoints(figure, out.rotations, out.root)) }));
