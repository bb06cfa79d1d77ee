// @ts-check
/**
 * The page's state and its signals. The server is the single source of truth for the
 * scene, the tracks and the history; the page mirrors them (from `state`, `tracks`,
 * `values`, `history` messages), plays the tracks itself every frame, and sends
 * performances (takes) and commands.
 *
 * Signals (events on the Studio, detail as noted): "state" (everything changed),
 * "tracks", "values" (detail: paths), "history", "selection", "transport", "record",
 * "take" (a take began, grew a piece or ended), "error" (detail: message), "frame".
 */
import { Clock } from './clock.js';
import { evaluate, pack, stepValue, valueOf } from './evaluate.js';
import { TakeSampler } from './take.js';

/**
 * @typedef {{name: string, dim: number, tol: number, unit: string, default: any[], choices: string[], continuous: boolean}} AttrType
 * @typedef {{name: string, kind: string, attributes: {name: string, value: any, type: AttrType}[]}} SceneObject
 * @typedef {{path: string, kind: 'curve', dim: number, order: number, rotation: boolean, tol: number, knots: number[], coef: number[][], start: number, end: number, takes: {start: number, end: number, mode: string, n: number}[]}} CurveTrack
 * @typedef {{path: string, kind: 'steps', times: number[], values: any[]}} StepsTrack
 * @typedef {CurveTrack | StepsTrack} Track
 * @typedef {object} Grab   Something the performer holds.
 * @property {string[]} paths     the attributes held (playback leaves them alone)
 * @property {string} label
 * @property {boolean} changed    moved since the press
 * @property {boolean} dirty      moved since the last preview sent
 * @property {boolean} recordable may still start a take (false after a loop wrap without loop recording)
 * @property {TakeSampler | null} take
 * @property {string | null} loopKey
 * @property {((dt: number, now: number) => void) | null} drive  moves the held attributes each frame (a device)
 * @typedef {object} TakeLog   A take the page sent, for the curve view, tests and benchmarks.
 * @property {string} id
 * @property {TakeSampler} sampler
 * @property {number} released   performance.now() of the release
 * @property {number | null} final performance.now() when the final curve arrived
 * @property {string | null} label History's label (null: refused or cancelled)
 * @property {number | null} serverMs the server's time from the release's message to the final curve
 */

/** Real seconds between frames beyond which the server treats the step as a stall (at least;
 * a slow page, e.g. software WebGL, gets 4 of its frame intervals: its ordinary frames are no stall). */
const GAP = 0.25;
/** Seconds of fade at a punch-in's seams. */
const BLEND = 0.1;

export class Studio extends EventTarget {
  /** @param {import('./Connection.js').Connection} connection */
  constructor(connection) {
    super();
    this.connection = connection;
    /** @type {SceneObject[]} */
    this.objects = [];
    /** @type {Map<string, AttrType>} */
    this.types = new Map();
    /** @type {Map<string, any>} the scene's current values, by path */
    this.values = new Map();
    /** @type {Map<string, Track>} */
    this.tracks = new Map();
    this.packed = pack([]);
    /** @type {StepsTrack[]} */
    this.steps = [];
    /** @type {[number, number]} */
    this.span = [0, 0];
    this.history = { undo: /** @type {string[]} */ ([]), redo: /** @type {string[]} */ ([]), can_undo: false, can_redo: false };
    this.ready = false;
    this.loaded = false;
    /** @type {string | null} */
    this.selected = null;
    /** The attribute the curve view shows. */
    this.attribute = 'position';
    this.clock = new Clock();
    this.time = 0;
    this.playSpeed = 1;
    this.record = false;
    /** @type {'replace' | 'additive'} */
    this.mode = 'replace';
    /** Seconds of pre-roll before recording starts (0: off). */
    this.countIn = 0;
    this.loopRecord = false;
    /** Transport seconds per real second while recording. */
    this.captureSpeed = 1;
    /** Takes start only once the transport reaches this time (the count-in's end). */
    this.punchFrom = -Infinity;
    /** @type {Grab | null} */
    this.grab = null;
    /** @type {TakeLog[]} */
    this.takes = [];
    /** @type {Map<string, any[]>} pieces of the growing curve of the take in progress, by path */
    this.pieces = new Map();
    /** @type {((path: string, value: any) => void)[]} what draws values (the viewport) */
    this.sinks = [];
    this.takeCount = 0;
    /** @type {any[]} the server's error messages, oldest first */
    this.errors = [];
    this.lastFrame = -Infinity;
    /** @type {number[]} the last frame intervals, ms */
    this.intervals = [];
    /** Milliseconds the last frame's playback took (evaluate and write the values). */
    this.playMs = 0;
    this.frames = 0;
    this.listen();
  }

