// @ts-check
/**
 * Clips into the scene from the outliner: a file input (`data-testid="import-clip"`) whose
 * chosen .bvh or .c3d is posted raw to `POST /api/clips?name=FILE` (an .asf and an .amc chosen
 * together: their texts as JSON to `POST /api/clips/amc?name=X.amc&skeleton=Y.asf`) — the server adds each joint
 * as an object with its world position and orientation tracks (each marker: its position, and
 * `visible` false where it was not seen), one undoable step, and every page
 * gets the new state. The line under it says what is happening or what was refused (the
 * server's 4xx `detail`: a truncated file's line, a wrong type, a size over the limit); a
 * refusal is also a notice. Nothing changes on a refusal. The line says what was imported once
 * the new objects are in this page's state (the server's answer can overtake its broadcast), or
 * after ARRIVAL_MS if another page changed them first.
 */
import { el } from './dom.js';
import { fetchJson, reason } from './api.js';

/** How long an import waits for its objects to reach this page before it says what it imported. */
const ARRIVAL_MS = 10_000;

export class ClipImport {
  /**
   * @param {import('./Studio.js').Studio} studio where refusals are told
   * @param {HTMLElement} root the outliner's panel (its list built: main.js builds the Outliner first)
   */
  constructor(studio, root) {
    this.studio = studio;
    this.input = el('input', { type: 'file', accept: '.bvh,.c3d,.asf,.amc', multiple: '', 'data-testid': 'import-clip' });
    const label = el('label', { class: 'clip-import', title: 'Add a motion clip: each joint (.bvh, or an .asf and its .amc chosen together) or marker (.c3d) an object with its tracks (undoable)' }, 'import clip (.bvh, .c3d, .asf + .amc) ');
    label.append(this.input);
    this.status = el('div', { class: 'hint clip-status', 'data-testid': 'import-clip-status', role: 'status' });
    const list = root.querySelector('[data-testid=outliner]');     // above the objects' list, which may be long
    for (const part of [label, this.status]) root.insertBefore(part, list);
    /** @type {{names: string[], done: () => void} | null} the import waiting for its objects */
    this.pending = null;
    studio.signals.on('state', () => this.arrive());
    this.input.addEventListener('change', () => {
      const files = [...(this.input.files ?? [])];
      if (files.length) this.choose(files).finally(() => { this.input.value = ''; });
    });
  }

  /**
   * One file posted as it is; an .asf and an .amc together as a pair; anything else refused here.
   * @param {File[]} files
   */
  async choose(files) {
    const ends = (/** @type {string} */ ext) => files.filter((f) => f.name.toLowerCase().endsWith(ext));
    const [asf, amc] = [ends('.asf'), ends('.amc')];
    if (files.length === 1 && !asf.length && !amc.length) return this.send(files[0]);
    if (files.length === 2 && asf.length === 1 && amc.length === 1) return this.send(amc[0], asf[0]);
    const text = `${files.map((f) => f.name).join(', ')} was not imported: choose one .bvh or .c3d, or an .asf with its .amc`;
    this.status.textContent = text;
    this.studio.tell('error', text, 'clip');
  }

  /** Ends the wait of the pending import once all its objects are in the page's state. */
  arrive() {
    const names = new Set(this.studio.objects.map((o) => o.name));
    if (this.pending?.names.every((n) => names.has(n))) {
      this.pending.done();
      this.pending = null;
    }
  }

  /**
   * Post the file (an .amc: with its .asf `skeleton`, both texts as JSON); say what came of it.
   * @param {File} file
   * @param {File} [skeleton]
   */
  async send(file, skeleton) {
    this.input.disabled = true;
    this.status.textContent = `importing ${file.name}…`;
    try {
      const name = encodeURIComponent(file.name);
      const request = skeleton
        ? fetchJson(`/api/clips/amc?name=${name}&skeleton=${encodeURIComponent(skeleton.name)}`, {
          method: 'POST', headers: { 'Content-Type': 'application/json' },
          body: JSON.stringify({ skeleton: await skeleton.text(), motion: await file.text() }),
        })
        : fetchJson(`/api/clips?name=${name}`, { method: 'POST', body: file });
      /** @type {{objects: string[], tracks: number, frames: number, seconds: number}} */
      const made = await request;
      await Promise.race([             // or, if another page changed them first, after a while anyway
        new Promise((done) => {
          this.pending = { names: made.objects, done: () => done(undefined) };
          this.arrive();
        }),
        new Promise((done) => setTimeout(done, ARRIVAL_MS)),
      ]);
      const what = file.name.toLowerCase().endsWith('.c3d') ? 'markers' : 'joints';
      this.status.textContent = `${file.name}: ${made.objects.length} ${what}, ${made.frames} frames (${made.seconds.toFixed(1)} s)`;
    } catch (err) {
      const text = `${file.name} was not imported: ${reason(err)}`;
      this.status.textContent = text;
      this.studio.tell('error', text, 'clip');
    } finally {
      this.pending = null;
      this.input.disabled = false;
    }
  }
}
