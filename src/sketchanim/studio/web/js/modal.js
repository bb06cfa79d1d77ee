// @ts-check
/**
 * A modal <dialog> of the page (the export and project dialogs): opened over everything,
 * closed by Escape, its Close button or a click outside its card, the focus given back to
 * where it was. While it is open no shortcut acts: its key listener, on the window in the
 * capture phase, is added before the keyboard's (main.js builds the dialogs first) and stops
 * every key but Tab there; what the keys do in the dialog's fields is their default action
 * (typing, a form's submit on Enter), which still happens.
 */
import { el } from './dom.js';

export class Modal {
  /**
   * @param {Window} win whose keys the open dialog keeps from the shortcuts
   * @param {string} testid the dialog's `data-testid`
   * @param {string} title its heading
   */
  constructor(win, testid, title) {
    this.dialog = el('dialog', { class: 'modal', 'data-testid': testid, 'aria-label': title });
    /** where the dialog's own parts go */
    this.body = el('div', { class: 'modal-body' });
    this.message = el('p', { class: 'modal-error', 'data-testid': `${testid}-error`, role: 'alert', hidden: '' });
    const close = el('button', { type: 'button', class: 'small', 'data-testid': `${testid}-close` }, 'Close');
    close.addEventListener('click', () => this.close());
    this.dialog.append(el('div', { class: 'panel-head' }, title), this.body, this.message, close);
    this.dialog.addEventListener('click', (e) => { if (e.target === this.dialog) this.close(); });   // the backdrop
    this.dialog.addEventListener('close', () => this.returnFocus?.focus());
    document.body.append(this.dialog);
    /** @type {HTMLElement | null} where the focus was before the dialog opened */
    this.returnFocus = null;
    win.addEventListener('keydown', (event) => {
      const e = /** @type {KeyboardEvent} */ (event);
      if (!this.open || e.key === 'Tab') return;
      e.stopImmediatePropagation();                 // no shortcut acts under the dialog
      if (e.key !== 'Escape') return;
      e.preventDefault();
      this.close();
    }, { capture: true });
  }

  get open() {
    return this.dialog.open;
  }

  /** Open it (no error shown), keeping where the focus was. */
  show() {
    if (this.open) return;
    this.returnFocus = /** @type {HTMLElement | null} */ (document.activeElement);
    this.say('');
    this.dialog.showModal();
  }

  close() {
    if (this.open) this.dialog.close();
  }

  /** @param {string} text an error to show, or '' for none */
  say(text) {
    this.message.textContent = text;
    this.message.hidden = !text;
  }
}
