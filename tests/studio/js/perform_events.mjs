// @ts-check
// Reads a script written by tests/studio/test_take_times.py (pointer events: ms after the
// hold and an x; frames: ms after the hold), performs it on a Studio in record mode (each
// frame: the events before it move the box and are marked, then the frame runs) and prints
// the take's samples: transport times, rows, clock stamps. Not a node --test file.
import { readFileSync } from 'node:fs';
import { Studio } from '../../../src/sketchanim/studio/web/js/Studio.js';

const script = JSON.parse(readFileSync(process.argv[2], 'utf8'));
/** @type {any[]} */
const sent = [];
const connection = { connected: true, send: (/** @type {any} */ m) => { sent.push(m); },
  connect: (/** @type {(m: any) => void} */ onMessage) => { connection.receive = onMessage; },
  receive: (/** @type {any} */ _m) => {} };
const studio = new Studio(connection);
const POSITION = { name: 'position', dim: 3, tol: 0.005, unit: 'scene units', default: [0, 0, 0], choices: [], continuous: true };
connection.receive({ type: 'state', ready: true, project: 'p', span: [0, 0], tracks: [], take: null, tolerances: {},
  history: { undo: [], redo: [], can_undo: false, can_redo: false }, transport: { time: 0, playing: false, speed: 1, loop: null },
  objects: [{ name: 'box', kind: 'object', attributes: [{ name: 'position', value: [0, 0.5, 0], type: POSITION }] }] });
studio.transport.setRecord(true);
studio.performer.hold(['box.position'], 'move box');
const t0 = studio.performer.grab?.lastEvent ?? 0;
let next = 0;
for (const frame of script.frames) {
  while (next < script.events.length && script.events[next][0] <= frame) {
    const [ms, x] = script.events[next++];
    studio.setLocal('box.position', [x, 0.5, 0]);
    studio.performer.mark(t0 + ms);
  }
  studio.frame(t0 + frame);
}
studio.performer.release();
const log = studio.takes.at(-1)?.sampler;
process.stdout.write(JSON.stringify({ t0, times: log?.times ?? [], rows: log?.rows ?? [], stamps: log?.stamps ?? [],
  begin: sent.find((m) => m.type === 'take.begin') }));
