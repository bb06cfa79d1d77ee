// @ts-check
/**
 * The layers panel (under the inspector): the takes of the track the curve view shows (the
 * selected object's attribute), in the order they are composed, each with its name, span
 * (frames and seconds), layer mode, smoothing, loop pass and whether it is muted. Per take:
 * mute / unmute, solo, delete, rename (double-click the name: Enter keeps, Escape drops),
 * move up / down, and for a pass of a loop recording "keep this pass". Each is one
 * `take.edit` (one History step); the server composes the track again from its takes, which
 * drops hand edits of its curve (the panel says so when there are any). Undo and redo in its
 * head. Disabled in a read-only project.
 */
import { el } from './dom.js';

/** @typedef {import('./messages.js').TakeSpanInfo} TakeSpanInfo */
/** @typedef {import('./messages.js').CurveTrack} CurveTrack */
/** @typedef {import('./messages.js').TakeOp} TakeOp */

/** What the layer modes are called on the page (as in the transport bar's menu). */
const MODES = { replace: 'punch-in', additive: 'additive' };

/**
 * A take's name as the panel shows it: its own, else "take N" (N from 1).
 * @param {TakeSpanInfo} take
 * @param {number} index
 *
 * @example
 * takeName({start: 0, end: 1, mode: 'replace', n: 9, smoothing: 0}, 2);   // 'take 3'
 */
export function takeName(take, index) {
  return take.name || `take ${index + 1}`;
}

/**
 * A take's span in frames at `fps` and in seconds.
 * @param {TakeSpanInfo} take
 * @param {number} fps
 *
 * @example
 * spanText({start: 0.5, end: 2, mode: 'replace', n: 9, smoothing: 0}, 24);   // 'f 12–48 · 0.50–2.00 s'
 */
export function spanText(take, fps) {
  return `f ${Math.round(take.start * fps)}–${Math.round(take.end * fps)} · ${take.start.toFixed(2)}–${take.end.toFixed(2)} s`;
}

/**
 * The loop recordings among `takes`: for each take that is part of one, its pass (from 1;
 * a pass may be several takes), the number of passes of its loop, and whether it is the
 * loop's first take (where the panel heads the loop).
 * @param {TakeSpanInfo[]} takes
 * @returns {Map<number, {pass: number, of: number, first: boolean}>} by take index
 *
 * @example
 * const t = {start: 0, end: 1, mode: 'replace', n: 9, smoothing: 0};
 * loopPasses([t, {...t, loop: 'a', loop_pass: 0}, {...t, loop: 'a', loop_pass: 1}]).get(2);   // {pass: 2, of: 2, first: false}
 */
export function loopPasses(takes) {
  /** @type {Map<string, Set<number>>} the passes of each loop recording */
  const byLoop = new Map();
  for (const t of takes) if (t.loop) byLoop.set(t.loop, (byLoop.get(t.loop) ?? new Set()).add(t.loop_pass ?? 0));
  const passes = new Map();
  const headed = new Set();
  takes.forEach((t, i) => {
    if (!t.loop) return;
    const ids = [...(byLoop.get(t.loop) ?? [])].sort((x, y) => x - y);
    passes.set(i, { pass: ids.indexOf(t.loop_pass ?? 0) + 1, of: ids.length, first: !headed.has(t.loop) });
    headed.add(t.loop);
  });
  return passes;
}

