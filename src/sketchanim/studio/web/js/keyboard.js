// @ts-check
/**
 * The studio's keys, all in one place (SHORTCUTS lists them, as the help overlay shows them;
 * Cmd for Ctrl on a Mac). A panel's own action goes out as the `command` signal.
 *
 * One model whichever control has focus: the window takes a shortcut in the capture phase,
 * before the focused element sees it, and prevents the key's default action, so a focused
 * button does not also click (Enter, Space), a checkbox does not toggle (Space), a menu does
 * not open or jump to an option (Space, a letter), the page does not scroll. Only while typing
 * in a text or number field are the keys the field's. Focus stays where it is (Tab still
 * walks the controls); no control needs its own key handling.
 */

/**
 * What a panel does on its own when its shortcut is pressed (the `command` signal carries it):
 * the curve editor frames all or the selection, inserts a knot at the playhead, normalises its
 * channels, removes the selected keys' knots; the timeline deletes, copies, cuts its range
 * and pastes; the help overlay shows or hides; the viewport
 * shows or hides motion paths and onion skin; the outliner renames the selected object.
 * @typedef {'frame-all' | 'frame-selection' | 'insert-knot' | 'normalise' | 'delete-points' | 'help' | 'motion-paths'
 *   | 'onion-skin' | 'rename' | 'delete-range' | 'copy' | 'cut' | 'paste'} PanelCommand
 */
/** @typedef {'undo' | 'redo' | 'record' | 'play' | 'stop' | 'loop' | 'camera' | 'deselect' | 'translate' | 'rotate' | 'scale'
 *   | 'previous-frame' | 'next-frame' | 'delete' | 'duplicate' | 'snap' | 'cue' | PanelCommand} KeyAction */
/** @typedef {{key: string, ctrlKey: boolean, metaKey: boolean, shiftKey: boolean, altKey: boolean}} Keys */

/**
 * @typedef {object} Shortcut   One shortcut, as the help overlay lists it.
 * @property {KeyAction} action
 * @property {string[]} keys   what to press, as shown (`Ctrl` is `Cmd` on a Mac)
 * @property {string} does     what it does
 */

/** @type {Shortcut[]} every shortcut of the studio, in the order the help overlay lists them */
export const SHORTCUTS = [
  { action: 'record', keys: ['R'], does: 'record mode on / off (grab an object to record a take)' },
  { action: 'play', keys: ['Space'], does: 'play / pause' },
  { action: 'stop', keys: ['Enter'], does: 'stop (back to the start)' },
  { action: 'previous-frame', keys: ['←'], does: 'one frame back' },
  { action: 'next-frame', keys: ['→'], does: 'one frame on' },
  { action: 'loop', keys: ['L'], does: 'loop range on / off (Shift-drag the timeline to set it)' },
  { action: 'snap', keys: ['Shift', 'S'], does: 'snap edits in time to frames on / off' },
  { action: 'cue', keys: ['M'], does: 'mark a cue (an event) on the selected object at the transport time (while playing: as you press it)' },
  { action: 'translate', keys: ['W'], does: 'move gizmo' },
  { action: 'rotate', keys: ['E'], does: 'turn gizmo' },
  { action: 'scale', keys: ['S'], does: 'scale gizmo' },
  { action: 'camera', keys: ['C'], does: 'look through the scene camera' },
  { action: 'motion-paths', keys: ['P'], does: 'motion paths on / off' },
  { action: 'onion-skin', keys: ['O'], does: 'onion skin (ghosts at nearby frames) on / off' },
  { action: 'deselect', keys: ['Esc'], does: 'select nothing' },
  { action: 'delete', keys: ['Delete'], does: "delete the timeline's selected range, else the selected keys (their knots), else the selected object" },
  { action: 'duplicate', keys: ['Shift', 'D'], does: 'duplicate the selected object' },
  { action: 'rename', keys: ['F2'], does: 'rename the selected object' },
  { action: 'frame-all', keys: ['Home'], does: 'curve editor: frame all' },
  { action: 'frame-selection', keys: ['F'], does: 'curve editor: frame the selection' },
  { action: 'insert-knot', keys: ['I'], does: 'curve editor: insert a knot at the playhead' },
  { action: 'normalise', keys: ['N'], does: 'curve editor: normalise the channels on / off' },
  { action: 'copy', keys: ['Ctrl', 'C'], does: "timeline: copy the selected range (the selected lane's)" },
  { action: 'cut', keys: ['Ctrl', 'X'], does: 'timeline: cut the selected range' },
  { action: 'paste', keys: ['Ctrl', 'V'], does: 'timeline: paste at the playhead on the selected lane' },
  { action: 'undo', keys: ['Ctrl', 'Z'], does: 'undo' },
  { action: 'redo', keys: ['Ctrl', 'Shift', 'Z'], does: 'redo (also Ctrl+Y)' },
  { action: 'help', keys: ['?'], does: 'this list of shortcuts' },
];

