// @ts-check
// The notice area: a server notice or a refusal shown by level, dismissable, fading only when
// it is not sticky; the studio keeps every notice and emits it. A tiny stand-in for the DOM.
import test, { mock } from 'node:test';
import assert from 'node:assert/strict';
import { FADE_MS, MAX_SHOWN, Notices, noticeOf } from '../../../src/sketchanim/studio/web/js/notices.js';
import { Studio } from '../../../src/sketchanim/studio/web/js/Studio.js';

class FakeElement extends EventTarget {
  /** @param {FakeDocument} doc @param {string} tag */
  constructor(doc, tag) {
    super();
    this.ownerDocument = doc;
    this.tagName = tag.toUpperCase();
    /** @type {FakeElement[]} */
    this.children = [];
    /** @type {FakeElement | null} */
    this.parent = null;
    this.className = '';
    this.textContent = '';
    this.title = '';
    /** @type {Record<string, string>} */
    this.dataset = {};
    /** @type {Record<string, string>} */
    this.attributes = {};
  }

  /** @param {string} k @param {string} v */
  setAttribute(k, v) { this.attributes[k] = v; }

  /** @param {...FakeElement} nodes */
  append(...nodes) {
    for (const n of nodes) {
      n.parent = this;
      this.children.push(n);
    }
  }

  remove() {
    if (this.parent) this.parent.children = this.parent.children.filter((c) => c !== this);
    this.parent = null;
  }

  /** All the text inside. @returns {string} */
  get text() { return [this.textContent, ...this.children.map((c) => c.text)].join(' ').trim(); }

  click() { this.dispatchEvent(new Event('click')); }
}

class FakeDocument {
  /** @param {string} tag */
  createElement(tag) { return new FakeElement(this, tag); }
}

class FakeConnection {
  constructor() {
    this.connected = true;
    /** @type {(m: any) => void} */
    this.onMessage = () => {};
  }
  /** @param {(m: any) => void} onMessage */
  connect(onMessage) { this.onMessage = onMessage; }
  send() {}
}

function page() {
  const connection = new FakeConnection();
  const studio = new Studio(connection);
  const root = new FakeDocument().createElement('div');
  new Notices(studio, /** @type {any} */ (root));
  return { studio, root, receive: connection.onMessage };
}

test('a recorder warning shows, by its level, with its text and source, until dismissed', () => {
  mock.timers.enable({ apis: ['setTimeout'] });
  try {
    const { studio, root, receive } = page();
    /** @type {any[]} */
    const heard = [];
    studio.signals.on('notice', (m) => heard.push(m));
    const notice = { type: 'notice', level: 'warning', text: 'a reducer process died; the take was reduced here', source: 'recorder' };
    receive(notice);
    assert.deepEqual(studio.notices, [notice]);
    assert.deepEqual(heard, [notice]);
    const [box] = root.children;
    assert.equal(box.className, 'notice warning');
    assert.equal(box.dataset.testid, 'notice');
    assert.equal(box.attributes.role, 'alert');
    assert.match(box.text, /recorder a reducer process died; the take was reduced here/);
    mock.timers.tick(10 * FADE_MS);
    assert.equal(root.children.length, 1, 'a warning went by itself');
    const dismiss = box.children.find((c) => c.dataset.testid === 'notice-dismiss');
    dismiss?.click();
    assert.equal(root.children.length, 0);
  } finally {
    mock.timers.reset();
  }
});

test('information and refusals go by themselves; no more than a few show at once', () => {
  mock.timers.enable({ apis: ['setTimeout'] });
  try {
    const { studio, root, receive } = page();
    receive({ type: 'notice', level: 'info', text: 'saved', source: 'project' });
    receive({ type: 'error', id: null, ref: 'set', code: 'refused', message: 'no attribute nothing.here' });
    assert.deepEqual(root.children.map((c) => c.className), ['notice info', 'notice error']);
    assert.match(root.children[1].text, /set refused: no attribute nothing.here/);
    assert.equal(studio.errors.length, 1);
    mock.timers.tick(FADE_MS);
    assert.equal(root.children.length, 0);
    for (let i = 0; i < MAX_SHOWN + 3; i++) receive({ type: 'notice', level: 'error', text: `n${i}`, source: 'recorder' });
    assert.equal(root.children.length, MAX_SHOWN);
    assert.match(root.children.at(-1)?.text ?? '', new RegExp(`n${MAX_SHOWN + 2}`));
  } finally {
    mock.timers.reset();
  }
});

test('noticeOf: a refusal names the message refused', () => {
  assert.deepEqual(noticeOf({ type: 'error', id: 3, ref: null, code: 'rate', message: 'too many' }),
    { level: 'error', text: 'rate: too many', source: 'server', sticky: false });
  assert.deepEqual(noticeOf({ type: 'notice', level: 'error', text: 'x', source: 'recorder' }),
    { level: 'error', text: 'x', source: 'recorder', sticky: true });
});
