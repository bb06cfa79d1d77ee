// @ts-check
// What the page shows and does when things go wrong: saves failing on the server, a
// read-only project, a take the server ended, a socket reset; the heartbeat that keeps a
// recording page's take alive.
import test, { mock } from 'node:test';
import assert from 'node:assert/strict';
import { BEAT_MS } from '../../../src/sketchanim/studio/web/js/Performer.js';
import { noticeOf } from '../../../src/sketchanim/studio/web/js/notices.js';
import { clockOf, saveText } from '../../../src/sketchanim/studio/web/js/savestatus.js';
import { TOO_BIG } from '../../../src/sketchanim/studio/web/js/Studio.js';
import { frames, stateOf, studio } from './fake_studio.mjs';

const FULL = { type: /** @type {'saved'} */ ('saved'), ok: false, error: 'No space left on device', since: 1_700_000_000 };
const OK = { type: /** @type {'saved'} */ ('saved'), ok: true, error: null, since: null };

/** A studio recording a take of the box (record mode, a hold, frames until take.begin went). */
function recording() {
  const { s, c } = studio();
  const t0 = performance.now();
  s.transport.setRecord(true);
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 200);
  const [begin] = c.of('take.begin');
  assert.ok(begin && s.performer.grab?.take?.id === begin.take, 'a take began');
  return { s, c, t0, take: begin.take };
}

test('the studio keeps whether everything is saved, from the state and from saved messages', () => {
  const { s, c } = studio({ saved: FULL });
  assert.deepEqual(s.saved, FULL);
  /** @type {any[]} */
  const heard = [];
  s.signals.on('saved', (m) => heard.push(m));
  c.receive(OK);
  assert.equal(s.saved.ok, true);
  assert.deepEqual(heard, [OK]);
  c.receive(FULL);
  assert.equal(s.saved.error, 'No space left on device');
  assert.equal(studio().s.saved.ok, true, 'a state without saved: everything is');
});

test('the save indicator says what failed, that it is kept and retried, and since when; nothing while saved', () => {
  assert.equal(saveText(OK), null);
  assert.equal(saveText(FULL), `not saved — No space left on device — kept in memory, retrying (since ${clockOf(FULL.since)})`);
  assert.equal(saveText({ ...FULL, since: null, error: null }), 'not saved — the last save failed — kept in memory, retrying');
  const d = new Date(FULL.since * 1000);
  assert.equal(clockOf(FULL.since), [d.getHours(), d.getMinutes(), d.getSeconds()].map((n) => String(n).padStart(2, '0')).join(':'));
  assert.match(clockOf(FULL.since), /^\d\d:\d\d:\d\d$/);
});

test('while this page records a take it pings every second, samples or not; the pings stop with the take', () => {
  mock.timers.enable({ apis: ['setInterval'] });
  try {
    const { s, c } = recording();
    assert.equal(c.of('ping').length, 0);
    mock.timers.tick(3 * BEAT_MS + 10);                 // no frames meanwhile: a background tab
    assert.equal(c.of('ping').length, 3);
    s.performer.release();
    assert.equal(c.of('take.end').length, 1);
    mock.timers.tick(5 * BEAT_MS);
    assert.equal(c.of('ping').length, 3, 'pings after the take ended');
    assert.equal(s.performer.beat, null);
  } finally {
    mock.timers.reset();
  }
});

test('a take the server ended (the page fell silent) stops here: no more samples, record mode off, a notice', () => {
  mock.timers.enable({ apis: ['setInterval'] });
  try {
    const { s, c, t0, take } = recording();
    c.receive({ type: 'take.ended', take, label: 'take move box', paths: ['box.position'], ms: 3, gaps: [], smoothing: 0, reason: 'silent' });
    const sent = c.sent.length;
    assert.equal(s.performer.grab?.take, null);
    assert.equal(s.transport.record, false, 'REC is back to idle');
    assert.deepEqual(s.notices.at(-1), { type: 'notice', level: 'warning', source: 'take',
      text: 'take kept: the server ended it — no frames from this page for 5 s' });
    assert.equal(s.takes.at(-1)?.id, take, 'the take is in the log, its label from the server');
    frames(s, t0, 216, 600);                             // the animator still drags
    mock.timers.tick(3 * BEAT_MS);
    s.performer.release();
    const after = c.sent.slice(sent).map((m) => m.type);
    assert.ok(!after.some((t) => ['take.samples', 'take.end', 'set', 'preview', 'ping'].includes(t)), after.join());
    assert.deepEqual(s.values.get('box.position'), [0, 0.5, 0], 'the release shows the server\'s values again');
  } finally {
    mock.timers.reset();
  }
});

test('a socket that drops ends this page\'s take here (the server keeps it); a 1009 close says a message was too large', () => {
  const { s, c, take } = recording();
  c.onStatus(false, 1006);
  assert.equal(s.performer.grab?.take, null);
  assert.equal(s.takes.at(-1)?.id, take);
  assert.match(s.notices.at(-1)?.text ?? '', /connection dropped/);
  c.onStatus(true);
  c.onStatus(false, TOO_BIG);
  assert.equal(s.notices.at(-1)?.level, 'error');
  assert.match(s.notices.at(-1)?.text ?? '', /too large.*reset/);
  s.performer.release();
});

test('a read-only project: the lock says so, REC stays off, holds and edits send nothing', () => {
  const { s, c } = studio({ read_only: true, history: { undo: ['set box.position'], redo: [], can_undo: true, can_redo: false } });
  assert.equal(s.lock?.kind, 'read-only');
  assert.equal(s.lock?.text, 'read-only project: plays and exports; edits are refused');
  s.transport.setRecord(true);
  assert.equal(s.transport.record, false);
  const t0 = performance.now();
  s.performer.hold(['box.position'], 'move box');
  frames(s, t0, 16, 300);
  assert.deepEqual(s.values.get('box.position'), [0.288, 0.5, 0], 'the drag shows in the page');
  s.performer.release();
  assert.deepEqual(s.values.get('box.position'), [0, 0.5, 0], 'and goes back on release');
  s.set('box.position', [1, 2, 3], 'set box.position');
  s.setTolerance('box.position', { amount: 2, unit: 'px' });
  s.undo();
  s.redo();
  s.addObject();
  const edits = c.sent.filter((m) => m.type !== 'transport').map((m) => m.type);
  assert.deepEqual(edits, [], 'sent to a read-only project');
  assert.deepEqual(s.values.get('box.position'), [0, 0.5, 0]);
  c.receive(stateOf({ read_only: false }));
  assert.equal(s.lock, null, 'writable again: no lock');
  s.transport.setRecord(true);
  assert.equal(s.transport.record, true);
});

test('refusals with the new codes say what happened', () => {
  const refusal = (/** @type {string} */ code) => noticeOf({ type: 'error', id: 1, ref: 'export', code, message: 'm' });
  assert.deepEqual(refusal('exists'), { level: 'warning', text: 'file exists: send again with overwrite — m', source: 'export', sticky: false });
  assert.deepEqual(refusal('read_only'), { level: 'warning', text: 'read-only project: edits are refused — m', source: 'export', sticky: false });
  assert.deepEqual(refusal('failed'), { level: 'error', text: 'not done — the disk failed — m', source: 'export', sticky: true });
  assert.equal(refusal('too_large').text, 'message too large — m');
  assert.equal(refusal('busy').text, 'busy: m');
});
