// @ts-check
/**
 * The save status in the header: nothing while everything is on disk; while the server's
 * saves fail (the disk is full, the folder cannot be written), a red indicator that stays
 * until they succeed again, saying why and since when. The server keeps what it could not
 * save in memory and retries, so closing the page loses nothing; closing the server would.
 * The page asks before it closes all the same (`beforeunload`): it is the only place the
 * fault shows, and the animator who closes it is likely about to stop the server too.
 * The server's own notices say when saves fail and when they work again.
 */

/**
 * A time of day as hh:mm:ss (local time).
 * @param {number} seconds epoch seconds
 * @returns {string}
 *
 * @example
 * clockOf(new Date(2026, 0, 2, 9, 5, 7).getTime() / 1000);     // '09:05:07'
 */
export function clockOf(seconds) {
  const d = new Date(seconds * 1000);
  return [d.getHours(), d.getMinutes(), d.getSeconds()].map((n) => String(n).padStart(2, '0')).join(':');
}

/**
 * What the indicator says (null: everything is saved, no indicator).
 * @param {import('./messages.js').Saved} saved
 * @returns {string | null}
 *
 * @example
 * saveText({type: 'saved', ok: false, error: 'No space left on device', since: null});
 * // 'not saved — No space left on device — kept in memory, retrying'
 */
export function saveText(saved) {
  if (saved.ok) return null;
  const since = saved.since === null ? '' : ` (since ${clockOf(saved.since)})`;
  return `not saved — ${saved.error ?? 'the last save failed'} — kept in memory, retrying${since}`;
}

export class SaveStatus {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} indicator the header's element (hidden while everything is saved)
   * @param {Window} [win] where closing is asked about
   */
  constructor(studio, indicator, win = window) {
    indicator.setAttribute('role', 'alert');
    const show = () => {
      const text = saveText(studio.saved);
      indicator.hidden = text === null;
      indicator.textContent = text ?? '';
      indicator.title = text === null ? '' : 'The server could not write the project file; it keeps every change and saves it once it can';
    };
    studio.signals.on('saved', show);
    show();
    win.addEventListener('beforeunload', (event) => {
      if (!studio.saved.ok) event.preventDefault();
    });
  }
}
