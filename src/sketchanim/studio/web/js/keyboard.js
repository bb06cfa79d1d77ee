// @ts-check
/**
 * The studio's keys, all in one place: R record mode, Space play / pause, Enter stop, L loop,
 * C the camera view, Escape deselect, W / E / S the move / turn / scale gizmo, Ctrl+Z undo,
 * Ctrl+Shift+Z or Ctrl+Y redo (Cmd for Ctrl on a Mac).
 *
 * One model whichever control has focus: the window takes a shortcut in the capture phase,
 * before the focused element sees it, and prevents the key's default action, so a focused
 * button does not also click (Enter, Space), a checkbox does not toggle (Space), a menu does
 * not open or jump to an option (Space, a letter), the page does not scroll. Only while typing
 * in a text or number field are the keys the field's. Focus stays where it is (Tab still
 * walks the controls); no control needs its own key handling.
 */

/** @typedef {'undo' | 'redo' | 'record' | 'play' | 'stop' | 'loop' | 'camera' | 'deselect' | 'translate' | 'rotate' | 'scale'} KeyAction */
/** @typedef {{key: string, ctrlKey: boolean, metaKey: boolean, shiftKey: boolean, altKey: boolean}} Keys */

/** @type {Record<string, KeyAction>} the plain keys (no Ctrl, Cmd or Alt), by their lower-case `key` */
const PLAIN = { r: 'record', ' ': 'play', enter: 'stop', l: 'loop', c: 'camera', escape: 'deselect',
  w: 'translate', e: 'rotate', s: 'scale' };

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

/** The input types one types text into (a checkbox, a slider, a colour picker are not). */
const TEXT_INPUTS = new Set(['text', 'number', 'search', 'email', 'url', 'tel', 'password']);

/**
 * Whether a key press is typing into a field (a text or number input, a text area, an
 * editable element): then it is the field's, not a shortcut.
 * @param {EventTarget | {tagName?: string, type?: string, isContentEditable?: boolean} | null} target
 * @returns {boolean}
 *
 * @example
 * typing({tagName: 'INPUT', type: 'number'});     // true
 * typing({tagName: 'SELECT'});                    // false: a menu's keys are shortcuts too
 */
export function typing(target) {
  if (!target || typeof target !== 'object') return false;
  const t = /** @type {{tagName?: string, type?: string, isContentEditable?: boolean}} */ (target);
  const tag = String(t.tagName ?? '');
  if (tag === 'TEXTAREA' || t.isContentEditable) return true;
  return tag === 'INPUT' && TEXT_INPUTS.has(String(t.type ?? 'text').toLowerCase());
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
 * Run `actions` on the key presses `target` (the window) receives, in the capture phase:
 * a shortcut's key does only the shortcut (its default action prevented), whichever
 * control has focus, except while typing in a field.
 * @param {EventTarget} target
 * @param {Record<KeyAction, () => void>} actions
 */
export function bindKeyboard(target, actions) {
  target.addEventListener('keydown', (event) => {
    const e = /** @type {KeyboardEvent} */ (event);
    if (typing(e.target)) return;
    const action = actionOf(e);
    if (!action) return;
    e.preventDefault();
    if (!e.repeat || action === 'undo' || action === 'redo') actions[action]();
  }, { capture: true });
  // Space activates a focused button or checkbox on its key up: that default goes too.
  target.addEventListener('keyup', (event) => {
    const e = /** @type {KeyboardEvent} */ (event);
    if (!typing(e.target) && actionOf(e)) e.preventDefault();
  }, { capture: true });
}
