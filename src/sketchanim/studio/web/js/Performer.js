// @ts-check
/**
 * The performer: what the animator holds (a drag, a gizmo, a slider, a device) and the
 * takes it records. A hold keeps playback off its attributes until the release; in record
 * mode it is a take, sent to the server in batches; outside record mode it previews and,
 * on release, sends one undoable edit.
 *
 * A take pairs each value with the time it was true. A pointer's input marks every event
 * it moved the held values on (`mark`, with the event's own timeStamp: coalesced events
 * included): each mark is a sample at its event's transport time. A frame without a mark,
 * `restMs` after the last (1.5 of the pointer's own intervals between events, at least
 * `REST`), finds the pointer at rest: a sample at the start of the rest and one at the
 * frame's time. A device (a hold with a `drive`) moves the values
 * on the frame: a sample at the frame's time. The take's tolerance per attribute is what
 * the input resolves there (the hold's `resolve`, resolution.js), or the animator's.
 *
 * In a read-only project a hold moves its attributes in the page only and sends nothing (its
 * release shows the server's values again). While this page records a take it pings the
 * server every second (BEAT_MS); a take the server ended (`ended`) stops here too.
 */
import { takeTolerance } from './resolution.js';
import { TakeSampler } from './take.js';

/** Real seconds between frames beyond which the server treats the step as a stall (at least;
 * a slow page, e.g. software WebGL, gets 4 of its frame intervals: its ordinary frames are no stall). */
const GAP = 0.25;
/** Seconds of fade at a punch-in's seams. */
const BLEND = 0.1;
/**
 * The smoothing menu, in seconds (the Gaussian's width in time; it halves the power of
 * motion at about 0.13 / s Hz): light keeps gestures and takes out hand tremor and pointer
 * jitter (8-12 Hz and up: half power at 6.6 Hz), medium keeps deliberate motion (half power
 * at 2.7 Hz), strong keeps only sweeping motion (1.3 Hz). Off by default: a take is the
 * performance as it was.
 */
export const SMOOTHING = /** @type {const} */ ([[0, 'off'], [0.02, 'light'], [0.05, 'medium'], [0.1, 'strong']]);
/** Milliseconds without an event after which a pointer is at rest, at least (one in motion reports at 60 Hz or more). */
export const REST = 25;
/** Events a hold keeps the intervals of (the pointer's own rate). */
const PACE = 16;
/** Milliseconds between the pings of a page recording a take, samples or not: the server ends
 * (and keeps) the take of a page silent for 5 s (its SILENCE). A timer, not the frame loop: a
 * background tab's timers still fire once a second, its frames not at all. */
export const BEAT_MS = 1000;
/** What the animator is told when the server ended this page's take, by its reason. */
const ENDED = {
  silent: 'take kept: the server ended it — no frames from this page for 5 s',
  shutdown: 'take kept: the server is stopping — it ended the take',
  gone: 'take kept: the connection dropped — the server ended the take',
};

/**
 * @typedef {object} Grab   Something the performer holds.
 * @property {string[]} paths     the attributes held (playback leaves them alone)
 * @property {string} label
 * @property {boolean} changed    moved since the press (a device's hold: from the start)
 * @property {boolean} dirty      moved since the last preview sent
 * @property {boolean} recordable may still start a take (false after a loop wrap without loop recording)
 * @property {TakeSampler | null} take
 * @property {string | null} loopKey
 * @property {((dt: number, now: number) => void) | null} drive  moves the held attributes each frame (a device)
 * @property {(() => Record<string, import('./resolution.js').Resolution>) | null} resolve  what the input resolves, per path, now
 * @property {{stamp: number, row: number[]}[]} marks  the events that moved the held values since the last frame
 * @property {number} lastEvent  performance.now() of the last of them (the press, before any)
 * @property {number[]} paces  ms between the hold's last events
 * @property {number} events  events marked so far
 * @property {boolean} inert  sends nothing (a read-only project; the server ended its take): the release shows the server's values
 */