export class Layers {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root where the panel's section is appended (the inspector's column)
   */
  constructor(studio, root) {
    this.studio = studio;
    this.title = el('span', {}, 'Takes');
    this.undoButton = el('button', { class: 'small', 'data-testid': 'layers-undo', title: 'Undo (Ctrl+Z)' }, '↶');
    this.undoButton.addEventListener('click', () => studio.undo());
    this.redoButton = el('button', { class: 'small', 'data-testid': 'layers-redo', title: 'Redo (Ctrl+Shift+Z)' }, '↷');
    this.redoButton.addEventListener('click', () => studio.redo());
    const buttons = el('span', { class: 'head-buttons' });
    buttons.append(this.undoButton, this.redoButton);
    const head = el('div', { class: 'panel-head' });
    head.append(this.title, buttons);
    this.note = el('p', { class: 'layers-note', 'data-testid': 'layers-edited', hidden: '' },
      'This curve was edited by hand: a change here composes it again from its takes and drops those edits.');
    this.list = el('ol', { class: 'layers', 'data-testid': 'layers' });
    const section = el('section', { class: 'layers-panel' });
    section.append(head, this.note, this.list);
    root.append(section);
    /** @type {{path: string, index: number, text: string} | null} the take whose name is being edited, and the text typed so far */
    this.renaming = null;
    const signals = studio.signals;
    for (const signal of /** @type {const} */ (['state', 'selection', 'attribute', 'tracks', 'lock', 'projectSettings'])) {
      signals.on(signal, () => this.show());
    }
    for (const signal of /** @type {const} */ (['state', 'history', 'lock'])) signals.on(signal, () => this.showHistory());
  }

  /** The path of the track shown (the selected object's attribute in the curve view), or null. */
  get path() {
    const s = this.studio;
    return s.selected ? `${s.selected}.${s.attribute}` : null;
  }

  /** @returns {CurveTrack | null} */
  get curve() {
    const track = this.path ? this.studio.tracks.get(this.path) : undefined;
    return track?.kind === 'curve' ? track : null;
  }

  showHistory() {
    const { history: h, readOnly } = this.studio;
    this.undoButton.disabled = !h.can_undo || readOnly;
    this.redoButton.disabled = !h.can_redo || readOnly;
    this.undoButton.title = h.can_undo ? `Undo ${h.undo[h.undo.length - 1]} (Ctrl+Z)` : 'Nothing to undo';
    this.redoButton.title = h.can_redo ? `Redo ${h.redo[h.redo.length - 1]} (Ctrl+Shift+Z)` : 'Nothing to redo';
  }

  show() {
    const s = this.studio;
    // a rename field keeps the focus across a rebuild of the rows (and takes it when just opened)
    const open = this.list.querySelector('input');
    const refocus = !open || open === document.activeElement;
    const path = this.path;
    const curve = this.curve;
    this.title.textContent = path ? `Takes · ${s.attribute}` : 'Takes';
    this.note.hidden = !curve?.edited;
    if (this.renaming && (this.renaming.path !== path || !curve || this.renaming.index >= curve.takes.length)) this.renaming = null;
    if (!curve || !curve.takes.length) {
      this.list.replaceChildren(el('li', { class: 'hint' }, path
        ? `${path} has no takes: turn REC on and grab it to record one.`
        : 'Select an object to see the takes of its attribute.'));
      return;
    }
    const passes = loopPasses(curve.takes);
    const playing = curve.takes.filter((t) => !t.muted).length;
    this.list.replaceChildren(...curve.takes.flatMap((_, i) => {
      const pass = passes.get(i) ?? null;
      const row = this.row(curve.path, curve.takes, i, pass, playing);
      return pass?.first ? [el('li', { class: 'loop-head' }, `⟲ loop recording · ${pass.of} passes`), row] : [row];
    }));
    const input = this.list.querySelector('input');
    if (input && refocus) input.focus();
  }

  /**
   * One take's row.
   * @param {string} path
   * @param {TakeSpanInfo[]} takes
   * @param {number} i
   * @param {{pass: number, of: number, first: boolean} | null} pass
   * @param {number} playing how many takes are not muted
   */
  row(path, takes, i, pass, playing) {
    const s = this.studio;
    const take = takes[i];
    const item = el('li', { 'data-take': String(i), class: `take${take.muted ? ' muted' : ''}${pass ? ' pass' : ''}` });
    const top = el('div', { class: 'take-top' });
    top.append(this.nameElement(path, take, i));
    const info = [spanText(take, s.fps), MODES[/** @type {keyof MODES} */ (take.mode)] ?? take.mode];
    if (take.smoothing > 0) info.push(`smoothed ${take.smoothing} s`);
    if (pass) info.push(`loop pass ${pass.pass}/${pass.of}`);
    if (take.muted) info.push('muted');
    const details = el('div', { class: 'take-info' }, info.join(' · '));
    const act = (/** @type {TakeOp} */ op, /** @type {{to?: number}} */ args = {}) => () => s.editTake(path, i, op, args);
    const lastPlaying = !take.muted && playing === 1;
    const buttons = [
      button('take-mute', 'M', take.muted ? 'Unmute: the take plays again' : lastPlaying ? 'The only take that plays cannot be muted' : 'Mute: leave the take out of the curve',
        act(take.muted ? 'unmute' : 'mute'), lastPlaying),
      button('take-solo', 'S', 'Solo: mute every other take', act('solo'), takes.length === 1),
      button('take-up', '↑', 'Move up: composed earlier', act('move', { to: i - 1 }), i === 0),
      button('take-down', '↓', 'Move down: composed later', act('move', { to: i + 1 }), i === takes.length - 1),
    ];
    if (pass) buttons.push(button('take-keep', 'keep', 'Keep this pass of the loop recording (mute the other passes)', act('keep'), false));
    buttons.push(button('take-delete', '✕', takes.length === 1 ? 'Delete the take (the last one: the track goes)' : 'Delete the take', act('delete'), false));
    buttons[0].classList.toggle('on', !!take.muted);
    buttons[0].setAttribute('aria-pressed', String(!!take.muted));
    const tools = el('div', { class: 'take-tools' });
    tools.append(...buttons);
    for (const b of buttons) b.disabled = b.disabled || s.readOnly;
    top.append(tools);
    item.append(top, details);
    return item;
  }

  /**
   * A take's name, or the field its name is edited in (Enter keeps it, Escape drops it).
   * @param {string} path
   * @param {TakeSpanInfo} take
   * @param {number} i
   */
  nameElement(path, take, i) {
    const s = this.studio;
    const editing = this.renaming?.path === path && this.renaming.index === i ? this.renaming : null;
    if (editing) {
      const input = el('input', { type: 'text', class: 'take-name', 'data-testid': 'take-name', maxlength: '64',
        placeholder: takeName(take, i) });
      input.value = editing.text;
      input.addEventListener('input', () => { editing.text = input.value; });
      // clicking away drops it; a rebuild of the rows (which blurs it too) leaves the new field focused
      input.addEventListener('blur', () => setTimeout(() => {
        if (!this.renaming || this.list.querySelector('input') === document.activeElement) return;
        this.renaming = null;
        this.show();
      }));
      input.addEventListener('keydown', (e) => {
        if (e.key !== 'Enter' && e.key !== 'Escape') return;
        this.renaming = null;
        const name = input.value.trim();
        if (e.key === 'Enter' && name !== (take.name ?? '')) s.editTake(path, i, 'rename', { name });
        this.show();
      });
      return input;
    }
    const name = el('span', { class: 'take-name', 'data-testid': 'take-name', title: s.readOnly ? '' : 'Double-click to rename' }, takeName(take, i));
    name.classList.toggle('unnamed', !take.name);
    name.addEventListener('dblclick', () => {
      if (s.readOnly) return;
      this.renaming = { path, index: i, text: take.name ?? '' };
      this.show();
      this.list.querySelector('input')?.select();
    });
    return name;
  }
}

/**
 * A small button of a take's row.
 * @param {string} testid
 * @param {string} text
 * @param {string} title
 * @param {() => void} onClick
 * @param {boolean} disabled
 */
function button(testid, text, title, onClick, disabled) {
  const b = el('button', { class: 'small', 'data-testid': testid, title }, text);
  b.disabled = disabled;
  b.addEventListener('click', onClick);
  return b;
}
