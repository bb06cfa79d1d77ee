// @ts-check
// The page's state machine without a browser: a fake connection records what it sends.
import test from 'node:test';
import assert from 'node:assert/strict';
import { frames, studio } from './fake_studio.mjs';
import { renamedSelection } from '../../../src/sketchanim/studio/web/js/Studio.js';

test("a hold in record mode is a take: each event's values at the event's transport time, sent in batches", () => {
  const { s, c } = studio();
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 400);
  s.performer.release();
  const [begin] = c.of('take.begin');
  assert.deepEqual(begin.paths, ['box.position']);
  const t = c.of('take.samples').flatMap((m) => m.t);
  const x = c.of('take.samples').flatMap((m) => m.values.map((/** @type {number[]} */ r) => r[0]));
  assert.equal(t.length, 25);
  assert.ok(Math.abs(t[0] - (begin.time - 0.004)) < 1e-9, "the first event is 4 ms before the take's first frame");
  assert.ok(c.of('take.samples').length < 25, 'not one message per sample');
  t.slice(1).forEach((ti, i) => assert.ok(Math.abs(ti - t[i] - 0.016) < 1e-9));
  // each value at the time it was true: the box is at x = (frame ms) / 1000 from 4 ms before that frame
  x.forEach((xi, i) => assert.ok(Math.abs(xi - (t[i] - t[0] + 0.016)) < 1e-9));
  assert.equal(c.sent.at(-1).type, 'take.end');
});

test('a pointer at rest: the start of the rest and every frame after it are samples of the held values', () => {
  const { s, c } = studio();
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 96);                               // 6 events, the last at 92 ms
  for (let ms = 112; ms <= 208; ms += 16) s.frame(t0 + ms);   // still: frames at 112 (20 ms after), 128, ...
  s.performer.release();
  const t = c.of('take.samples').flatMap((m) => m.t);
  const x = c.of('take.samples').flatMap((m) => m.values.map((/** @type {number[]} */ r) => r[0]));
  const first = t[0];
  const rest = t.slice(6).map((ti) => Math.round((ti - first) * 1000));
  // 112 ms is 20 ms after the last event (not yet at rest); 128 ms: rest from 92 + 25 = 117 ms, then each frame
  assert.deepEqual(rest, [117 - 12, 128 - 12, 144 - 12, 160 - 12, 176 - 12, 192 - 12, 208 - 12]);
  assert.ok(x.slice(6).every((v) => v === 0.096));
  t.slice(1).forEach((ti, i) => assert.ok(ti > t[i]));
});

test('a take is sent with the tolerance its input resolves, or the one the animator set', () => {
  const { s, c } = studio();
  s.transport.setRecord(true);
  const resolve = () => ({ 'box.position': { step: 0.015, input: 'px' } });
  s.performer.hold(['box.position'], 'move box', null, resolve);
  frames(s, performance.now(), 16, 64);
  s.performer.release();
  assert.ok(Math.abs(c.of('take.begin')[0].tol['box.position'] - 0.03) < 1e-12);   // 2 px
  c.receive({ type: 'tolerances', tolerances: { 'box.position': { amount: 0.5, unit: 'units' } } });
  s.performer.hold(['box.position'], 'move box', null, resolve);
  frames(s, performance.now() + 1000, 16, 64);
  s.performer.release();
  assert.equal(c.of('take.begin')[1].tol['box.position'], 0.5);
  assert.ok(Math.abs((s.takes.at(-1)?.sampler.tolerance['box.position'].steps ?? NaN) - 0.5 / 0.015) < 1e-9);
});

test('capture speed slows the transport while performing; the count-in delays the take to the punch point', () => {
  const { s, c } = studio();
  s.transport.setCaptureSpeed(0.5);
  s.transport.setCountIn(1);
  const t0 = performance.now();
  s.transport.setRecord(true);                       // pre-roll: the transport starts 0.5 s of transport time early
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 960);
  assert.equal(c.of('take.begin').length, 0, 'a take began during the count-in');
  frames(s, t0, 976, 1400);
  const [begin] = c.of('take.begin');
  assert.equal(begin.speed, 0.5);
  assert.ok(begin.time >= 0 && begin.time < 0.02);
  const t = c.of('take.samples').flatMap((m) => m.t);
  assert.ok(Math.abs(t[1] - t[0] - 0.008) < 1e-9, 'samples are 8 ms of transport time apart at half speed');
  s.performer.release();                             // the take ends (its heartbeat with it)
});

test('loop recording: each pass of the loop is a take with the same loop key', () => {
  const { s, c } = studio();
  s.performer.setLoopRecord(true);
  s.transport.setLoop([0, 0.2]);
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 700);
  s.performer.release();
  const begins = c.of('take.begin');
  assert.ok(begins.length >= 3);
  assert.ok(begins.every((b) => b.loop && b.loop === begins[0].loop));
  assert.equal(c.of('take.end').length, begins.length);
});

