// @ts-check
/**
 * The outliner: the scene's objects; a click selects, a dot marks the animated ones. Its
 * tools act on the selected object: rename (also F2, or a double-click on its name: an inline
 * field, Enter keeps, Escape drops; a name is 1 to 64 letters, digits, `_` or `-`), duplicate
 * (also Shift+D) and delete (also Delete). "+ object" adds one in front of the camera, clear
 * of the others (placement.js); "+ chain" and "+ walker" add a rig there, standing on the floor
 * (a chain's base, a walker's ground marker). Each is one undoable step; none in a read-only project.
 */
import * as THREE from 'three';
import { el } from './dom.js';
import { placeInFront } from './placement.js';
import { PLACED } from './rigs.js';

const ICONS = { object: '◼', light: '☀', camera: '◉', cue: '♪', chain: '⚯', walker: '☺' };
/** The room an object fills around its position, by kind (metres, at scale 1): a new object is placed clear of it. */
const ROOM = { object: 0.75, light: 0.3, camera: 0.3, chain: 0.6, walker: 0.5 };
/** What the add buttons add: kind, label, tooltip. */
const ADDS = /** @type {const} */ ([
  ['object', '+ object', 'Add an object in front of the camera (undoable)'],
  ['chain', '+ chain', 'Add an articulated chain standing on the floor in front of the camera: drag its green goal to pose it (undoable)'],
  ['walker', '+ walker', 'Add a walking character in front of the camera: drag its green ground marker to walk it (undoable)'],
]);
/** What an object's name may be (as the server checks it). */
export const NAME = /^[A-Za-z0-9_-]{1,64}$/;

/**
 * Why `name` cannot be the new name of object `from` (among `names`), or '' when it can.
 * @param {string} name
 * @param {string} from
 * @param {string[]} names every object's name
 *
 * @example
 * nameProblem('box 2', 'box', ['box', 'ball']);   // 'a name is 1 to 64 letters, digits, _ or -'
 * nameProblem('ball', 'box', ['box', 'ball']);    // 'ball is taken'
 */
export function nameProblem(name, from, names) {
  if (!NAME.test(name)) return 'a name is 1 to 64 letters, digits, _ or -';
  return name !== from && names.includes(name) ? `${name} is taken` : '';
}

export class Outliner {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root
   * @param {Pick<import('./viewport.js').Viewport, 'camera'>} viewport whose camera new objects are placed in front of
   */
  constructor(studio, root, viewport) {
    this.studio = studio;
    this.viewport = viewport;
    this.list = el('ul', { class: 'outliner', 'data-testid': 'outliner' });
    this.addButtons = ADDS.map(([kind, label, title]) => {
      const button = el('button', { class: 'small', 'data-testid': `add-${kind}`, title }, label);
      button.addEventListener('click', () => this.add(kind));
      return button;
    });
    const head = el('div', { class: 'panel-head' }, 'Scene');
    const adds = el('div', { class: 'outliner-tools' });
    adds.append(...this.addButtons);
    this.renameButton = el('button', { class: 'small', 'data-testid': 'object-rename', title: 'Rename the selected object (F2)' }, 'rename');
    this.renameButton.addEventListener('click', () => this.startRename());
    this.duplicateButton = el('button', { class: 'small', 'data-testid': 'object-duplicate', title: 'Duplicate the selected object with its tracks (Shift+D)' }, 'duplicate');
    this.duplicateButton.addEventListener('click', () => { if (studio.selected) studio.duplicateObject(studio.selected); });
    this.deleteButton = el('button', { class: 'small', 'data-testid': 'object-delete', title: 'Delete the selected object and its tracks (Delete)' }, 'delete');
    this.deleteButton.addEventListener('click', () => { if (studio.selected) studio.removeObject(studio.selected); });
    const tools = el('div', { class: 'outliner-tools' });
    tools.append(this.renameButton, this.duplicateButton, this.deleteButton);
    root.append(head, adds, tools, this.list);
    /** @type {{name: string, text: string, problem: string} | null} the object being renamed, the text typed, what is wrong with it */
    this.renaming = null;
    /** @type {{from: string, to: string} | null} a rename sent: its object is selected again under the new name */
    this.renamed = null;
    for (const signal of /** @type {const} */ (['state', 'selection', 'tracks', 'lock'])) studio.signals.on(signal, () => this.show());
    studio.signals.on('state', () => this.followRename());
    studio.signals.on('command', (c) => { if (c === 'rename') this.startRename(); });
  }

  /** After a rename went through, select the object under its new name (the state dropped the old one). */
  followRename() {
    const r = this.renamed;
    if (!r) return;
    const names = this.studio.objects.map((o) => o.name);
    if (names.includes(r.to) && !names.includes(r.from)) {
      this.renamed = null;
      this.studio.select(r.to);
    }
  }

