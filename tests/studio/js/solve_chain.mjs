// @ts-check
// Reads a dump written by tests/motion/test_ik.py (cases of a chain and its goals at ticks)
// and prints the page's poses of each (ik.js solve), for the test to compare with the model's.
// Not a node --test file: pytest runs it with the dump's path.
import { readFileSync } from 'node:fs';
import { solve } from '../../../src/sketchanim/studio/web/js/ik.js';

/** @typedef {{lengths: number[], limits: number[], hinges: boolean[], goals: number[]}} Case */
const dump = /** @type {{cases: Case[]}} */ (JSON.parse(readFileSync(process.argv[2], 'utf8')));
const poses = dump.cases.map((c) => Array.from(solve({ lengths: c.lengths, limits: c.limits, hinges: c.hinges }, c.goals)));
process.stdout.write(JSON.stringify({ poses }));
