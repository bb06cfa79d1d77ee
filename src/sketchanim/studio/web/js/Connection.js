// @ts-check
/**
 * The live stream: one websocket to the server's /ws, JSON messages both ways (messages.js).
 * Messages sent while the socket is (re)connecting wait in order; a dropped socket is
 * reopened with a growing delay (whatever closed it: the server closes a socket that sent a
 * frame over its transport limit with code 1009, and the page reconnects as after any drop).
 */

/** @typedef {import('./messages.js').PageMessage} PageMessage */
/** @typedef {import('./messages.js').ServerMessage} ServerMessage */

export class Connection {
  /** @param {string} url e.g. ws://127.0.0.1:8000/ws */
  constructor(url) {
    this.url = url;
    /** @type {WebSocket | null} */
    this.socket = null;
    /** @type {string[]} */
    this.queue = [];
    this.delay = 250;
    /** @type {(m: ServerMessage) => void} */
    this.onMessage = () => {};
    /** @type {(open: boolean, code?: number) => void} */
    this.onStatus = () => {};
  }

  /**
   * Open the socket (and reopen it whenever it drops): every message received goes to
   * `onMessage`, every opening and closing (with the close code) to `onStatus`.
   * @param {(m: ServerMessage) => void} onMessage
   * @param {(open: boolean, code?: number) => void} onStatus
   */
  connect(onMessage, onStatus) {
    this.onMessage = onMessage;
    this.onStatus = onStatus;
    this.open();
  }

  open() {
    const socket = new WebSocket(this.url);
    this.socket = socket;
    socket.addEventListener('open', () => {
      this.delay = 250;
      for (const text of this.queue.splice(0)) socket.send(text);
      this.onStatus(true);
    });
    socket.addEventListener('message', (event) => this.onMessage(/** @type {ServerMessage} */ (JSON.parse(event.data))));
    socket.addEventListener('close', (event) => {
      this.onStatus(false, event.code);
      setTimeout(() => this.open(), this.delay);
      this.delay = Math.min(this.delay * 2, 4000);
    });
  }

  /** @returns {boolean} */
  get connected() {
    return this.socket?.readyState === WebSocket.OPEN;
  }

  /**
   * Send a message (queued while not connected).
   * @param {PageMessage} message
   */
  send(message) {
    const text = JSON.stringify(message);
    if (this.connected) this.socket?.send(text);
    else this.queue.push(text);
  }
}