  // -- signals --------------------------------------------------------------------------

  /**
   * @param {string} name
   * @param {any} [detail]
   */
  emit(name, detail) {
    this.dispatchEvent(new CustomEvent(name, { detail }));
  }

  /**
   * @param {string} name
   * @param {(detail: any) => void} handler
   */
  on(name, handler) {
    this.addEventListener(name, (event) => handler(/** @type {CustomEvent} */ (event).detail));
  }

  // -- the server's messages --------------------------------------------------------------

  listen() {
    const c = this.connection;
    c.on('state', (m) => this.loadState(m));
    c.on('tracks', (m) => {
      for (const track of m.changed) this.tracks.set(track.path, track);
      for (const path of m.removed) this.tracks.delete(path);
      this.span = m.span;
      this.repack();
      this.emit('tracks');
    });
    c.on('values', (m) => this.receiveValues(m.values));
    c.on('preview', (m) => this.receiveValues({ [m.path]: m.value }));
    c.on('history', (m) => {
      this.history = m;
      this.emit('history');
    });
    c.on('take.piece', (m) => {
      const list = this.pieces.get(m.path) ?? [];
      list.push(m);
      this.pieces.set(m.path, list);
      this.emit('take');
    });
    c.on('take.ended', (m) => {
      const log = this.takes.find((l) => l.id === m.take);
      if (log) {
        log.final = performance.now();
        log.label = m.label;
        log.serverMs = m.ms;
      }
      if (!this.grab?.take) this.pieces.clear();
      this.emit('take');
    });
    c.on('transport', (m) => this.receiveTransport(m));
    c.on('ready', () => {
      this.ready = true;
      this.emit('ready');
    });
    c.on('error', (m) => {
      this.errors.push(m);
      this.emit('error', m);
    });
  }

  /** @param {any} m the `state` message */
  loadState(m) {
    this.objects = m.objects;
    this.types.clear();
    this.values.clear();
    for (const o of this.objects) {
      for (const a of o.attributes) {
        this.types.set(`${o.name}.${a.name}`, a.type);
        this.values.set(`${o.name}.${a.name}`, a.value);
      }
    }
    this.tracks = new Map(m.tracks.map((/** @type {Track} */ t) => [t.path, t]));
    this.span = m.span;
    this.history = m.history;
    this.ready = this.ready || m.ready;
    if (!this.loaded) this.receiveTransport(m.transport);
    if (this.selected && !this.objects.some((o) => o.name === this.selected)) this.selected = null;
    this.repack();
    this.loaded = true;
    this.emit('state');
    for (const [path, value] of this.values) this.draw(path, value);
    if (this.ready) this.emit('ready');
  }

  /** @param {Record<string, any>} values */
  receiveValues(values) {
    for (const [path, value] of Object.entries(values)) {
      if (this.grab?.paths.includes(path)) continue;           // the performer holds it
      this.values.set(path, value);
      this.draw(path, value);
    }
    this.emit('values', Object.keys(values));
  }

  /** @param {{time: number, playing: boolean, speed: number, loop: [number, number] | null}} m */
  receiveTransport(m) {
    const now = performance.now();
    this.clock.seek(m.time, now);
    this.clock.loop = m.loop;
    this.playSpeed = m.speed;
    this.clock.setSpeed(m.speed, now);
    if (m.playing && this.loaded) this.clock.play(now);
    else this.clock.pause(now);
    this.time = m.time;
    this.emit('transport');
  }

  repack() {
    const curves = [...this.tracks.values()].filter((t) => t.kind === 'curve');
    this.packed = pack(/** @type {CurveTrack[]} */ (curves));
    this.steps = /** @type {StepsTrack[]} */ ([...this.tracks.values()].filter((t) => t.kind === 'steps'));
    this.writeTracks(this.time);
  }

  // -- values ---------------------------------------------------------------------------

  /**
   * Show a value (the viewport and whoever listens draw it).
   * @param {string} path
   * @param {any} value
   */
  draw(path, value) {
    for (const sink of this.sinks) sink(path, value);
  }

  /**
   * Change a value in the page only (a drag in progress, playback).
   * @param {string} path
   * @param {any} value
   */
  setLocal(path, value) {
    this.values.set(path, value);
    if (this.grab?.paths.includes(path)) this.grab.changed = this.grab.dirty = true;
    this.draw(path, value);
  }

