// @ts-check
/**
 * Clips into the scene from the outliner: a file input (`data-testid="import-clip"`) whose
 * chosen .bvh or .c3d is posted raw to `POST /api/clips?name=FILE` — the server adds each joint
 * as an object with its world position and orientation tracks (each marker: its position, and
 * `visible` false where it was not seen), one undoable step, and every page
 * gets the new state. The line under it says what is happening or what was refused (the
 * server's 4xx `detail`: a truncated file's line, a wrong type, a size over the limit); a
 * refusal is also a notice. Nothing changes on a refusal.
 */
import { el } from './dom.js';
import { fetchJson, reason } from './api.js';

export class ClipImport {
  /**
   * @param {import('./Studio.js').Studio} studio where refusals are told
   * @param {HTMLElement} root the outliner's panel (its list built: main.js builds the Outliner first)
   */
  constructor(studio, root) {
    this.studio = studio;
    this.input = el('input', { type: 'file', accept: '.bvh,.c3d', 'data-testid': 'import-clip' });
    const label = el('label', { class: 'clip-import', title: 'Add a motion clip: each joint (.bvh) or marker (.c3d) an object with its tracks (undoable)' }, 'import clip (.bvh, .c3d) ');
    label.append(this.input);
    this.status = el('div', { class: 'hint clip-status', 'data-testid': 'import-clip-status', role: 'status' });
    const list = root.querySelector('[data-testid=outliner]');     // above the objects' list, which may be long
    for (const part of [label, this.status]) root.insertBefore(part, list);
    this.input.addEventListener('change', () => {
      const file = this.input.files?.[0];
      if (file) this.send(file).finally(() => { this.input.value = ''; });
    });
  }

  /**
   * Post the file; say what came of it.
   * @param {File} file
   */
  async send(file) {
    this.input.disabled = true;
    this.status.textContent = `importing ${file.name}…`;
    try {
      /** @type {{objects: string[], tracks: number, frames: number, seconds: number}} */
      const made = await fetchJson(`/api/clips?name=${encodeURIComponent(file.name)}`, { method: 'POST', body: file });
      const what = file.name.toLowerCase().endsWith('.c3d') ? 'markers' : 'joints';
      this.status.textContent = `${file.name}: ${made.objects.length} ${what}, ${made.frames} frames (${made.seconds.toFixed(1)} s)`;
    } catch (err) {
      const text = `${file.name} was not imported: ${reason(err)}`;
      this.status.textContent = text;
      this.studio.tell('error', text, 'clip');
    } finally {
      this.input.disabled = false;
    }
  }
}
