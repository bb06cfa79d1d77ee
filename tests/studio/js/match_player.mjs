// @ts-check
// Reads a dump written by tests/studio/test_studio_js.py (curves, times, Player.values at each
// time) and prints the largest difference between the page's evaluation and the model's.
// Not a node --test file: pytest runs it with the dump's path.
import { readFileSync } from 'node:fs';
import { pack, evaluate } from '../../../src/sketchanim/studio/web/js/evaluate.js';

const dump = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const packed = pack(dump.curves);
let worst = 0;
dump.times.forEach((/** @type {number} */ t, /** @type {number} */ i) => {
  const out = evaluate(packed, t);
  const want = dump.values[i];
  if (want.length !== out.length) throw new Error(`time ${t}: ${out.length} values, the model has ${want.length}`);
  for (let c = 0; c < out.length; c++) worst = Math.max(worst, Math.abs(out[c] - want[c]));
});
process.stdout.write(JSON.stringify({ worst, paths: packed.paths }));