test("without loop recording, the loop's wrap ends the take and the hold records no more", () => {
  const { s, c } = studio();
  s.transport.setLoop([0, 0.2]);
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 700);
  assert.equal(c.of('take.begin').length, 1);
  assert.equal(c.of('take.end').length, 1);
});

test('a page sent to the background ends its take at the last sample', () => {
  const { s, c } = studio();
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 200);
  s.hidden();
  assert.equal(s.performer.grab, null);
  const ends = c.of('take.end');
  assert.equal(ends.length, 1);
  const last = c.of('take.samples').at(-1);
  assert.ok(c.sent.indexOf(last) < c.sent.indexOf(ends[0]), 'the last samples go before the end');
  assert.equal(last.t.at(-1), s.takes[0].sampler.last);
});

test('outside record mode a drag previews, then sends one undoable edit on release', () => {
  const { s, c } = studio();
  const t0 = performance.now();
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 100);
  s.performer.release();
  assert.equal(c.of('take.begin').length, 0);
  assert.ok(c.of('preview').length > 0);
  const sets = c.of('set');
  assert.equal(sets.length, 1);
  assert.deepEqual(sets[0].value, s.values.get('box.position'));
});

test('playback writes the tracks but not what the performer holds', () => {
  const { s, c } = studio();
  c.receive({ type: 'tracks', span: [0, 1], removed: [], changed: [{ path: 'box.position', kind: 'curve', dim: 3, order: 2,
    rotation: false, tol: 0.005, knots: [0, 0, 1, 1], coef: [[0, 0, 0], [1, 0, 0]], start: 0, end: 1, takes: [] }] });
  s.transport.seek(0.5);
  assert.deepEqual(s.values.get('box.position'), [0.5, 0, 0]);
  s.performer.hold(['box.position'], 'move box');
  s.setLocal('box.position', [9, 9, 9]);
  s.transport.seek(0.25);
  assert.deepEqual(s.values.get('box.position'), [9, 9, 9]);
});

test("the studio's operations emit their signals: an attribute shown, an object added by the first free name", () => {
  const { s, c } = studio();
  /** @type {string[]} */
  const heard = [];
  s.signals.on('attribute', (a) => heard.push(`attribute ${a}`));
  s.signals.on('selection', (name) => heard.push(`selection ${name}`));
  s.select('box');
  s.showAttribute('position');
  assert.deepEqual(heard, ['selection box', 'attribute position']);
  c.receive({ type: 'state', ready: true, project: 'p', span: [0, 0], tracks: [], take: null, tolerances: {},
    history: { undo: [], redo: [], can_undo: false, can_redo: false },
    transport: { time: 0, playing: false, speed: 1, loop: null, count_in: 0, capture_speed: 1, mode: 'replace', loop_record: false, smoothing: 0 },
    objects: [{ name: 'object1', kind: 'object', attributes: [] }, { name: 'object3', kind: 'object', attributes: [] }] });
  s.addObject();
  assert.deepEqual(c.of('object.add').at(-1), { type: 'object.add', name: 'object2', kind: 'object' });
});

test('the loop key: on over the tracks\' span (else 0 to 4 s), off, then on again over the last range', () => {
  const { s } = studio();
  s.transport.toggleLoop();
  assert.deepEqual(s.transport.clock.loop, [0, 4]);
  s.transport.toggleLoop();
  assert.equal(s.transport.clock.loop, null);
  s.transport.setLoop([1, 2]);
  s.transport.toggleLoop();
  s.transport.toggleLoop();
  assert.deepEqual(s.transport.clock.loop, [1, 2]);
});

test('a notice from the server is kept and emitted', () => {
  const { s, c } = studio();
  /** @type {string[]} */
  const texts = [];
  s.signals.on('notice', (m) => texts.push(`${m.level} ${m.source}: ${m.text}`));
  c.receive({ type: 'notice', level: 'warning', text: 'the journal failed', source: 'recorder' });
  assert.deepEqual(texts, ['warning recorder: the journal failed']);
  assert.equal(s.notices.length, 1);
});

test('a message field the protocol does not have is a type error (tsc, tests/studio/test_page_types.py)', () => {
  const { s, c } = studio();
  // @ts-expect-error: 'valu' is no field of a set message
  s.send({ type: 'set', path: 'box.position', valu: [1, 2, 3] });
  // @ts-expect-error: 'warn' is no notice level
  c.receive({ type: 'notice', level: 'warn', text: 'x', source: 'recorder' });
  assert.equal(c.sent.at(-1).type, 'set');
  assert.equal(s.notices.length, 1);
});

