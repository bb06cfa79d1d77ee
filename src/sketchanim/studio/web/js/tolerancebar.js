// @ts-check
/**
 * The tolerance after the take, in the curve editor's header: a slider and a number (the
 * attribute's units) for the shown track's tolerance. Dragging the slider asks the server for
 * previews (`track.reduce` with `preview`, at most one in flight, the latest value sent when
 * the answer comes) and shows their control points and largest error; the editor draws the
 * would-be curves dashed. Releasing the slider, or a changed number, re-reduces for good (one
 * History step). "all shown" applies it to every shown track of the same units that has takes.
 * A track without takes cannot be re-reduced (disabled, the tooltip says why); a track edited
 * by hand is re-reduced from its takes, so the bar warns that the hand edits go (undo brings them back).
 */
import { el } from './dom.js';

/** The slider's steps: 0 .. 1000 spans the attribute's default tolerance / 100 .. * 100 (log scale). */
const STEPS = 1000;
const DECADES = 2;

/**
 * The slider position of a tolerance, against the attribute's default `base`.
 * @param {number} tol
 * @param {number} base
 * @example sliderOf(0.005, 0.005)   // 500
 */
export function sliderOf(tol, base) {
  return Math.round(Math.min(STEPS, Math.max(0, STEPS / 2 + (STEPS / (2 * DECADES)) * Math.log10(tol / base))));
}

/**
 * The tolerance at a slider position (sliderOf's inverse), to 3 significant digits.
 * @param {number} position
 * @param {number} base
 * @example toleranceAt(750, 0.005)   // 0.05
 */
export function toleranceAt(position, base) {
  return Number((base * 10 ** (((position - STEPS / 2) * 2 * DECADES) / STEPS)).toPrecision(3));
}

export class ToleranceBar {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {() => void} changed  the preview curves changed (the editor redraws)
   */
  constructor(studio, changed) {
    this.studio = studio;
    this.changed = changed;
    this.slider = /** @type {HTMLInputElement} */ (el('input', { type: 'range', min: '0', max: String(STEPS), step: '1', 'data-testid': 'tolerance-slider' }));
    this.number = /** @type {HTMLInputElement} */ (el('input', { type: 'number', step: 'any', min: '0', 'data-testid': 'tolerance' }));
    this.unit = el('span', { class: 'unit' });
    this.all = /** @type {HTMLInputElement} */ (el('input', { type: 'checkbox', 'data-testid': 'tolerance-all' }));
    this.info = el('span', { class: 'info', 'data-testid': 'tolerance-info' });
    this.warning = el('span', { class: 'warning', 'data-testid': 'tolerance-warning', hidden: '' });
    const all = el('label', { class: 'all', title: 'Apply to every shown track of these units that has takes' });
    all.append(this.all, 'all shown');
    this.root = el('span', { class: 'tolerance' });
    this.root.append(el('span', { class: 'label' }, 'tol'), this.slider, this.number, this.unit, all, this.info, this.warning);
    /** @type {string | null} the shown track */
    this.path = null;
    /** @type {string[]} the tracks shown in the editor */
    this.shown = [];
    /** @type {Map<string, import('./messages.js').CurveTrack>} the would-be curves of the last preview, by path */
    this.preview = new Map();
    this.inFlight = false;
    /** @type {number | null} a preview asked while one was in flight */
    this.pending = null;
    /** @type {import('./messages.js').Track | null} the track the info text speaks of (the one answered for) */
    this.answeredFor = null;
    /** The slider is being dragged (previews shown); false once released. */
    this.previewing = false;
    this.slider.addEventListener('input', () => {
      const tol = toleranceAt(Number(this.slider.value), this.base());
      this.number.value = String(tol);
      this.previewing = true;
      this.ask(tol);
    });
    this.slider.addEventListener('change', () => this.apply(toleranceAt(Number(this.slider.value), this.base())));
    this.number.addEventListener('change', () => {
      const tol = Number(this.number.value);
      if (tol > 0 && Number.isFinite(tol)) this.apply(tol);
      else {
        studio.tell('warning', `a tolerance is a number > 0 (${this.path ?? 'the track'} keeps its own)`, 'curve editor');
        this.number.value = '';                     // show() puts the track's back
        this.number.blur();
        this.show();
      }
    });
    // a release where the drag began fires no change: there the previews end with the pointer
    let from = this.slider.value;
    this.slider.addEventListener('pointerdown', () => { from = this.slider.value; });
    const released = () => {
      if (!this.previewing || this.slider.value !== from) return;            // a change applies it
      this.previewing = false;
      this.pending = null;
      this.preview.clear();
      this.show();
      this.changed();
    };
    this.slider.addEventListener('pointerup', released);
    this.slider.addEventListener('pointercancel', released);
    this.all.addEventListener('change', () => this.show());
    studio.signals.on('reduced', (m) => this.answered(m));
    // a preview refused, or lost with the socket, is answered by no `reduced`: the next one may go
    studio.signals.on('error', (m) => { if (m.ref === 'track.reduce') this.unblock(); });
    studio.signals.on('connection', () => this.unblock());
  }

