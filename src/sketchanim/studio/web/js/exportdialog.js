// @ts-check
/**
 * The export dialog: the header's Export button (`data-testid="export"`) opens a modal
 * dialog (modal.js) listing what the server offers (`GET /api/export/choices`: each format,
 * its file, and what each client plays from it, within which tolerance); a choice's button
 * fetches `GET /api/export?format=...` and hands the file to the browser as a download (an
 * <a download> to the fetched file), then the dialog closes. A refusal (the server's 4xx
 * JSON `detail`) is shown in the dialog, which stays open.
 */
import { el } from './dom.js';
import { fetchJson, reason, refusal } from './api.js';
import { Modal } from './modal.js';

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

export class ExportDialog {
  /**
   * @param {HTMLElement} header where the Export button goes (the page's header)
   * @param {Window} win whose keys the open dialog keeps from the shortcuts
   */
  constructor(header, win) {
    this.button = el('button', { class: 'small', 'data-testid': 'export', title: 'Export the scene or the project' }, 'Export…');
    this.button.addEventListener('click', () => this.show());
    header.append(this.button);
    this.modal = new Modal(win, 'export-dialog', 'Export');
    this.list = el('div', { class: 'export-choices' });
    this.modal.body.append(this.list,
      el('p', { class: 'hint' }, 'Tolerances are the largest of the tracks each file animates (docs/clients.md). Esc closes this.'));
  }

  /** Open the dialog and fill it with the server's choices. */
  async show() {
    if (this.modal.open) return;
    this.list.replaceChildren(el('p', { class: 'hint' }, 'asking the server…'));
    this.modal.show();
    try {
      /** @type {{choices: ExportChoice[]}} */
      const body = await fetchJson('/api/export/choices');
      this.list.replaceChildren(...body.choices.map((c) => this.choice(c)));
      /** @type {HTMLElement | null} */ (this.list.querySelector('button'))?.focus();
    } catch (err) {
      this.list.replaceChildren();
      this.modal.say(`no export choices: ${reason(err)}`);
    }
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
    if (c.left_out.length) block.append(el('p', { class: 'hint' }, `left out (${c.format === 'bvh' ? 'BVH holds the skeletons only' : 'glTF and USD animate transforms only'}): ${c.left_out.join(', ')}`));
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
    this.modal.say('');
    try {
      const response = await fetch(`/api/export?format=${encodeURIComponent(c.format)}`);
      if (!response.ok) throw new Error(await refusal(response));
      const url = URL.createObjectURL(await response.blob());
      const link = el('a', { href: url, download: c.file, hidden: '' });
      document.body.append(link);
      link.click();
      link.remove();
      setTimeout(() => URL.revokeObjectURL(url), 60_000);
      this.modal.close();
    } catch (err) {
      this.modal.say(`${c.file} was not made: ${reason(err)}`);
    } finally {
      button.disabled = false;
    }
  }
}