test("a pointer reporting slower than REST is not at rest between its events (1.5 of its own pace)", () => {
  const { s, c } = studio();
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  for (let ms = 16; ms <= 400; ms += 16) {
    if (ms % 48 === 0) {                                // an event every 48 ms, frames every 16 ms
      s.setLocal('box.position', [ms / 1000, 0.5, 0]);
      s.performer.mark(t0 + ms - 4);
    }
    s.frame(t0 + ms);
  }
  s.performer.release();
  const values = c.of('take.samples').flatMap((m) => m.values.map((/** @type {number[]} */ r) => r[0]));
  // once its pace is known (two events), only its events are samples: none held between them
  const from = values.indexOf(0.096);
  assert.deepEqual(values.slice(from), [96, 144, 192, 240, 288, 336, 384].map((ms) => ms / 1000));
  // before the first event it was at rest: held samples of where it was
  assert.ok(values.slice(0, values.indexOf(0.048)).every((v) => v === 0));
});

test("another page's take: shown from its pieces, no take begins here, a hold in record mode leaves the server's values", () => {
  const { s, c } = studio();
  s.transport.setRecord(true);
  c.receive({ type: 'take.running', take: 'a1', paths: ['box.position'], mode: 'replace', time: 0, layout: [['box.position', 0, 3]] });
  assert.equal(s.remoteTake?.take, 'a1');
  c.receive({ type: 'take.piece', take: 'a1', path: 'box.position', order: 2, rotation: false, knots: [0, 0, 1, 1],
    coef: [[0, 0.5, 0], [0.3, 0.5, 0]] });
  assert.deepEqual(s.values.get('box.position'), [0.3, 0.5, 0], 'the other take is not shown');
  s.performer.hold(['box.position'], 'move box');
  s.setLocal('box.position', [2, 2, 2]);
  frames(s, performance.now(), 16, 200);
  s.performer.release();
  assert.equal(c.of('take.begin').length, 0, 'a take began while another page records');
  assert.deepEqual(s.values.get('box.position'), [0, 0.5, 0], 'the hold left a value the server does not hold');
  c.receive({ type: 'take.ended', take: 'a1', label: 'take box.position', paths: ['box.position'], ms: 1, gaps: [], smoothing: 0 });
  assert.equal(s.remoteTake, null);
  s.transport.setRecord(false);
  s.transport.setRecord(true);
  assert.equal(s.transport.record, true);
});

test('record mode stays off while another page records; a refused take.begin puts the server values back', () => {
  const { s, c } = studio();
  c.receive({ type: 'take.running', take: 'a1', paths: ['cam.position'], mode: 'replace', time: 0, layout: [['cam.position', 0, 3]] });
  s.transport.setRecord(true);
  assert.equal(s.transport.record, false);
  c.receive({ type: 'take.ended', take: 'a1', label: null, paths: [], ms: 0, gaps: [], smoothing: 0 });
  s.transport.setRecord(true);
  const t0 = performance.now();
  s.performer.hold(['box.position'], 'move box');
  s.setLocal('box.position', [1, 1, 1]);
  frames(s, t0, 16, 60);
  assert.equal(c.of('take.begin').length, 1);
  c.receive({ type: 'error', id: null, ref: 'take.begin', code: 'busy', message: "take 'x' is being recorded" });
  assert.equal(s.performer.grab?.take, null);
  assert.deepEqual(s.values.get('box.position'), [0, 0.5, 0]);
  s.setLocal('box.position', [2, 1, 1]);
  frames(s, t0 + 60, 16, 60);
  s.performer.release();
  assert.equal(c.of('take.begin').length, 1, 'the refused hold began another take');
  assert.deepEqual(s.values.get('box.position'), [0, 0.5, 0]);
});

test('the transport and record settings go to the server and come back from it', () => {
  const { s, c } = studio();
  s.transport.setSpeed(0.5);
  s.transport.setCountIn(2);
  s.transport.setCaptureSpeed(0.25);
  s.performer.setMode('additive');
  s.performer.setLoopRecord(true);
  s.performer.setSmoothing(0.05);
  const last = c.of('transport').at(-1);
  assert.deepEqual({ ...last, time: 0 }, { type: 'transport', time: 0, playing: false, speed: 0.5, loop: null, count_in: 2,
    capture_speed: 0.25, mode: 'additive', loop_record: true, smoothing: 0.05 });
  const fresh = studio().s;
  fresh.transport.receive(last);
  assert.deepEqual([fresh.transport.playSpeed, fresh.transport.countIn, fresh.transport.captureSpeed, fresh.performer.mode,
    fresh.performer.loopRecord, fresh.performer.smoothing], [0.5, 2, 0.25, 'additive', true, 0.05]);
});

test('a renamed object stays selected through the rename, its undo and its redo; a removed one does not', () => {
  assert.equal(renamedSelection('box', ['box', 'ball'], ['crate', 'ball']), 'crate');
  assert.equal(renamedSelection('crate', ['crate', 'ball'], ['box', 'ball']), 'box');
  assert.equal(renamedSelection('box', ['box', 'ball'], ['ball']), null);
  assert.equal(renamedSelection('ball', ['box', 'ball'], ['crate', 'ball']), 'ball');
  assert.equal(renamedSelection('box', ['box', 'ball'], ['ball', 'x', 'y']), null);
  assert.equal(renamedSelection(null, ['box'], ['crate']), null);
});
