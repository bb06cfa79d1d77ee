// @ts-check
/**
 * The cues playback passes, flashed over the 3D view's top right corner as they fire (the
 * object's name and the cue's label), each for `FLASH_MS`; the last `MAX_FLASHED` at once.
 */
import { el } from './dom.js';

/** Milliseconds a fired cue stays shown. */
export const FLASH_MS = 700;
/** Cues shown at once (the oldest goes first). */
export const MAX_FLASHED = 4;

export class CueFlash {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} view the 3D view's element (the flashes go over it)
   */
  constructor(studio, view) {
    this.box = el('div', { class: 'cue-flash', 'data-testid': 'cue-flash', 'aria-live': 'polite' });
    view.append(this.box);
    /** Cues fired since the page loaded (for a script or a test to read). */
    this.count = 0;
    studio.signals.on('fired', (fired) => {
      for (const cue of fired) this.flash(cue);
    });
  }

  /** @param {import('./events.js').Fired} cue */
  flash(cue) {
    this.count += 1;
    const [object, attr] = cue.path.split('.');
    const item = el('div', { class: 'cue' }, `◆ ${object}${attr === 'cue' ? '' : `.${attr}`}${cue.label ? ` · ${cue.label}` : ''}`);
    this.box.append(item);
    while (this.box.children.length > MAX_FLASHED) this.box.firstElementChild?.remove();
    setTimeout(() => item.remove(), FLASH_MS);
  }
}
