// @ts-check
/**
 * The project dialog: the header's Project button (`data-testid="files"`) opens a modal
 * dialog (modal.js) to save the project as a new one in the files folder (`POST
 * /api/project/save-as?name=...`: the studio goes on with the copy) and to open a project of
 * the files folder or of the recent list (`POST /api/project/open?path=...`), as
 * `GET /api/recent` lists them. Every page then gets the new project's `state` from the
 * server. A refusal (the server's 4xx JSON `detail`) is shown in the dialog, which stays open.
 */
import { el } from './dom.js';
import { fetchJson, reason } from './api.js';
import { Modal } from './modal.js';

/**
 * A project the page may open (projectfiles.py's ProjectFile).
 * @typedef {object} ProjectFile
 * @property {string} path
 * @property {string} name
 * @property {boolean} exists
 * @property {number | null} [opened]
 */

/**
 * `GET /api/recent`'s answer (projectfiles.py's ProjectFiles).
 * @typedef {object} ProjectFiles
 * @property {string} current
 * @property {string} folder
 * @property {ProjectFile[]} recent
 * @property {ProjectFile[]} files
 */

/**
 * The name offered for a copy of the project `name`: its stem and "-copy".
 * @param {string} name
 * @returns {string}
 *
 * @example
 * copyName('show.sketchanim');   // 'show-copy.sketchanim'
 */
export function copyName(name) {
  return `${name.replace(/\.sketchanim$/i, '') || 'project'}-copy.sketchanim`;
}

export class FilesDialog {
  /**
   * @param {import('./Studio.js').Studio} studio whose project's name the copy's is made from
   * @param {HTMLElement} header where the Project button goes (the page's header)
   * @param {Window} win whose keys the open dialog keeps from the shortcuts
   */
  constructor(studio, header, win) {
    this.studio = studio;
    this.button = el('button', { class: 'small', 'data-testid': 'files', title: 'Save as, open, recent projects' }, 'Project…');
    this.button.addEventListener('click', () => this.show());
    header.append(this.button);
    this.modal = new Modal(win, 'files-dialog', 'Project');
    this.name = el('input', { type: 'text', 'data-testid': 'save-as-name', 'aria-label': 'New project name', spellcheck: 'false' });
    const form = el('form', { class: 'save-as' });
    form.append(el('label', { class: 'field' }, 'Save as'), this.name, el('button', { type: 'submit', 'data-testid': 'save-as' }, 'Save'));
    form.addEventListener('submit', (e) => { e.preventDefault(); this.saveAs(); });
    this.where = el('p', { class: 'hint' });
    this.lists = el('div', { class: 'project-lists' });
    this.modal.body.append(form, this.where, this.lists);
  }

  /** Open the dialog and fill it with the server's lists. */
  async show() {
    if (this.modal.open) return;
    this.name.value = copyName(this.studio.project);
    this.lists.replaceChildren(el('p', { class: 'hint' }, 'asking the server…'));
    this.modal.show();
    this.name.focus();
    this.name.select();
    try {
      /** @type {ProjectFiles} */
      const files = await fetchJson('/api/recent');
      this.where.textContent = `Copies go to ${files.folder}; the studio goes on with the copy.`;
      this.lists.replaceChildren(
        this.list('In the files folder', files.files, files.current, 'name', 'open-file'),
        this.list('Recent', files.recent, files.current, 'path', 'open-recent'));
    } catch (err) {
      this.lists.replaceChildren();
      this.modal.say(`no project lists: ${reason(err)}`);
    }
  }

  /**
   * A list of projects, each with an Open button (none for the open one or one gone).
   * @param {string} title
   * @param {ProjectFile[]} projects
   * @param {string} current the open project's path
   * @param {'name' | 'path'} by what the open request names it by
   * @param {string} testid the Open buttons' `data-testid`
   * @returns {HTMLElement}
   */
  list(title, projects, current, by, testid) {
    const block = el('section', { class: 'project-list' });
    block.append(el('div', { class: 'export-title' }, title));
    if (!projects.length) block.append(el('p', { class: 'hint' }, 'none'));
    for (const f of projects) {
      const row = el('div', { class: 'project-row', title: f.path });
      row.append(el('span', { class: 'project-name' }, f.name));
      if (f.path === current) row.append(el('span', { class: 'hint' }, 'open now'));
      else if (!f.exists) row.append(el('span', { class: 'hint' }, 'gone (moved or deleted)'));
      else {
        const open = el('button', { type: 'button', class: 'small', 'data-testid': testid, 'data-path': f.path }, 'Open');
        open.addEventListener('click', () => this.run(`/api/project/open?path=${encodeURIComponent(by === 'name' ? f.name : f.path)}`, f.name));
        row.append(open);
      }
      block.append(row);
    }
    return block;
  }

  saveAs() {
    const name = this.name.value.trim();
    this.run(`/api/project/save-as?name=${encodeURIComponent(name)}`, name);
  }

  /**
   * Post a save-as or an open; close the dialog when done (the server sends the new
   * project's state), or say why it was refused.
   * @param {string} url
   * @param {string} name the project's name, for the message
   */
  async run(url, name) {
    this.modal.say('');
    try {
      await fetchJson(url, { method: 'POST' });
      this.modal.close();
    } catch (err) {
      this.modal.say(`${name || 'the project'}: ${reason(err)}`);
    }
  }
}