export class Performer {
  /** @param {import('./Studio.js').Studio} studio */
  constructor(studio) {
    this.studio = studio;
    /** @type {Grab | null} */
    this.grab = null;
    /** @type {import('./messages.js').LayerMode} how a take lays over the track: punch-in or additive */
    this.mode = 'replace';
    /** While looping, each pass is a take (the last one is kept). */
    this.loopRecord = false;
    /** Seconds a take's samples are smoothed over before the server reduces them (0: off; SMOOTHING). */
    this.smoothing = 0;
    this.takeCount = 0;
    this.lastFrame = -Infinity;
    /** @type {ReturnType<typeof setInterval> | null} the heartbeat while this page records a take */
    this.beat = null;
    /** @type {number[]} the last frame intervals, ms */
    this.intervals = [];
    studio.signals.on('record', (on) => {
      if (!on && this.grab?.take) this.endTake(this.grab, performance.now());
    });
  }

  /** @param {import('./messages.js').LayerMode} mode */
  setMode(mode) {
    this.mode = mode;
    this.studio.signals.emit('settings');
    this.studio.transport.send();                              // a record setting the server keeps
  }

  /** @param {number} seconds how much the next takes are smoothed (0: off) */
  setSmoothing(seconds) {
    this.smoothing = seconds;
    this.studio.signals.emit('settings');
    this.studio.transport.send();
  }

  /** @param {boolean} on */
  setLoopRecord(on) {
    this.loopRecord = on;
    this.studio.signals.emit('settings');
    this.studio.transport.send();
  }

  /**
   * Whether `path` is held (playback and the server's values leave it alone).
   * @param {string} path
   */
  holds(path) {
    return !!this.grab?.paths.includes(path);
  }

  /**
   * A held value moved.
   * @param {string} path
   */
  moved(path) {
    if (this.grab && this.holds(path)) this.grab.changed = this.grab.dirty = true;
  }

  /**
   * Take hold of attributes: playback leaves them alone until the release, and in record
   * mode the hold is a take of them.
   * @param {string[]} paths continuous attributes
   * @param {string} label
   * @param {((dt: number, now: number) => void) | null} [drive] a device's: moves the attributes each frame
   * @param {(() => Record<string, import('./resolution.js').Resolution>) | null} [resolve] what the input resolves, per path
   * @returns {Grab}
   */
  hold(paths, label, drive = null, resolve = null) {
    if (this.grab) this.release();
    this.grab = { paths, label, changed: drive !== null, dirty: false, recordable: true, take: null, loopKey: null, drive,
      resolve, marks: [], lastEvent: performance.now(), paces: [], events: 0, inert: this.studio.readOnly };
    return this.grab;
  }

  /**
   * The input moved the held values on an event at `stamp` (its timeStamp, the clock of
   * performance.now()): the values now are a sample at that time.
   * @param {number} stamp
   */
  mark(stamp) {
    const grab = this.grab;
    if (!grab || grab.drive) return;
    grab.marks.push({ stamp, row: this.heldRow() });
    if (stamp > grab.lastEvent && grab.events++ > 0) {
      grab.paces.push(stamp - grab.lastEvent);
      if (grab.paces.length > PACE) grab.paces.shift();
    }
    grab.lastEvent = Math.max(grab.lastEvent, stamp);
  }

  /**
   * Milliseconds without an event after which the held pointer is at rest: 1.5 of its
   * median interval between events, at least `REST`.
   * @param {Grab} grab
   */
  restMs(grab) {
    const sorted = [...grab.paces].sort((a, b) => a - b);
    return Math.max(REST, sorted.length ? 1.5 * sorted[sorted.length >> 1] : 0);
  }