/** @type {{where: string, gesture: string, does: string}[]} the mouse's gestures, as the help overlay lists them */
export const GESTURES = [
  { where: 'view', gesture: 'drag an object', does: 'move it (in record mode: perform a take)' },
  { where: 'view', gesture: 'drag a path handle', does: "move that control point of the object's path" },
  { where: 'view', gesture: "drag a chain's green goal / its body", does: 'pose the chain by its goal / move its base (record mode: a take of it)' },
  { where: 'view', gesture: "drag a walker's green marker or its body", does: 'walk it along the floor (record mode: a take of its path)' },
  { where: 'timeline ruler', gesture: 'drag / Shift-drag', does: 'scrub / set the loop range' },
  { where: 'timeline', gesture: 'click an object row', does: 'fold / unfold its lanes (wheel: scroll the lanes)' },
  { where: 'timeline', gesture: "drag a take's block / its right edge", does: 'move the take / stretch it about its start (Ctrl: about the playhead)' },
  { where: 'timeline', gesture: 'Alt-drag a lane', does: 'move its whole track (the selected lanes, if in the range)' },
  { where: 'timeline', gesture: 'drag on empty time / Shift-drag', does: "select a range (across lanes); its right edge stretches the tracks; Esc drops a drag" },
  { where: 'timeline', gesture: 'double-click a lane', does: 'select the loop range there (no loop: the whole track)' },
  { where: 'curves', gesture: 'drag a point, a key or a handle', does: 'move it (one undo step on release; Esc cancels)' },
  { where: 'curves', gesture: 'drag on empty space / Shift-click', does: 'box-select / add to the selection' },
  { where: 'curves', gesture: 'double-click a curve', does: 'insert a knot there' },
  { where: 'curves', gesture: 'wheel / Ctrl- or Shift-wheel', does: 'zoom time / zoom values' },
  { where: 'curves', gesture: 'middle-drag or Alt-drag', does: 'pan' },
  { where: 'outliner, takes', gesture: 'double-click a name', does: 'rename it (Enter keeps, Esc cancels)' },
];

/** @type {Record<string, KeyAction>} the plain keys (no Ctrl, Cmd or Alt; Shift ignored), by their lower-case `key` */
const PLAIN = { r: 'record', ' ': 'play', enter: 'stop', l: 'loop', c: 'camera', escape: 'deselect',
  w: 'translate', e: 'rotate', s: 'scale', arrowleft: 'previous-frame', arrowright: 'next-frame', delete: 'delete',
  backspace: 'delete', f2: 'rename', home: 'frame-all', f: 'frame-selection', i: 'insert-knot', n: 'normalise',
  p: 'motion-paths', o: 'onion-skin', m: 'cue', '?': 'help' };
/** @type {Record<string, KeyAction>} the keys with Ctrl (Cmd) that copy, cut and paste */
const CLIPBOARD = { c: 'copy', x: 'cut', v: 'paste' };
/** @type {Record<string, KeyAction>} the keys with Shift that do something else than without */
const SHIFTED = { s: 'snap', d: 'duplicate' };

/**
 * The action a key press asks for, or null.
 * @param {Keys} e
 * @returns {KeyAction | null}
 *
 * @example
 * actionOf({key: 'z', ctrlKey: true, metaKey: false, shiftKey: true, altKey: false});    // 'redo'
 * actionOf({key: 'D', ctrlKey: false, metaKey: false, shiftKey: true, altKey: false});   // 'duplicate'
 */
export function actionOf(e) {
  const key = e.key.toLowerCase();
  if (e.ctrlKey || e.metaKey) {
    if (key === 'z') return e.shiftKey ? 'redo' : 'undo';
    if (CLIPBOARD[key]) return CLIPBOARD[key];
    return key === 'y' ? 'redo' : null;
  }
  if (e.altKey) return null;
  if (e.shiftKey && SHIFTED[key]) return SHIFTED[key];
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
 * The panels' own actions: each goes out as the `command` signal.
 * @param {import('./Studio.js').Studio} studio
 * @returns {Record<PanelCommand, () => void>}
 */
function panelActions(studio) {
  /** @param {PanelCommand} c */
  const emit = (c) => () => studio.signals.emit('command', c);
  return { 'frame-all': emit('frame-all'), 'frame-selection': emit('frame-selection'), 'insert-knot': emit('insert-knot'),
    normalise: emit('normalise'), 'delete-points': emit('delete-points'), help: emit('help'),
    'motion-paths': emit('motion-paths'), 'onion-skin': emit('onion-skin'), rename: emit('rename'),
    'delete-range': emit('delete-range'), copy: emit('copy'), cut: emit('cut'), paste: emit('paste') };
}

/**
 * What each action does in the studio.
 * @param {import('./Studio.js').Studio} studio
 * @param {Pick<import('./viewport.js').Viewport, 'setGizmo' | 'togglePreviewCamera'>} viewport
 * @returns {Record<KeyAction, (stamp: number) => void>} each called with the key press's timeStamp
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
    'previous-frame': () => t.stepFrames(-1),
    'next-frame': () => t.stepFrames(1),
    delete: () => studio.deleteSelection(),
    duplicate: () => { if (studio.selected) studio.duplicateObject(studio.selected); },
    snap: () => studio.toggleSnap(),
    cue: (stamp) => studio.cue(stamp),
    ...panelActions(studio),
  };
}

/**
 * Run `actions` on the key presses `target` (the window) receives, in the capture phase:
 * a shortcut's key does only the shortcut (its default action prevented), whichever
 * control has focus, except while typing in a field.
 * @param {EventTarget} target
 * @param {Record<KeyAction, (stamp: number) => void>} actions called with the key press's timeStamp
 */
export function bindKeyboard(target, actions) {
  target.addEventListener('keydown', (event) => {
    const e = /** @type {KeyboardEvent} */ (event);
    if (typing(e.target)) return;
    const action = actionOf(e);
    if (!action) return;
    e.preventDefault();
    if (!e.repeat || action === 'undo' || action === 'redo') actions[action](e.timeStamp);
  }, { capture: true });
  // Space activates a focused button or checkbox on its key up: that default goes too.
  target.addEventListener('keyup', (event) => {
    const e = /** @type {KeyboardEvent} */ (event);
    if (!typing(e.target) && actionOf(e)) e.preventDefault();
  }, { capture: true });
}
