// @ts-check
/**
 * The performer: what the animator holds (a drag, a gizmo, a slider, a device) and the
 * takes it records. A hold keeps playback off its attributes until the release; in record
 * mode it is a take, sampled on every animation frame (stamped with transport time) and sent
 * to the server in batches; outside record mode it previews and, on release, sends one
 * undoable edit.
 */
import { TakeSampler } from './take.js';

/** Real seconds between frames beyond which the server treats the step as a stall (at least;
 * a slow page, e.g. software WebGL, gets 4 of its frame intervals: its ordinary frames are no stall). */
const GAP = 0.25;
/** Seconds of fade at a punch-in's seams. */
const BLEND = 0.1;

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
    this.takeCount = 0;
    this.lastFrame = -Infinity;
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
   * @returns {Grab}
   */
  hold(paths, label, drive = null) {
    if (this.grab) this.release();
    this.grab = { paths, label, changed: drive !== null, dirty: false, recordable: true, take: null, loopKey: null, drive };
    return this.grab;
  }

  /** Let go of what is held: ends its take, or sends its edit outside record mode. */
  release() {
    const grab = this.grab;
    if (!grab) return;
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
    if (this.loopRecord && s.transport.clock.loop && !grab.loopKey) grab.loopKey = `loop ${id}`;
    s.beganTake();
    s.send({ type: 'take.begin', take: id, paths: grab.paths, mode: this.mode, blend: BLEND, time,
      speed: s.transport.captureSpeed, loop: grab.loopKey, gap: grab.take.gap });
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
  }

  /** The server refused this page's take (another page records): the hold records nothing
   * more and shows the server's values again. */
  refused() {
    const grab = this.grab;
    if (!grab?.take) return;
    grab.take = null;
    grab.recordable = false;
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
    if (transport.record && !grab.take && grab.recordable && !this.studio.remoteTake && transport.clock.playing
      && time >= transport.punchFrom) {
      this.beginTake(grab, time);
    }
    if (grab.take) {
      grab.take.add(time, this.heldRow(), now);
      const batch = grab.take.batch(now);
      if (batch) this.studio.send(batch);
    } else if (!transport.record && grab.dirty) {
      grab.dirty = false;
      for (const path of grab.paths) {
        this.studio.send({ type: 'preview', key: `${grab.label} ${path}`, path, value: this.studio.values.get(path) });
      }
    }
  }
}
