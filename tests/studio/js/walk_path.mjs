// @ts-check
// Reads a dump written by tests/motion/test_walk.py (a humanoid's height and the marker at
// each tick, n x 3) and prints the page's walk of it as JSON (rotations n * J * 4, root n * 3,
// stance n * 2, behind). Not a node --test file: pytest runs it with the dump's path.
import { readFileSync } from 'node:fs';
import { humanoid, walk } from '../../../src/sketchanim/studio/web/js/walk.js';

const dump = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const out = walk(humanoid(dump.height), new Float64Array(dump.markers.flat()));
process.stdout.write(JSON.stringify({ rotations: Array.from(out.rotations), root: Array.from(out.root),
  stance: Array.from(out.stance), behind: out.behind }));
