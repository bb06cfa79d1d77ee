// @ts-check
/**
 * The transport: the clock that maps the browser's time to transport time, play / pause /
 * stop / seek, speed, the loop range, and record mode (the transport runs at the capture
 * speed, after the count-in's pre-roll). What it changes, and the record settings (count-in,
 * capture speed, the performer's layer mode and loop recording), goes to the server (kept for
 * a reload, relayed to the other pages) and out as the "transport", "settings" and "record"
 * signals. While another page records a take, or the project is read-only, record mode stays off here.
 */
import { Clock, inLoop } from './clock.js';

/** @typedef {import('./messages.js').TransportFields} TransportFields */

export class Transport {
  /** @param {import('./Studio.js').Studio} studio */
  constructor(studio) {
    this.studio = studio;
    this.clock = new Clock();
    /** Transport seconds at the last frame (or seek). */
    this.time = 0;
    /** Transport seconds per real second outside record mode. */
    this.playSpeed = 1;
    this.record = false;
    /** Seconds of pre-roll before recording starts (0: off). */
    this.countIn = 0;
    /** Transport seconds per real second while recording. */
    this.captureSpeed = 1;
    /** Takes start only once the transport reaches this time (the count-in's end). */
    this.punchFrom = -Infinity;
    /** @type {[number, number] | null} the last loop range, for turning the loop on again */
    this.lastLoop = null;
  }

  /**
   * The server's transport and record settings (on connecting, or another page's): taken
   * as they are; it plays only once the state is loaded.
   * @param {TransportFields} m
   */
  receive(m) {
    const now = performance.now();
    this.clock.seek(m.time, now);
    this.clock.loop = m.loop;
    if (m.loop) this.lastLoop = m.loop;
    this.playSpeed = m.speed;
    this.clock.setSpeed(m.speed, now);
    if (m.playing && this.studio.loaded) this.clock.play(now);
    else this.clock.pause(now);
    this.time = m.time;
    this.studio.firedTo = m.time;
    this.countIn = m.count_in;
    this.captureSpeed = m.capture_speed;
    this.studio.performer.mode = m.mode;
    this.studio.performer.loopRecord = m.loop_record;
    this.studio.performer.smoothing = m.smoothing;
    this.studio.signals.emit('transport');
    this.studio.signals.emit('settings');
  }

  /** Tell the server (and the panels) the transport and the record settings as they are now. */
  send() {
    const p = this.studio.performer;
    this.studio.send({ type: 'transport', time: this.time, playing: this.clock.playing, speed: this.playSpeed,
      loop: this.clock.loop, count_in: this.countIn, capture_speed: this.captureSpeed, mode: p.mode,
      loop_record: p.loopRecord, smoothing: p.smoothing });
    this.studio.signals.emit('transport');
  }

  /**
   * Advance the clock to `now` (a frame): wraps in the loop, stops at the tracks' end
   * outside record mode.
   * @param {number} now performance.now()
   */
  tick(now) {
    const step = this.clock.tick(now, this.record ? null : this.studio.playSpan);
    this.time = step.time;
    return step;
  }

  play() {
    const now = performance.now();
    const span = this.studio.playSpan;
    if (!this.record && span[1] > span[0] && !this.clock.loop && this.playSpeed > 0 && this.time >= span[1]) {
      this.clock.seek(span[0], now);                          // play again from the start
    }
    this.clock.play(now);
    this.send();
  }

  pause() {
    this.clock.pause(performance.now());
    this.time = this.clock.time0;
    this.send();
  }

  togglePlay() {
    if (this.clock.playing) this.pause();
    else this.play();
  }

  /** Pause and go back to the loop's start (or the start). */
  stop() {
    if (this.record) this.setRecord(false);
    this.pause();
    this.seek(this.clock.loop ? this.clock.loop[0] : Math.min(0, this.studio.span[0]));
  }

  /** @param {number} time */
  seek(time) {
    this.clock.seek(time, performance.now());
    this.time = time;
    this.studio.firedTo = time;                                   // no event fires on the way
    this.studio.writeTracks(time);
    this.send();
  }

  /**
   * Pause and step `n` frames of the project's frame rate (back if negative), landing on a frame
   * (from between two frames, as after a change of frame rate, the first step lands on the next one).
   * @param {number} n
   */
  stepFrames(n) {
    if (this.clock.playing) this.pause();
    const fps = this.studio.fps;
    const at = this.time * fps;
    const near = Math.round(at);
    const on = Math.abs(at - near) < 1e-6 ? near : null;           // on a frame, or between two
    this.seek(((on ?? (n > 0 ? Math.floor(at) : Math.ceil(at))) + n) / fps);
  }

  /**
   * The transport's time at `stamp` (performance.now() of an input event: between two frames,
   * so an event keyed while playing lands when it was pressed), inside the loop range when looping.
   * @param {number} stamp
   * @returns {number}
   */
  timeAt(stamp) {
    const t = this.clock.raw(stamp);
    const loop = this.clock.loop;
    if (!this.clock.playing || !loop || !(loop[1] > loop[0])) return t;
    return inLoop(t, loop);
  }

  /** The frame the transport is on (the project's frame rate; frame 0 at time 0). */
  get frame() {
    return Math.round(this.time * this.studio.fps);
  }

  /** @param {number} speed */
  setSpeed(speed) {
    this.playSpeed = speed;
    if (!this.record) this.clock.setSpeed(speed, performance.now());
    this.send();
  }

  /** @param {[number, number] | null} loop */
  setLoop(loop) {
    this.clock.loop = loop && loop[1] > loop[0] ? loop : null;
    if (this.clock.loop) this.lastLoop = this.clock.loop;
    this.send();
  }

  /** Loop off, or on over the last loop range (else the tracks' span, else 0 to 4 s). */
  toggleLoop() {
    const [a, b] = this.studio.span;
    this.setLoop(this.clock.loop ? null : this.lastLoop ?? (b > a ? [a, b] : [0, 4]));
  }

  /**
   * Record mode: the transport runs (at the capture speed, after the count-in's pre-roll)
   * and every grab is a take; off, the take in progress ends and the transport pauses.
   * @param {boolean} on
   */
  setRecord(on) {
    const now = performance.now();
    if (on === this.record || (on && this.studio.lock)) return;
    this.record = on;
    if (on) {
      const time = this.clock.raw(now);
      this.punchFrom = time;
      if (this.countIn > 0) this.clock.seek(time - this.countIn * this.captureSpeed, now);
      this.clock.setSpeed(this.captureSpeed, now);
      this.clock.play(now);
    } else {
      this.clock.setSpeed(this.playSpeed, now);
      this.clock.pause(now);
      this.time = this.clock.time0;
    }
    this.studio.signals.emit('record', on);
    this.send();
  }

  /** @param {number} seconds the count-in's pre-roll (0: off) */
  setCountIn(seconds) {
    this.countIn = seconds;
    this.studio.signals.emit('settings');
    this.send();
  }

  /** @param {number} speed transport seconds per real second while recording */
  setCaptureSpeed(speed) {
    this.captureSpeed = speed;
    this.studio.signals.emit('settings');
    this.send();
  }

  /** Seconds left of the count-in (0 when none is running). */
  get countingIn() {
    return this.record && this.time < this.punchFrom ? this.punchFrom - this.time : 0;
  }
}
