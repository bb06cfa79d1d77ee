// @ts-check
// The keyboard module: which key asks for what, and keys typed into a field left alone.
import test from 'node:test';
import assert from 'node:assert/strict';
import { actionOf, bindKeyboard, typing } from '../../../src/sketchanim/studio/web/js/keyboard.js';

/** @param {string} key @param {{ctrlKey?: boolean, metaKey?: boolean, shiftKey?: boolean, altKey?: boolean}} [mods] */
const press = (key, mods = {}) => ({ key, ctrlKey: false, metaKey: false, shiftKey: false, altKey: false, ...mods });

test('the plain keys: record, play, stop, loop, camera, deselect and the gizmo, in either case', () => {
  const seen = ['r', ' ', 'Enter', 'l', 'C', 'Escape', 'w', 'e', 'S'].map((k) => actionOf(press(k)));
  assert.deepEqual(seen, ['record', 'play', 'stop', 'loop', 'camera', 'deselect', 'translate', 'rotate', 'scale']);
  assert.equal(actionOf(press('x')), null);
});

test('Ctrl or Cmd: Z undoes, Shift+Z and Y redo; with Ctrl, Cmd or Alt a plain key does nothing', () => {
  assert.equal(actionOf(press('z', { ctrlKey: true })), 'undo');
  assert.equal(actionOf(press('Z', { metaKey: true, shiftKey: true })), 'redo');
  assert.equal(actionOf(press('y', { ctrlKey: true })), 'redo');
  for (const mods of [{ ctrlKey: true }, { metaKey: true }, { altKey: true }]) {
    assert.equal(actionOf(press('r', mods)), null);
    assert.equal(actionOf(press('w', mods)), null);
  }
});

/** A key press as the window gets it (node has no KeyboardEvent). */
function keydown(/** @type {string} */ key, /** @type {object} */ target, mods = {}) {
  const event = new Event('keydown', { cancelable: true });
  Object.defineProperties(event, Object.fromEntries(Object.entries({ ...press(key, mods), target })
    .map(([k, v]) => [k, { value: v }])));
  return event;
}

test('bound keys run their action once, their default prevented, whatever has focus; keys typed into a field do not', () => {
  const target = new EventTarget();
  /** @type {string[]} */
  const ran = [];
  const actions = /** @type {Parameters<typeof bindKeyboard>[1]} */ (/** @type {unknown} */ (Object.fromEntries(
    ['undo', 'redo', 'record', 'play', 'stop', 'loop', 'camera', 'deselect', 'translate', 'rotate', 'scale']
      .map((a) => [a, () => { ran.push(a); }]))));
  bindKeyboard(target, actions);
  const space = keydown(' ', { tagName: 'CANVAS' });
  target.dispatchEvent(space);
  assert.ok(space.defaultPrevented, 'Space would scroll the page');
  for (const focused of [{ tagName: 'BUTTON' }, { tagName: 'SELECT' }, { tagName: 'INPUT', type: 'checkbox' },
    { tagName: 'INPUT', type: 'range' }, { tagName: 'INPUT', type: 'color' }]) {
    const enter = keydown('Enter', focused);
    target.dispatchEvent(enter);
    assert.ok(enter.defaultPrevented, `Enter would also activate the focused ${focused.tagName}`);
  }
  target.dispatchEvent(keydown('z', { tagName: 'BODY' }, { ctrlKey: true }));
  for (const focused of [{ tagName: 'INPUT', type: 'number' }, { tagName: 'INPUT', type: 'text' }, { tagName: 'TEXTAREA' },
    { tagName: 'DIV', isContentEditable: true }]) {
    const r = keydown('r', focused);
    target.dispatchEvent(r);
    assert.ok(!r.defaultPrevented, `a key typed into ${focused.tagName} was taken`);
  }
  const q = keydown('q', { tagName: 'BODY' });
  target.dispatchEvent(q);
  assert.ok(!q.defaultPrevented, 'a key that is no shortcut keeps its default');
  assert.deepEqual(ran, ['play', 'stop', 'stop', 'stop', 'stop', 'stop', 'undo']);
});

test('typing: text and number fields, text areas and editable elements only', () => {
  assert.equal(typing({ tagName: 'INPUT', type: 'number' }), true);
  assert.equal(typing({ tagName: 'INPUT' }), true);                  // no type: a text field
  assert.equal(typing({ tagName: 'INPUT', type: 'checkbox' }), false);
  assert.equal(typing({ tagName: 'SELECT' }), false);
  assert.equal(typing({ tagName: 'BUTTON' }), false);
  assert.equal(typing(null), false);
});

test('Ctrl or Cmd with C, X, V: copy, cut, paste (the timeline acts on them)', () => {
  assert.deepEqual(['c', 'X', 'v'].map((k) => actionOf(press(k, { ctrlKey: true }))), ['copy', 'cut', 'paste']);
  assert.equal(actionOf(press('v', { metaKey: true })), 'paste');
  assert.equal(actionOf(press('c')), 'camera');
});
