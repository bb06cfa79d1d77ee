// @ts-check
// The declared signal registry: listeners in order, payloads passed, undeclared names refused.
import test from 'node:test';
import assert from 'node:assert/strict';
import { SIGNALS, Signals } from '../../../src/sketchanim/studio/web/js/signals.js';

test('listeners of a signal get its payload, in the order they were added', () => {
  const signals = new Signals();
  /** @type {(string | null)[]} */
  const seen = [];
  signals.on('selection', (name) => seen.push(`a ${name}`));
  signals.on('selection', (name) => seen.push(`b ${name}`));
  signals.on('record', () => seen.push('record'));
  signals.emit('selection', 'box');
  signals.emit('selection', null);
  assert.deepEqual(seen, ['a box', 'b box', 'a null', 'b null']);
});

test('a signal without a payload is emitted without one', () => {
  const signals = new Signals();
  let calls = 0;
  signals.on('state', () => { calls += 1; });
  signals.emit('state');
  assert.equal(calls, 1);
});

test('emitting or listening to an undeclared signal throws, naming it', () => {
  const signals = new Signals();
  // @ts-expect-error: 'take' is not a declared signal
  assert.throws(() => signals.emit('take'), /no signal named "take"/);
  // @ts-expect-error: nor is 'attributes'
  assert.throws(() => signals.on('attributes', () => {}), /no signal named "attributes"/);
});

test('every declared signal says what it means', () => {
  for (const [name, declared] of Object.entries(SIGNALS)) {
    assert.ok(declared.doc.length > 10, `signal ${name} has no description`);
  }
});
