// @ts-check
/**
 * The live stream: one websocket to the server's /ws, JSON messages both ways.
 * Messages sent while the socket is (re)connecting wait in order; a dropped socket is
 * reopened with a growing delay. Every message received is dispatched as an event named
 * by its `type` (detail: the message), plus "open" and "close".
 */

export class Connection extends EventTarget {
  /** @param {string} url e.g. ws://127.0.0.1:8000/ws */
  constructor(url) {
    super();
    this.url = url;
    /** @type {WebSocket | null} */
    this.socket = null;
    /** @type {string[]} */
    this.queue = [];
    this.delay = 250;
    this.nextId = 1;
    /** @type {Map<number, {resolve: (m: any) => void, reject: (e: Error) => void}>} */
    this.pending = new Map();
    this.open();
  }

  open() {
    const socket = new WebSocket(this.url);
    this.socket = socket;
    socket.addEventListener('open', () => {
      this.delay = 250;
      for (const text of this.queue.splice(0)) socket.send(text);
      this.dispatchEvent(new CustomEvent('open'));
    });
    socket.addEventListener('message', (event) => {
      const message = JSON.parse(event.data);
      if (message.id != null && this.pending.has(message.id)) {
        const waiter = this.pending.get(message.id);
        this.pending.delete(message.id);
        if (message.type === 'error') waiter?.reject(new Error(message.message));
        else waiter?.resolve(message);
      }
      this.dispatchEvent(new CustomEvent(message.type, { detail: message }));
    });
    socket.addEventListener('close', () => {
      this.dispatchEvent(new CustomEvent('close'));
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
   * @param {object} message
   */
  send(message) {
    const text = JSON.stringify(message);
    if (this.connected) this.socket?.send(text);
    else this.queue.push(text);
  }

  /**
   * Send a message with an id; resolves with its ack, rejects with its error.
   * @param {object} message
   * @returns {Promise<any>}
   */
  request(message) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.send({ ...message, id });
    });
  }

  /**
   * Listen to messages of one type.
   * @param {string} type
   * @param {(message: any) => void} handler
   */
  on(type, handler) {
    this.addEventListener(type, (event) => handler(/** @type {CustomEvent} */ (event).detail));
  }
}
