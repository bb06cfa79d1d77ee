// @ts-check
// A Studio without a browser, for the node tests: a fake connection records what the page
// sends and hands it the server's messages; the project holds one box. Not a node --test file.
import { Studio } from '../../../src/sketchanim/studio/web/js/Studio.js';

/** @typedef {import('../../../src/sketchanim/studio/web/js/messages.js').ServerMessage} ServerMessage */
/** @typedef {import('../../../src/sketchanim/studio/web/js/messages.js').StateSnapshot} StateSnapshot */

export class FakeConnection {
  constructor() {
    /** @type {any[]} */
    this.sent = [];
    this.connected = true;
    /** @type {(m: ServerMessage) => void} */
    this.onMessage = () => {};
    /** @type {(open: boolean, code?: number) => void} */
    this.onStatus = () => {};
  }

  /** @param {(m: any) => void} onMessage @param {(open: boolean, code?: number) => void} onStatus */
  connect(onMessage, onStatus) { this.onMessage = onMessage; this.onStatus = onStatus; }

  /** @param {any} m */
  send(m) { this.sent.push(m); }

  /** @param {ServerMessage} m */
  receive(m) { this.onMessage(m); }

  /** @param {string} type */
  of(type) { return this.sent.filter((m) => m.type === type); }
}

const POSITION = { name: 'position', dim: 3, tol: 0.005, unit: 'scene units', default: [0, 0, 0], choices: [], continuous: true };

/**
 * The state of a project of one box (with `extra` fields).
 * @param {Partial<StateSnapshot>} [extra]
 * @returns {StateSnapshot}
 */
export function stateOf(extra = {}) {
  return { type: 'state', ready: true, project: 'p', span: [0, 0], tracks: [], take: null, tolerances: {},
    history: { undo: [], redo: [], can_undo: false, can_redo: false },
    transport: { time: 0, playing: false, speed: 1, loop: null, count_in: 0, capture_speed: 1, mode: 'replace', loop_record: false, smoothing: 0 },
    objects: [{ name: 'box', kind: 'object', attributes: [{ name: 'position', value: [0, 0.5, 0], type: POSITION }] }], ...extra };
}

/**
 * A studio whose server sent the state of a project of one box (with `extra` fields).
 * @param {Partial<StateSnapshot>} [extra]
 */
export function studio(extra = {}) {
  const c = new FakeConnection();
  const s = new Studio(c);
  c.receive(stateOf(extra));
  return { s, c };
}

/** Run frames every 16 ms from `from` to `to` (ms after `t0`), moving the box along x on a
 * pointer event 4 ms before each frame. */
export function frames(/** @type {Studio} */ s, /** @type {number} */ t0, /** @type {number} */ from, /** @type {number} */ to) {
  for (let ms = from; ms <= to; ms += 16) {
    if (s.performer.grab) {
      s.setLocal('box.position', [ms / 1000, 0.5, 0]);
      s.performer.mark(t0 + ms - 4);
    }
    s.frame(t0 + ms);
  }
}
