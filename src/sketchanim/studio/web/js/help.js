// @ts-check
/**
 * The help overlay: every shortcut of the studio (keyboard.js's SHORTCUTS) and the mouse's
 * gestures (GESTURES), opened by `?`
 * (the `command` signal 'help') or the `?` button in the header; closed by Escape, `?` or a
 * click outside its card. While it is open, its own key listener (on the window, in the
 * capture phase, added before the keyboard's: main.js builds it first) stops every key there
 * (no shortcut acts under the overlay; Tab still moves the focus), and Escape or `?` closes it,
 * so Escape does not also select nothing.
 */
import { el } from './dom.js';
import { GESTURES, SHORTCUTS } from './keyboard.js';

/** Whether the keys read Cmd for Ctrl (a Mac). */
const MAC = typeof navigator !== 'undefined' && /Mac|iPhone|iPad/.test(navigator.platform);

export class Help {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} header where the `?` button goes (the page's header)
   * @param {Window} win whose keys close the overlay (listened to before the keyboard's shortcuts)
   */
  constructor(studio, header, win) {
    this.button = el('button', { class: 'small help-button', 'data-testid': 'help-button', title: 'Keyboard shortcuts (?)' }, '?');
    this.button.addEventListener('click', () => this.toggle());
    header.append(this.button);
    this.overlay = el('div', { class: 'help-overlay', 'data-testid': 'help', hidden: '' });
    const card = el('div', { class: 'help-card', role: 'dialog', 'aria-label': 'Keyboard shortcuts' });
    const table = el('table', { class: 'help-keys' });
    for (const s of SHORTCUTS) {
      const row = el('tr', { 'data-action': s.action });
      const keys = el('td', { class: 'keys' });
      s.keys.forEach((k, i) => {
        if (i) keys.append('+');
        keys.append(el('kbd', {}, MAC && k === 'Ctrl' ? 'Cmd' : k));
      });
      row.append(keys, el('td', {}, s.does));
      table.append(row);
    }
    const gestures = el('table', { class: 'help-keys', 'data-testid': 'help-gestures' });
    for (const g of GESTURES) {
      const row = el('tr');
      row.append(el('td', { class: 'keys' }, g.where), el('td', {}, `${g.gesture}: ${g.does}`));
      gestures.append(row);
    }
    card.append(el('div', { class: 'panel-head' }, 'Keyboard shortcuts'), table, el('div', { class: 'panel-head' }, 'Mouse'), gestures,
      el('p', { class: 'hint' }, 'Esc, ? or a click outside closes this.'));
    this.overlay.append(card);
    this.overlay.addEventListener('click', (e) => { if (e.target === this.overlay) this.close(); });
    document.body.append(this.overlay);
    studio.signals.on('command', (c) => { if (c === 'help') this.toggle(); });
    win.addEventListener('keydown', (event) => {
      const e = /** @type {KeyboardEvent} */ (event);
      if (!this.open || e.key === 'Tab') return;
      e.stopImmediatePropagation();                 // no shortcut acts under the overlay
      if (e.key !== 'Escape' && e.key !== '?') return;
      e.preventDefault();
      if (!e.repeat) this.close();
    }, { capture: true });
  }

  get open() {
    return !this.overlay.hidden;
  }

  toggle() {
    if (this.open) this.close();
    else this.overlay.hidden = false;
  }

  close() {
    this.overlay.hidden = true;
  }
}