  /**
   * The tolerance a take of `grab` is sent with, per path: what its input resolves there
   * now, in steps (`DEFAULT_STEPS`) or as the animator set it; a path the input gives no
   * resolution for is sent only with the animator's tolerance in its units.
   * @param {Grab} grab
   * @returns {Record<string, import('./take.js').SentTolerance>}
   */
  tolerances(grab) {
    const resolved = grab.resolve ? grab.resolve() : {};
    /** @type {Record<string, import('./take.js').SentTolerance>} */
    const out = {};
    for (const path of grab.paths) {
      const setting = this.studio.tolerances.get(path);
      const res = resolved[path];
      const unit = this.studio.types.get(path)?.unit === 'degrees' ? '°' : '';
      if (res && res.step > 0 && Number.isFinite(res.step)) out[path] = { ...takeTolerance(res, setting), input: res.input, unit };
      else if (setting?.unit === 'units') out[path] = { tol: setting.amount, steps: NaN, input: '', unit };
    }
    return out;
  }

  /** Let go of what is held: ends its take, or sends its edit outside record mode (an inert
   * hold: nothing, the server's values shown again). */
  release() {
    const grab = this.grab;
    if (!grab) return;
    if (grab.inert) {
      this.grab = null;
      this.studio.revert(grab.paths);
      return;
    }
    const now = performance.now();
    const took = !!grab.take;
    if (grab.take) this.endTake(grab, now);
    this.grab = null;
    if (!took && this.studio.transport.record) this.studio.revert(grab.paths);   // nothing was stored
    if (!grab.take && !this.studio.transport.record && grab.changed) {
      const merge = `${grab.label} ${now}`;
      for (const path of grab.paths) {
        this.studio.send({ type: 'set', path, value: this.studio.values.get(path), label: grab.label, merge });
      }
    }
  }

  /**
   * @param {Grab} grab
   * @param {number} time transport time of the first sample
   */
  beginTake(grab, time) {
    const s = this.studio;
    const id = `t${Date.now().toString(36)}${this.takeCount++}`;
    const dims = grab.paths.map((p) => s.types.get(p)?.dim ?? 0);
    grab.take = new TakeSampler(id, grab.paths, dims);
    grab.take.gap = this.stallGap();
    grab.take.tolerance = this.tolerances(grab);
    grab.take.smoothing = this.smoothing;
    const tol = Object.fromEntries(Object.entries(grab.take.tolerance).map(([path, t]) => [path, t.tol]));
    if (this.loopRecord && s.transport.clock.loop && !grab.loopKey) grab.loopKey = `loop ${id}`;
    s.beganTake();
    s.send({ type: 'take.begin', take: id, paths: grab.paths, mode: this.mode, blend: BLEND, time,
      speed: s.transport.captureSpeed, tol, loop: grab.loopKey, gap: grab.take.gap,
      smoothing: this.smoothing });
    this.heartbeat(true);
  }

  /**
   * While this page records a take, a ping every BEAT_MS whether samples go or not (the
   * server's silence rule then ends only the takes of pages gone or frozen).
   * @param {boolean} on
   */
  heartbeat(on) {
    if (on && this.beat === null) this.beat = setInterval(() => this.studio.send({ type: 'ping' }), BEAT_MS);
    if (!on && this.beat !== null) {
      clearInterval(this.beat);
      this.beat = null;
    }
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
    if (rest) this.studio.send(rest);
    this.studio.send({ type: 'take.end', take: take.id, label: `take ${grab.label}` });
    this.studio.endedTake(take, now);
    grab.take = null;
    this.heartbeat(false);
  }

  /**
   * The server ended this page's take (`reason`: the page fell silent, its socket went, the
   * server stops) and kept it: nothing more is sent for it, record mode goes off, the hold
   * still in the animator's hand sends nothing more, and a notice says what happened.
   * @param {NonNullable<import('./messages.js').TakeEnded['reason']>} reason
   */
  ended(reason) {
    const grab = this.grab;
    const take = grab?.take;
    if (!grab || !take) return;
    this.studio.endedTake(take, performance.now());
    grab.take = null;
    grab.inert = true;
    this.heartbeat(false);
    this.studio.tell('warning', ENDED[/** @type {keyof ENDED} */ (reason)] ?? `take kept: the server ended it (${reason})`, 'take');
    this.studio.transport.setRecord(false);
  }

