// @ts-check
/**
 * The studio's keys, all in one place: R record mode, Space play / pause, Enter stop, L loop,
 * C the camera view, Escape deselect, W / E / S the move / turn / scale gizmo, Ctrl+Z undo,
 * Ctrl+Shift+Z or Ctrl+Y redo (Cmd for Ctrl on a Mac). Keys typed into a field are the field's.
 */

/** @typedef {'undo' | 'redo' | 'record' | 'play' | 'stop' | 'loop' | 'camera' | 'deselect' | 'translate' | 'rotate' | 'scale'} KeyAction */
/** @typedef {{key: string, ctrlKey: boolean, metaKey: boolean, shiftKey: boolean, altKey: boolean}} Keys */

/** @type {Record<string, KeyAction>} the plain keys (no Ctrl, Cmd or Alt), by their lower-case `key` */
const PLAIN = { r: 'record', ' ': 'play', enter: 'stop', l: 'loop', c: 'camera', escape: 'deselect',
  w: 'translate', e: 'rotate', s: 'scale' };
/** What the browser would otherwise do with these keys (scroll, its own undo). */
const PREVENT = new Set(['undo', 'redo', 'play']);

/**
 * The action a key press asks for, or null.
 * @param {Keys} e
 * @returns {KeyAction | null}
 *
 * @example
 * actionOf({key: 'z', ctrlKey: true, metaKey: false, shiftKey: true, altKey: false});    // 'redo'
 */
export function actionOf(e) {
  const key = e.key.toLowerCase();
  if (e.ctrlKey || e.metaKey) {
    if (key === 'z') return e.shiftKey ? 'redo' : 'undo';
    return key === 'y' ? 'redo' : null;
  }
  if (e.altKey) return null;
  return PLAIN[key] ?? null;
}

/**
 * Whether a key press goes to a field (a number, a select, a text box) and not to the studio.
 * @param {EventTarget | null} target
 */
function typing(target) {
  const tag = target && 'tagName' in target ? String(target.tagName) : '';
  return tag === 'INPUT' || tag === 'SELECT' || tag === 'TEXTAREA';
}

/**
 * What each action does in the studio.
 * @param {import('./Studio.js').Studio} studio
 * @param {Pick<import('./viewport.js').Viewport, 'setGizmo' | 'togglePreviewCamera'>} viewport
 * @returns {Record<KeyAction, () => void>}
 */
export function studioActions(studio, viewport) {
  const t = studio.transport;
  return {
    undo: () => studio.undo(),
    redo: () => studio.redo(),
    record: () => t.setRecord(!t.record),
    play: () => t.togglePlay(),
    stop: () => t.stop(),
    loop: () => t.toggleLoop(),
    camera: () => viewport.togglePreviewCamera(),
    deselect: () => studio.select(null),
    translate: () => viewport.setGizmo('translate'),
    rotate: () => viewport.setGizmo('rotate'),
    scale: () => viewport.setGizmo('scale'),
  };
}

/**
 * Run `actions` on the key presses `target` (the window) receives.
 * @param {EventTarget} target
 * @param {Record<KeyAction, () => void>} actions
 */
export function bindKeyboard(target, actions) {
  target.addEventListener('keydown', (event) => {
    const e = /** @type {KeyboardEvent} */ (event);
    if (typing(e.target)) return;
    const action = actionOf(e);
    if (!action) return;
    if (PREVENT.has(action)) e.preventDefault();
    actions[action]();
  });
}