  /**
   * An undoable edit of one value (sent to the server; one History entry, merged with
   * the previous one when `merge` is the same key).
   * @param {string} path
   * @param {any} value
   * @param {string} label
   * @param {string | null} [merge]
   */
  set(path, value, label, merge = null) {
    this.setLocal(path, value);
    this.connection.send({ type: 'set', path, value, label, merge });
  }

  /** @param {string} name */
  objectOf(name) {
    return this.objects.find((o) => o.name === name) ?? null;
  }

  /** @param {string | null} name */
  select(name) {
    this.selected = name;
    const obj = name ? this.objectOf(name) : null;
    if (obj && !obj.attributes.some((a) => a.name === this.attribute && a.type.continuous)) {
      this.attribute = obj.attributes.find((a) => a.type.continuous)?.name ?? 'position';
    }
    this.emit('selection');
  }

  // -- transport -----------------------------------------------------------------------

  sendTransport() {
    this.connection.send({ type: 'transport', time: this.time, playing: this.clock.playing,
      speed: this.playSpeed, loop: this.clock.loop });
    this.emit('transport');
  }

  play() {
    const now = performance.now();
    if (!this.record && this.span[1] > this.span[0] && !this.clock.loop && this.playSpeed > 0 && this.time >= this.span[1]) {
      this.clock.seek(this.span[0], now);                     // play again from the start
    }
    this.clock.play(now);
    this.sendTransport();
  }

  pause() {
    this.clock.pause(performance.now());
    this.time = this.clock.time0;
    this.sendTransport();
  }

  /** Pause and go back to the loop's start (or the start). */
  stop() {
    if (this.record) this.setRecord(false);
    this.pause();
    this.seek(this.clock.loop ? this.clock.loop[0] : Math.min(0, this.span[0]));
  }

  /** @param {number} time */
  seek(time) {
    this.clock.seek(time, performance.now());
    this.time = time;
    this.writeTracks(time);
    this.sendTransport();
  }

  /** @param {number} speed */
  setSpeed(speed) {
    this.playSpeed = speed;
    if (!this.record) this.clock.setSpeed(speed, performance.now());
    this.sendTransport();
  }

  /** @param {[number, number] | null} loop */
  setLoop(loop) {
    this.clock.loop = loop && loop[1] > loop[0] ? loop : null;
    this.sendTransport();
  }

  /**
   * Record mode: the transport runs (at the capture speed, after the count-in's pre-roll)
   * and every grab is a take.
   * @param {boolean} on
   */
  setRecord(on) {
    const now = performance.now();
    if (on === this.record) return;
    this.record = on;
    if (on) {
      const time = this.clock.raw(now);
      this.punchFrom = time;
      if (this.countIn > 0) this.clock.seek(time - this.countIn * this.captureSpeed, now);
      this.clock.setSpeed(this.captureSpeed, now);
      this.clock.play(now);
    } else {
      if (this.grab?.take) this.endTake(this.grab, now);
      this.clock.setSpeed(this.playSpeed, now);
      this.clock.pause(now);
      this.time = this.clock.time0;
    }
    this.emit('record');
    this.sendTransport();
  }

  /** Seconds left of the count-in (0 when none is running). */
  get countingIn() {
    return this.record && this.time < this.punchFrom ? this.punchFrom - this.time : 0;
  }

  // -- performing -------------------------------------------------------------------------

  /**
   * Take hold of attributes (a drag, a gizmo, a slider, a device): playback leaves them
   * alone until the release, and in record mode the hold is a take of them.
   * @param {string[]} paths continuous attributes
   * @param {string} label
   * @param {((dt: number, now: number) => void) | null} [drive]
   * @returns {Grab}
   */
  hold(paths, label, drive = null) {
    if (this.grab) this.release();
    this.grab = { paths, label, changed: false, dirty: false, recordable: true, take: null, loopKey: null, drive };
    this.emit('take');
    return this.grab;
  }

  /** Let go of what is held: ends its take, or sends its edit outside record mode. */
  release() {
    const grab = this.grab;
    if (!grab) return;
    const now = performance.now();
    if (grab.take) this.endTake(grab, now);
    this.grab = null;
    if (!grab.take && !this.record && grab.changed) {
      const merge = `${grab.label} ${now}`;
      for (const path of grab.paths) {
        this.connection.send({ type: 'set', path, value: this.values.get(path), label: grab.label, merge });
      }
    }
    this.emit('take');
  }

