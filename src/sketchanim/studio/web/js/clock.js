// @ts-check
/**
 * The transport's clock: the browser's clock (performance.now(), milliseconds) mapped to
 * transport time (seconds). While it runs, `time = time0 + speed * (now - now0) / 1000`
 * from the last anchor (play, seek, a change of speed, a wrap of the loop), so a sample
 * stamped on an animation frame gets the transport time of that frame.
 */

/**
 * `time` brought into the loop range `[a, b)` (the loop's length added or taken away).
 * @param {number} time
 * @param {[number, number]} loop
 * @returns {number}
 *
 * @example
 * inLoop(5.5, [1, 3]);   // 1.5
 */
export function inLoop(time, [a, b]) {
  return a + ((((time - a) % (b - a)) + (b - a)) % (b - a));
}

export class Clock {
  constructor() {
    /** Transport seconds at the anchor. */
    this.time0 = 0;
    /** performance.now() at the anchor, milliseconds. */
    this.now0 = 0;
    this.playing = false;
    /** Transport seconds per real second (negative plays backwards). */
    this.speed = 1;
    /** @type {[number, number] | null} the loop range, when looping */
    this.loop = null;
  }

  /**
   * Transport time at `now`, without wrapping or stopping.
   * @param {number} now performance.now()
   * @returns {number}
   */
  raw(now) {
    return this.playing ? this.time0 + (this.speed * (now - this.now0)) / 1000 : this.time0;
  }

  /**
   * Advance to `now`: wraps inside the loop range (re-anchoring at the wrap), or, when
   * `end` is given and not looping, stops there (and at `start` playing backwards).
   * @param {number} now
   * @param {[number, number] | null} [bounds] where playback stops without a loop
   * @returns {{time: number, wrapped: boolean, laps: number, stopped: boolean}} `laps`: how many
   *   times it went round the loop range since the last tick (more than one after a stall longer than the range)
   */
  tick(now, bounds = null) {
    let time = this.raw(now);
    let wrapped = false;
    let laps = 0;
    let stopped = false;
    if (this.playing && this.loop && this.loop[1] > this.loop[0]) {
      const [a, b] = this.loop;
      if (time >= b || time < a) {
        wrapped = true;
        laps = Math.abs(Math.floor((time - a) / (b - a)));
        time = inLoop(time, this.loop);
        this.time0 = time;
        this.now0 = now;
      }
    } else if (this.playing && bounds && bounds[1] > bounds[0]) {
      if ((this.speed > 0 && time >= bounds[1]) || (this.speed < 0 && time <= bounds[0])) {
        time = Math.min(Math.max(time, bounds[0]), bounds[1]);
        this.playing = false;
        this.time0 = time;
        stopped = true;
      }
    }
    return { time, wrapped, laps, stopped };
  }

  /** @param {number} now */
  play(now) {
    if (!this.playing) {
      this.now0 = now;
      this.playing = true;
    }
  }

  /** @param {number} now */
  pause(now) {
    this.time0 = this.raw(now);
    this.playing = false;
  }

  /**
   * @param {number} time
   * @param {number} now
   */
  seek(time, now) {
    this.time0 = time;
    this.now0 = now;
  }

  /**
   * @param {number} speed
   * @param {number} now
   */
  setSpeed(speed, now) {
    this.time0 = this.raw(now);
    this.now0 = now;
    this.speed = speed;
  }
}
