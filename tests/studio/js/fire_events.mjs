// @ts-check
// Reads cases written by tests/studio/test_events_fire.py (event times, a loop range or
// null, a speed, the start time and the frames' ms), plays each on the page's Clock,
// firing what events.js says each frame passed, and prints the times fired per case.
// Not a node --test file.
import { readFileSync } from 'node:fs';
import { Clock } from '../../../src/sketchanim/studio/web/js/clock.js';
import { cuesOf, passed } from '../../../src/sketchanim/studio/web/js/events.js';

const cases = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const out = cases.map((/** @type {any} */ c) => {
  const cues = cuesOf([{ path: 'box.cue', times: c.events, values: c.events.map(() => null) }]);
  const clock = new Clock();
  clock.loop = c.loop;
  clock.setSpeed(c.speed, 0);
  clock.seek(c.start, 0);
  clock.play(0);
  let now = 0;
  let at = c.start;
  /** @type {number[]} */
  const fired = [];
  for (const ms of c.frames) {
    now += ms;
    const { time, laps } = clock.tick(now);
    for (const e of passed(cues, at, time, c.speed, c.loop, laps)) fired.push(e.time);
    at = time;
  }
  return fired;
});
process.stdout.write(JSON.stringify(out));