  /**
   * @param {Grab} grab
   * @param {number} time transport time of the first sample
   */
  beginTake(grab, time) {
    const id = `t${Date.now().toString(36)}${this.takeCount++}`;
    const dims = grab.paths.map((p) => this.types.get(p)?.dim ?? 0);
    grab.take = new TakeSampler(id, grab.paths, dims);
    grab.take.gap = this.stallGap();
    if (this.loopRecord && this.clock.loop && !grab.loopKey) grab.loopKey = `loop ${id}`;
    this.pieces.clear();
    this.connection.send({ type: 'take.begin', take: id, paths: grab.paths, mode: this.mode, blend: BLEND, time,
      speed: this.captureSpeed, loop: grab.loopKey, gap: grab.take.gap });
    this.emit('take');
  }

  /**
   * End a take at its last sample: the samples not sent yet go first.
   * @param {Grab} grab
   * @param {number} now
   */
  endTake(grab, now) {
    const take = grab.take;
    if (!take) return;
    const rest = take.batch(now, true);
    if (rest) this.connection.send(rest);
    this.connection.send({ type: 'take.end', take: take.id, label: `take ${grab.label}` });
    this.takes.push({ id: take.id, sampler: take, released: now, final: null, label: null, serverMs: null });
    grab.take = null;
  }

  /** Real seconds without a frame that make a stall: 0.25 s, or 4 frame intervals on a slow page. */
  stallGap() {
    const sorted = [...this.intervals].sort((a, b) => a - b);
    const median = sorted.length ? sorted[sorted.length >> 1] / 1000 : 0;
    return Math.max(GAP, 4 * median);
  }

  /** The row of the held attributes' current values, end to end. */
  heldRow() {
    return (this.grab?.paths ?? []).flatMap((p) => this.values.get(p));
  }

  // -- every frame ------------------------------------------------------------------------

  /**
   * Write every track's value at `time` into the scene, except what the performer holds.
   * @param {number} time
   */
  writeTracks(time) {
    const p = this.packed;
    const held = this.grab ? this.grab.paths : [];
    evaluate(p, time);
    for (let j = 0; j < p.paths.length; j++) {
      const path = p.paths[j];
      if (held.length && held.includes(path)) continue;
      const value = Array.from(valueOf(p, j));
      this.values.set(path, value);
      this.draw(path, value);
    }
    for (const steps of this.steps) {
      if (held.includes(steps.path)) continue;
      const value = stepValue(steps, time);
      if (value !== null && value !== this.values.get(steps.path)) {
        this.values.set(steps.path, value);
        this.draw(steps.path, value);
      }
    }
  }

  /**
   * One animation frame: the transport's time from the browser's clock, playback, and
   * the held attributes sampled into the take.
   * @param {number} now performance.now() of the frame
   */
  frame(now) {
    const dt = Math.min(Math.max((now - this.lastFrame) / 1000, 0), GAP);   // a device moves for the time that passed
    if (Number.isFinite(this.lastFrame)) {
      this.intervals.push(now - this.lastFrame);
      if (this.intervals.length > 60) this.intervals.shift();
    }
    this.lastFrame = now;
    this.frames += 1;
    const wasPlaying = this.clock.playing;
    const { time, wrapped, stopped } = this.clock.tick(now, this.record ? null : this.span);
    this.time = time;
    const grab = this.grab;
    if (grab && wrapped && grab.take) {             // a pass of the loop ends here
      this.endTake(grab, now);
      grab.recordable = this.loopRecord;
    }
    const started = performance.now();
    if (this.clock.playing || wrapped || stopped) this.writeTracks(time);
    this.playMs = performance.now() - started;
    if (grab) {
      if (grab.drive) grab.drive(dt, now);
      if (this.record && !grab.take && grab.recordable && this.clock.playing && time >= this.punchFrom) {
        this.beginTake(grab, time);
      }
      if (grab.take) {
        grab.take.add(time, this.heldRow(), now);
        const batch = grab.take.batch(now);
        if (batch) this.connection.send(batch);
      } else if (!this.record && grab.dirty) {
        grab.dirty = false;
        for (const path of grab.paths) {
          this.connection.send({ type: 'preview', key: `${grab.label} ${path}`, path, value: this.values.get(path) });
        }
      }
    }
    if (wasPlaying !== this.clock.playing) this.sendTransport();
    this.emit('frame', now);
  }

  /** The page went to the background (no more frames): a take ends at its last sample. */
  hidden() {
    if (this.grab) this.release();
  }

  // -- commands -----------------------------------------------------------------------------

  undo() {
    if (this.grab) return;
    this.connection.send({ type: 'undo' });
  }

  redo() {
    if (this.grab) return;
    this.connection.send({ type: 'redo' });
  }
}
