// @ts-check
/** The outliner: the scene's objects; a click selects, a dot marks the animated ones; "+ object" adds one (not in a read-only project). */
import { el } from './dom.js';

const ICONS = { object: '◼', light: '☀', camera: '◉' };

export class Outliner {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root
   */
  constructor(studio, root) {
    this.studio = studio;
    this.list = el('ul', { class: 'outliner', 'data-testid': 'outliner' });
    const add = el('button', { class: 'small', 'data-testid': 'add-object', title: 'Add an object (undoable)' }, '+ object');
    add.addEventListener('click', () => studio.addObject());
    const head = el('div', { class: 'panel-head' }, 'Scene');
    head.append(add);
    root.append(head, this.list);
    for (const signal of /** @type {const} */ (['state', 'selection', 'tracks'])) studio.signals.on(signal, () => this.show());
    studio.signals.on('lock', () => { add.disabled = studio.readOnly; });
  }

  show() {
    const s = this.studio;
    this.list.replaceChildren(...s.objects.map((o) => {
      const animated = [...s.tracks.keys()].some((p) => p.startsWith(`${o.name}.`));
      const item = el('li', { 'data-object': o.name, title: `${o.kind} ${o.name}${animated ? ' (animated)' : ''}` });
      item.classList.toggle('selected', o.name === s.selected);
      item.append(el('span', { class: `icon ${o.kind}` }, ICONS[/** @type {keyof ICONS} */ (o.kind)] ?? '•'),
        el('span', { class: 'name' }, o.name), el('span', { class: animated ? 'anim on' : 'anim' }, animated ? '●' : ''));
      item.addEventListener('click', () => s.select(o.name));
      return item;
    }));
  }
}
