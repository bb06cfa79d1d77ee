// @ts-check
/**
 * The notice area (over the 3D view's top left corner, clear of REC, the camera view and
 * the curve view): the server's notices (a recorder's warning: a reducer process died, the
 * journal failed) and its refusals of a message, each styled by its level, readable until
 * dismissed. Warnings and errors the server sends stay until dismissed; information, and a
 * refusal (an answer to something just done), go by themselves after a few seconds.
 */

/** @typedef {import('./messages.js').NoticeLevel} NoticeLevel */
/** @typedef {{level: NoticeLevel, text: string, source: string, sticky: boolean}} Shown */

/** Milliseconds a notice that is not sticky stays. */
export const FADE_MS = 6000;
/** Notices shown at once (the oldest goes first). */
export const MAX_SHOWN = 4;

/**
 * What a refusal's code says happened, where its code alone does not (the server's message
 * follows). A disk failure stays until dismissed; the others are answers to something just done.
 * @type {Record<string, {level: NoticeLevel, says: string, sticky: boolean}>}
 */
const REFUSALS = {
  read_only: { level: 'warning', says: 'read-only project: edits are refused', sticky: false },
  exists: { level: 'warning', says: 'file exists: send again with overwrite', sticky: false },
  failed: { level: 'error', says: 'not done — the disk failed', sticky: true },
  too_large: { level: 'error', says: 'message too large', sticky: false },
};

/**
 * How a server message is shown.
 * @param {import('./messages.js').Notice | import('./messages.js').ErrorReply} m
 * @returns {Shown}
 *
 * @example
 * noticeOf({type: 'error', id: null, ref: 'set', code: 'refused', message: 'no box.size'});
 * // {level: 'error', text: 'refused: no box.size', source: 'set', sticky: false}
 * noticeOf({type: 'error', id: 4, ref: 'export', code: 'exists', message: 'out.glb exists'});
 * // {level: 'warning', text: 'file exists: send again with overwrite — out.glb exists', source: 'export', sticky: false}
 */
export function noticeOf(m) {
  if (m.type === 'error') {
    const known = REFUSALS[m.code];
    const source = m.ref ?? 'server';
    if (!known) return { level: 'error', text: `${m.code}: ${m.message}`, source, sticky: false };
    return { level: known.level, text: `${known.says} — ${m.message}`, source, sticky: known.sticky };
  }
  return { level: m.level, text: m.text, source: m.source, sticky: m.level !== 'info' };
}

export class Notices {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root the notice area
   */
  constructor(studio, root) {
    this.root = root;
    studio.signals.on('notice', (m) => this.show(noticeOf(m)));
    studio.signals.on('error', (m) => this.show(noticeOf(m)));
  }

  /**
   * Show a notice.
   * @param {Shown} notice
   * @returns {HTMLElement} its element
   */
  show(notice) {
    const doc = this.root.ownerDocument;
    const box = doc.createElement('div');
    box.className = `notice ${notice.level}`;
    box.dataset.testid = 'notice';
    box.dataset.level = notice.level;
    box.setAttribute('role', notice.level === 'info' ? 'status' : 'alert');
    const source = doc.createElement('span');
    source.className = 'source';
    source.textContent = notice.source;
    const text = doc.createElement('span');
    text.className = 'text';
    text.textContent = notice.text;
    const dismiss = doc.createElement('button');
    dismiss.className = 'dismiss';
    dismiss.dataset.testid = 'notice-dismiss';
    dismiss.title = 'Dismiss';
    dismiss.textContent = '×';
    dismiss.addEventListener('click', () => box.remove());
    box.append(source, text, dismiss);
    this.root.append(box);
    while (this.root.children.length > MAX_SHOWN) this.root.children[0].remove();
    if (!notice.sticky) setTimeout(() => box.remove(), FADE_MS);
    return box;
  }
}