  /**
   * Add an object (or a rig, on the floor) in front of the view's camera, clear of every other object.
   * @param {import('./messages.js').ObjectKind} [kind]
   */
  add(kind = 'object') {
    const s = this.studio;
    const camera = this.viewport.camera;
    const direction = camera.getWorldDirection(new THREE.Vector3());
    const occupied = s.objects.flatMap((o) => {
      const position = s.values.get(`${o.name}.${PLACED[/** @type {keyof PLACED} */ (o.kind)] ?? 'position'}`);
      if (!position) return [];
      const scale = s.values.get(`${o.name}.scale`) ?? [1, 1, 1];
      return [{ position, radius: (ROOM[/** @type {keyof ROOM} */ (o.kind)] ?? 0.5) * Math.max(...scale.map(Math.abs)) }];
    });
    const at = placeInFront(camera.position.toArray(), direction.toArray(), occupied);
    if (kind === 'chain' || kind === 'walker') at[1] = 0;                 // rigs stand on the floor
    s.addObject(kind, at);
  }

  /** Edit the selected object's name in its row. */
  startRename() {
    const s = this.studio;
    if (!s.selected || s.readOnly) return;
    this.renaming = { name: s.selected, text: s.selected, problem: '' };
    this.show();
    this.list.querySelector('input')?.select();
  }

  /** Send the rename typed (when the name is good; else say why in the row). */
  commitRename() {
    const r = this.renaming;
    if (!r) return;
    const to = r.text.trim();
    r.problem = nameProblem(to, r.name, this.studio.objects.map((o) => o.name));
    if (r.problem) { this.show(); return; }
    this.renaming = null;
    if (to !== r.name) {
      this.renamed = { from: r.name, to };
      this.studio.renameObject(r.name, to);
    }
    this.show();
  }

  show() {
    const s = this.studio;
    // a rename field keeps the focus across a rebuild of the rows (and takes it when just opened)
    const open = this.list.querySelector('input');
    const refocus = !open || open === document.activeElement;
    const none = !s.selected || s.readOnly;
    this.renameButton.disabled = none;
    this.duplicateButton.disabled = none;
    this.deleteButton.disabled = none;
    for (const button of this.addButtons) button.disabled = s.readOnly;
    if (this.renaming && (s.readOnly || !s.objects.some((o) => o.name === this.renaming?.name))) this.renaming = null;
    this.list.replaceChildren(...s.objects.map((o) => {
      const animated = [...s.tracks.keys()].some((p) => p.startsWith(`${o.name}.`));
      const item = el('li', { 'data-object': o.name, title: `${o.kind} ${o.name}${animated ? ' (animated)' : ''}` });
      item.classList.toggle('selected', o.name === s.selected);
      const name = this.renaming?.name === o.name ? this.renameField(this.renaming) : el('span', { class: 'name' }, o.name);
      item.append(el('span', { class: `icon ${o.kind}` }, ICONS[/** @type {keyof ICONS} */ (o.kind)] ?? '•'),
        name, el('span', { class: animated ? 'anim on' : 'anim' }, animated ? '●' : ''));
      item.addEventListener('click', () => { if (!this.renaming) s.select(o.name); });
      item.addEventListener('dblclick', () => { if (!this.renaming) { s.select(o.name); this.startRename(); } });
      return item;
    }));
    const input = this.list.querySelector('input');
    if (input && refocus) input.focus();
  }

  /**
   * The inline field a name is edited in: Enter keeps the name (if it is good), Escape drops it.
   * @param {{name: string, text: string, problem: string}} r
   */
  renameField(r) {
    const wrap = el('span', { class: 'rename' });
    const input = el('input', { type: 'text', class: 'name', 'data-testid': 'object-name', maxlength: '64', spellcheck: 'false' });
    input.value = r.text;
    input.addEventListener('input', () => { r.text = input.value; r.problem = ''; problem.textContent = ''; });
    // clicking away drops it; a rebuild of the rows (which blurs it too) leaves the new field focused
    input.addEventListener('blur', () => setTimeout(() => {
      if (!this.renaming || this.list.querySelector('input') === document.activeElement) return;
      this.renaming = null;
      this.show();
    }));
    input.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') this.commitRename();
      else if (e.key === 'Escape') { this.renaming = null; this.show(); }
    });
    input.addEventListener('click', (e) => e.stopPropagation());
    const problem = el('span', { class: 'rename-problem', 'data-testid': 'rename-problem', role: 'alert' }, r.problem);
    wrap.append(input, problem);
    return wrap;
  }
}