  /** The attribute's default tolerance (the slider's middle). */
  base() {
    return (this.path && this.studio.types.get(this.path)?.tol) || 1;
  }

  /**
   * The tracks the editor shows now, the first the one the bar is for.
   * @param {string | null} path
   * @param {string[]} shown
   */
  setTracks(path, shown) {
    if (path !== this.path) this.info.textContent = '';   // what it said was another track's
    this.path = path;
    this.shown = shown;
    this.show();
  }

  /** The tracks a tolerance applies to: the shown track, or every shown track of its units with takes. */
  paths() {
    const s = this.studio;
    const track = this.path ? s.tracks.get(this.path) : null;
    if (!this.path || track?.kind !== 'curve' || !track.takes.length) return [];
    if (!this.all.checked) return [this.path];
    const unit = s.types.get(this.path)?.unit;
    return this.shown.filter((p) => {
      const t = s.tracks.get(p);
      return t?.kind === 'curve' && t.takes.length > 0 && s.types.get(p)?.unit === unit;
    });
  }

  /** Show the track's tolerance, or why it cannot change. */
  show() {
    const s = this.studio;
    const track = this.path ? s.tracks.get(this.path) : null;
    const curve = track?.kind === 'curve' ? track : null;
    const type = this.path ? s.types.get(this.path) : null;
    const why = !curve ? 'No track yet: record a take first' : !curve.takes.length
      ? 'This track has no takes (it was not recorded): there is nothing to re-reduce' : s.readOnly ? 'Read-only project' : '';
    for (const input of [this.slider, this.number]) {
      input.disabled = !!why;
      input.title = why || `The tolerance of ${this.path} in ${type?.unit || 'its units'}: the curve is reduced again from its takes (one undo step)`;
    }
    this.root.title = why;
    this.unit.textContent = type?.unit ?? '';
    if (curve && document.activeElement !== this.number && !this.previewing) {
      this.number.value = String(Number(curve.tol.toPrecision(3)));
      this.slider.value = String(sliderOf(curve.tol, this.base()));
    }
    if (curve !== this.answeredFor) this.info.textContent = '';   // the track changed since the answer
    const edited = this.paths().some((p) => { const t = s.tracks.get(p); return t?.kind === 'curve' && t.edited; });
    this.warning.hidden = !edited;
    this.warning.textContent = edited ? 'edited by hand: re-reducing drops the hand edits (undo brings them back)' : '';
  }

  /**
   * Ask for a preview at `tol` (one in flight at most; the latest asked goes when it is answered).
   * @param {number} tol
   */
  ask(tol) {
    const paths = this.paths();
    if (!paths.length) return;
    if (this.inFlight) {
      this.pending = tol;
      return;
    }
    this.inFlight = true;
    this.pending = null;
    this.studio.reduceTracks(paths, tol, true);
  }

  /**
   * Re-reduce for good at `tol` (one History step); previews stop.
   * @param {number} tol
   */
  apply(tol) {
    this.previewing = false;
    this.pending = null;
    const paths = this.paths();
    if (paths.length) this.studio.reduceTracks(paths, tol, false);
    this.preview.clear();
    this.changed();
  }

  /** No preview is in flight any more (it was refused or lost): the latest asked goes now. */
  unblock() {
    this.inFlight = false;
    if (this.previewing && this.pending !== null) this.ask(this.pending);
  }

  /** @param {import('./messages.js').Reduced} m */
  answered(m) {
    if (m.preview) {
      this.inFlight = false;
      if (!this.previewing) return;                 // released meanwhile: this preview is stale
      this.preview = new Map(m.curves.map((c) => [c.path, c]));
      if (this.pending !== null) this.ask(this.pending);
    } else {
      this.preview.clear();
    }
    const n = m.results.reduce((sum, r) => sum + r.n, 0);
    const error = Math.max(...m.results.map((r) => r.error));
    const unit = this.path ? this.studio.types.get(this.path)?.unit ?? '' : '';
    this.answeredFor = this.path ? this.studio.tracks.get(this.path) ?? null : null;   // what the text is of
    this.info.textContent = `${m.preview ? 'preview: ' : ''}${n} control points · max error ${Number(error.toPrecision(3))} ${unit}`;
    this.changed();
  }
}