  /**
   * This frame's samples of the take: a device's values at the frame's time; a pointer's
   * marks at their events' times, or, at rest, the start of the rest and the frame's time
   * (the first sample of a take: the values at the frame's time).
   * @param {Grab} grab
   * @param {TakeSampler} take
   * @param {number} now performance.now() of the frame
   * @param {number} time the frame's transport time
   */
  sample(grab, take, now, time) {
    const speed = this.studio.transport.clock.speed;
    const at = (/** @type {number} */ stamp) => time + (speed * (stamp - now)) / 1000;
    if (grab.drive || (!take.times.length && !grab.marks.length)) {
      take.add(time, this.heldRow(), now);
      return;
    }
    for (const m of grab.marks) take.add(at(m.stamp), m.row, m.stamp);
    const wait = this.restMs(grab);
    if (grab.marks.length || now - grab.lastEvent < wait) return;
    const rest = grab.lastEvent + wait;
    if (take.stamps[take.stamps.length - 1] < rest) take.add(at(rest), this.heldRow(), rest);
    take.add(time, this.heldRow(), now);
  }

  /** The server refused this page's take (another page records): the hold records nothing
   * more and shows the server's values again. */
  refused() {
    const grab = this.grab;
    if (!grab?.take) return;
    grab.take = null;
    grab.recordable = false;
    this.heartbeat(false);
    this.studio.revert(grab.paths);
  }

  /** Real seconds without a frame that make a stall: 0.25 s, or 4 frame intervals on a slow page. */
  stallGap() {
    const sorted = [...this.intervals].sort((a, b) => a - b);
    const median = sorted.length ? sorted[sorted.length >> 1] / 1000 : 0;
    return Math.max(GAP, 4 * median);
  }

  /** The row of the held attributes' current values, end to end. */
  heldRow() {
    return (this.grab?.paths ?? []).flatMap((p) => this.studio.values.get(p));
  }

  /**
   * A new frame: its interval is kept; the seconds a device moves for (at most a stall's).
   * @param {number} now performance.now() of the frame
   */
  lap(now) {
    const dt = Math.min(Math.max((now - this.lastFrame) / 1000, 0), GAP);
    if (Number.isFinite(this.lastFrame)) {
      this.intervals.push(now - this.lastFrame);
      if (this.intervals.length > 60) this.intervals.shift();
    }
    this.lastFrame = now;
    return dt;
  }

  /**
   * The loop wrapped: a pass ends here (the hold records the next pass only with loop
   * recording).
   * @param {number} now
   */
  wrapped(now) {
    const grab = this.grab;
    if (grab?.take) {
      this.endTake(grab, now);
      grab.recordable = this.loopRecord;
    }
  }

  /**
   * One frame of the hold: a device moves the held attributes, a take begins (record mode,
   * past the punch-in) or takes this frame's sample and sends a batch when due; outside
   * record mode the moved values are previewed.
   * @param {number} dt seconds a device moves for
   * @param {number} now performance.now() of the frame
   * @param {number} time the frame's transport time
   */
  step(dt, now, time) {
    const grab = this.grab;
    const transport = this.studio.transport;
    if (!grab) return;
    if (grab.drive) grab.drive(dt, now);
    if (grab.inert) {
      grab.marks.length = 0;
      return;
    }
    if (transport.record && !grab.take && grab.recordable && !this.studio.lock && transport.clock.playing
      && time >= transport.punchFrom) {
      this.beginTake(grab, time);
    }
    if (grab.take) {
      this.sample(grab, grab.take, now, time);
      const batch = grab.take.batch(now);
      if (batch) this.studio.send(batch);
    }
    grab.marks.length = 0;
    if (!grab.take && !transport.record && grab.dirty) {
      grab.dirty = false;
      for (const path of grab.paths) {
        this.studio.send({ type: 'preview', key: `${grab.label} ${path}`, path, value: this.studio.values.get(path) });
      }
    }
  }
}
