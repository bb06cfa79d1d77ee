// @ts-check
/**
 * The banner over the 3D view's bottom edge while something keeps this page from recording
 * (studio.lock): another tab records a take (shown here as it comes, read-only), or the
 * project is read-only (it plays and exports; edits are refused). The body's class says
 * which (`remote-recording`, `read-only`: the view's frame takes its colour); the REC
 * button is disabled by the transport bar from the same lock.
 */

export class LockBanner {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} view the 3D view (the banner goes in it)
   */
  constructor(studio, view) {
    const doc = view.ownerDocument;
    const banner = doc.createElement('div');
    banner.className = 'lock-banner';
    banner.setAttribute('role', 'status');
    banner.hidden = true;
    view.append(banner);
    studio.signals.on('lock', () => {
      const lock = studio.lock;
      banner.hidden = !lock;
      banner.textContent = lock ? lock.text : '';
      banner.dataset.testid = lock ? lock.kind : 'lock';
      doc.body.classList.toggle('remote-recording', lock?.kind === 'remote');
      doc.body.classList.toggle('read-only', lock?.kind === 'read-only');
    });
  }
}
