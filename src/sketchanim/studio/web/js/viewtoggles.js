// @ts-check
/**
 * What the 3D view draws over the scene, and the buttons that switch it (bottom left of the
 * view): motion paths (P; on at first), onion skin (O; off at first), and whether both show
 * every animated object or only the selected one.
 */
import { el } from './dom.js';

/** @typedef {'paths' | 'onion' | 'all'} ToggleName */

/** @type {{name: ToggleName, testid: string, text: string, title: string}[]} */
const BUTTONS = [
  { name: 'paths', testid: 'motion-paths', text: 'Paths', title: 'Motion paths of animated positions (P)' },
  { name: 'onion', testid: 'onion-skin', text: 'Onion', title: 'Onion skin: ghosts at nearby frames (O)' },
  { name: 'all', testid: 'overlays-all', text: 'All objects', title: 'Paths and ghosts of every animated object, not only the selected one' },
];

export class ViewToggles {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} container the view's element (the buttons go over its canvas)
   */
  constructor(studio, container) {
    /** @type {Record<ToggleName, boolean>} */
    this.on = { paths: true, onion: false, all: false };
    this.bar = el('div', { class: 'view-toggles', 'data-testid': 'view-toggles' });
    /** @type {Map<ToggleName, HTMLButtonElement>} */
    this.buttons = new Map();
    for (const b of BUTTONS) {
      const button = el('button', { type: 'button', 'data-testid': b.testid, title: b.title }, b.text);
      button.addEventListener('click', () => this.flip(b.name));
      this.buttons.set(b.name, button);
      this.bar.append(button);
    }
    container.append(this.bar);
    studio.signals.on('command', (c) => {
      if (c === 'motion-paths') this.flip('paths');
      else if (c === 'onion-skin') this.flip('onion');
    });
    this.show();
  }

  /**
   * Switch one on or off.
   * @param {ToggleName} name
   */
  flip(name) {
    this.on[name] = !this.on[name];
    this.show();
  }

  show() {
    for (const [name, button] of this.buttons) button.setAttribute('aria-pressed', String(this.on[name]));
  }
}
