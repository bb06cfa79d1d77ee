// @ts-check
/**
 * The studio's signals, declared once: each with what it means and the type of its payload.
 * Panels listen to them and the studio's parts emit them; a name not declared here is a type
 * error for tsc and throws at run time.
 */

/**
 * A signal's declaration: what it means; `T` is its payload's type (never held).
 * @template T
 * @typedef {{doc: string, payload?: T}} Signal
 */

/**
 * @template T
 * @param {string} doc
 * @returns {Signal<T>}
 */
function signal(doc) {
  return { doc };
}

export const SIGNALS = {
  state: /** @type {Signal<void>} */ (signal('everything changed (a state message): the scene, tracks, history')),
  ready: /** @type {Signal<void>} */ (signal('the server is warm: takes can be recorded')),
  connection: /** @type {Signal<boolean>} */ (signal('the socket opened (true) or closed (false)')),
  tracks: /** @type {Signal<void>} */ (signal('tracks changed or went')),
  values: /** @type {Signal<string[]>} */ (signal('these paths got values from the server')),
  history: /** @type {Signal<void>} */ (signal("the History's labels changed")),
  selection: /** @type {Signal<string | null>} */ (signal('this object is selected (null: none)')),
  attribute: /** @type {Signal<string>} */ (signal('the curve view shows this attribute of the selected object')),
  transport: /** @type {Signal<void>} */ (signal('the transport changed: time, play / pause, speed, loop')),
  record: /** @type {Signal<boolean>} */ (signal('record mode went on (true) or off (false)')),
  settings: /** @type {Signal<void>} */ (signal('a recording setting changed: layer mode, count-in, capture speed, loop recording')),
  tolerances: /** @type {Signal<void>} */ (signal("the animator's take tolerances changed")),
  lock: /** @type {Signal<void>} */ (signal('what keeps this page from recording may have changed (studio.lock): another page\'s take, a read-only project')),
  saved: /** @type {Signal<import('./messages.js').Saved>} */ (signal('whether everything is on disk changed (studio.saved)')),
  error: /** @type {Signal<import('./messages.js').ErrorReply>} */ (signal('the server refused a message')),
  notice: /** @type {Signal<import('./messages.js').Notice>} */ (signal('the server has news for the animator')),
  points: /** @type {Signal<import('./Studio.js').PointSelection[]>} */ (signal('the selected control points and keys changed (studio.points)')),
  projectSettings: /** @type {Signal<void>} */ (signal("the project's settings changed (studio.fps)")),
  reduced: /** @type {Signal<import('./messages.js').Reduced>} */ (signal('the server answered a track.reduce (a preview or the step done)')),
  samples: /** @type {Signal<import('./messages.js').Samples>} */ (signal('the server sent the samples a curve keeps')),
  piece: /** @type {Signal<import('./messages.js').TrackPieceInfo>} */ (signal('a copied range came back (track.piece): the timeline keeps it as the clipboard')),
  timeRange: /** @type {Signal<import('./Studio.js').TimeRange | null>} */ (signal('the range selected in the timeline changed (studio.timeRange)')),
  command: /** @type {Signal<import('./keyboard.js').PanelCommand>} */ (signal("a shortcut for a panel's own action (the panel that owns it acts)")),
  fired: /** @type {Signal<import('./events.js').Fired[]>} */ (signal('playback passed these events (in the order it passed them)')),
  sounds: /** @type {Signal<void>} */ (signal("the project's sounds changed (studio.sounds)")),
  beats: /** @type {Signal<import('./messages.js').BeatsBaked>} */ (signal("the server baked a sound's beats into an event track")),
  frame: /** @type {Signal<number>} */ (signal('an animation frame was stepped, at this performance.now()')),
};

/** @typedef {keyof typeof SIGNALS} SignalName */
/**
 * The payload type of each signal.
 * @typedef {{[K in SignalName]: typeof SIGNALS[K] extends Signal<infer T> ? T : never}} Payloads
 */

/**
 * Listeners by declared signal; emit calls them in the order they were added.
 *
 * @example
 * const signals = new Signals();
 * signals.on('selection', (name) => console.log(name));
 * signals.emit('selection', 'box');      // logs "box"
 * signals.emit('nonsense');              // tsc: not a signal; at run time: throws
 */
export class Signals {
  /** @param {Record<string, Signal<any>>} [declared] the signals (the studio's: SIGNALS) */
  constructor(declared = SIGNALS) {
    /** @type {Map<string, ((payload: any) => void)[]>} */
    this.listeners = new Map(Object.keys(declared).map((name) => [name, []]));
  }

  /** @param {string} name */
  list(name) {
    const list = this.listeners.get(name);
    if (!list) throw new Error(`no signal named ${JSON.stringify(name)}: declare it in signals.js`);
    return list;
  }

  /**
   * @template {SignalName} K
   * @param {K} name
   * @param {(payload: Payloads[K]) => void} listener
   */
  on(name, listener) {
    this.list(name).push(listener);
  }

  /**
   * @template {SignalName} K
   * @param {K} name
   * @param {Payloads[K] extends void ? [] : [Payloads[K]]} payload none for a signal of no payload
   */
  emit(name, ...payload) {
    for (const listener of this.list(name)) listener(payload[0]);
  }
}
