// @ts-check
/**
 * The export dialog: the header's Export button (`data-testid="export"`) opens a modal
 * <dialog> listing what the server offers (`GET /api/export/choices`: each format, its file,
 * and what each client plays from it, within which tolerance); a choice's button fetches
 * `GET /api/export?format=...` and hands the file to the browser as a download (an
 * <a download> to the fetched file), then the dialog closes. A refusal (the server's 4xx
 * JSON `detail`) is shown in the dialog, which stays open. Escape, the Close button or a
 * click outside the card closes it; the focus goes back to where it was. While it is open
 * no shortcut acts (its key listener, on the window in the capture phase, is added before
 * the keyboard's: main.js builds it first).
 */
import { el } from './dom.js';

/**
 * What one client plays from an export (downloads.py's ClientPlay).
 * @typedef {object} ClientPlay
 * @property {string} client
 * @property {string} plays
 */

/**
 * One choice of the dialog (downloads.py's ExportChoice).
 * @typedef {object} ExportChoice
 * @property {string} format
 * @property {string} title
 * @property {string} file
 * @property {ClientPlay[]} clients
 * @property {string[]} left_out
 */

/**
 * The server's words for a refused request: its JSON `detail`, or the status.
 * @param {Response} response
 * @returns {Promise<string>}
 */
export async function refusal(response) {
  try {
    const body = await response.json();
    if (typeof body.detail === 'string') return body.detail;
  } catch { /* not JSON: the status says it */ }
  return `the server answered ${response.status} ${response.statusText}`;
}

export class ExportDialog {
  /**
   * @param {HTMLElement} header where the Export button goes (the page's header)
   * @param {Window} win whose keys the open dialog keeps from the shortcuts
   */
  constructor(header, win) {
    this.button = el('button', { class: 'small export-button', 'data-testid': 'export', title: 'Export the scene or the project' }, 'Export…');
    this.button.addEventListener('click', () => this.show());
    header.append(this.button);
    this.dialog = el('dialog', { class: 'export-dialog', 'data-testid': 'export-dialog', 'aria-label': 'Export' });
    this.list = el('div', { class: 'export-choices' });
    this.message = el('p', { class: 'export-error', 'data-testid': 'export-error', role: 'alert', hidden: '' });
    const close = el('button', { class: 'small', 'data-testid': 'export-close' }, 'Close');
    close.addEventListener('click', () => this.close());
    this.dialog.append(el('div', { class: 'panel-head' }, 'Export'), this.list, this.message,
      el('p', { class: 'hint' }, 'Tolerances are the largest of the tracks each file animates (docs/clients.md). Esc closes this.'), close);
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

  /** Open the dialog and fill it with the server's choices. */
  async show() {
    if (this.open) return;
    this.returnFocus = /** @type {HTMLElement | null} */ (document.activeElement);
    this.say('');
    this.list.replaceChildren(el('p', { class: 'hint' }, 'asking the server…'));
    this.dialog.showModal();
    try {
      const response = await fetch('/api/export/choices');
      if (!response.ok) throw new Error(await refusal(response));
      /** @type {{choices: ExportChoice[]}} */
      const body = await response.json();
      this.list.replaceChildren(...body.choices.map((c) => this.choice(c)));
      /** @type {HTMLElement | null} */ (this.list.querySelector('button'))?.focus();
    } catch (err) {
      this.list.replaceChildren();
      this.say(`no export choices: ${err instanceof Error ? err.message : err}`);
    }
  }

  close() {
    if (this.open) this.dialog.close();
  }

  /** @param {string} text an error to show, or '' for none */
  say(text) {
    this.message.textContent = text;
    this.message.hidden = !text;
  }

  /**
   * One choice's block: its title, its clients and what they play, its download button.
   * @param {ExportChoice} c
   * @returns {HTMLElement}
   */
  choice(c) {
    const block = el('section', { class: 'export-choice', 'data-format': c.format });
    const get = el('button', { 'data-testid': `export-${c.format}` }, `Download ${c.file}`);
    get.addEventListener('click', () => this.download(c, get));
    const clients = el('ul', { class: 'export-clients' });
    for (const p of c.clients) {
      const item = el('li', {}, `${p.client}: `);
      item.append(el('b', {}, p.plays));
      clients.append(item);
    }
    block.append(el('div', { class: 'export-title' }, c.title), clients);
    if (c.left_out.length) block.append(el('p', { class: 'hint' }, `left out (glTF and USD animate transforms only): ${c.left_out.join(', ')}`));
    block.append(get);
    return block;
  }

  /**
   * Fetch the export and hand it to the browser as a download; close the dialog, or say
   * why the server refused.
   * @param {ExportChoice} c
   * @param {HTMLButtonElement} button disabled while the file is made
   */
  async download(c, button) {
    button.disabled = true;
    this.say('');
    try {
      const response = await fetch(`/api/export?format=${encodeURIComponent(c.format)}`);
      if (!response.ok) throw new Error(await refusal(response));
      const url = URL.createObjectURL(await response.blob());
      const link = el('a', { href: url, download: c.file, hidden: '' });
      document.body.append(link);
      link.click();
      link.remove();
      setTimeout(() => URL.revokeObjectURL(url), 60_000);
      this.close();
    } catch (err) {
      this.say(`${c.file} was not made: ${err instanceof Error ? err.message : err}`);
    } finally {
      button.disabled = false;
    }
  }
}
