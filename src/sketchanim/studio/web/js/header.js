// @ts-check
/** The header's live parts: the project's name, and the connection's and server's status. */

export class Header {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} project where the project's name goes
   * @param {HTMLElement} status
   */
  constructor(studio, project, status) {
    const show = () => {
      const connected = studio.connection.connected;
      status.textContent = !connected ? 'reconnecting…' : studio.ready ? 'ready' : 'warming up…';
      status.className = connected && studio.ready ? 'ok' : 'wait';
      project.textContent = studio.project;
    };
    for (const signal of /** @type {const} */ (['connection', 'ready', 'state'])) studio.signals.on(signal, show);
  }
}
