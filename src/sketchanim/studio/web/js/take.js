// @ts-check
/**
 * One take as the page samples it: rows of the grabbed attributes' values (end to end,
 * in the order of `paths`), each stamped with the transport time it was true (an input
 * event's, or a frame's: Performer.js), kept for drawing the raw trail and sent to the
 * server in batches.
 */

/**
 * @typedef {object} SentTolerance  A take's tolerance for one attribute, as sent and shown.
 * @property {number} tol    in the attribute's units
 * @property {number} steps  in input steps (NaN: set in units, no input resolution)
 * @property {string} input  what a step is ('px', 'step')
 * @property {string} unit   the attribute's unit as shown ('°' for degrees)
 */

export class TakeSampler {
  /**
   * @param {string} id        the take's key on the wire
   * @param {string[]} paths   the attributes recorded, in row order
   * @param {number[]} dims    their sizes
   * @param {number} [batchMs] send a batch when the oldest unsent sample is this old
   */
  constructor(id, paths, dims, batchMs = 50) {
    this.id = id;
    this.paths = paths;
    this.dims = dims;
    this.width = dims.reduce((a, b) => a + b, 0);
    this.batchMs = batchMs;
    /** @type {number[]} every sample's transport time */
    this.times = [];
    /** @type {number[][]} every sample's row */
    this.rows = [];
    /** @type {number[]} performance.now() clock time of every sample (its event's or frame's) */
    this.stamps = [];
    this.sent = 0;
    this.dropped = 0;
    /** Real seconds without a frame that the server treats as a stall (set at the take's start). */
    this.gap = 0.25;
    /** @type {Record<string, SentTolerance>} the tolerance sent, by path (set at the take's start) */
    this.tolerance = {};
    /** Seconds the server smooths the samples over before it reduces them (0: off; set at the take's start). */
    this.smoothing = 0;
  }

  /** The last sample's transport time (-Infinity before the first). */
  get last() {
    return this.times.length ? this.times[this.times.length - 1] : -Infinity;
  }

  /**
   * Keep one frame's sample; refused (false) when its time does not come after the last
   * one's or a value is not a finite number (nothing is sent that the server would refuse).
   * @param {number} t transport time
   * @param {number[]} row
   * @param {number} now its performance.now() clock time (the event's or the frame's)
   * @returns {boolean}
   */
  add(t, row, now) {
    if (!(t > this.last) || row.length !== this.width || !row.every(Number.isFinite)) {
      this.dropped += 1;
      return false;
    }
    this.times.push(t);
    this.rows.push(row);
    this.stamps.push(now);
    return true;
  }

  /**
   * The unsent samples as a `take.samples` message if they are due (`force`, or the
   * oldest is `batchMs` old at `now`), else null.
   * @param {number} now
   * @param {boolean} [force]
   * @returns {{type: 'take.samples', take: string, t: number[], values: number[][]} | null}
   */
  batch(now, force = false) {
    const n = this.times.length;
    if (this.sent >= n || (!force && now - this.stamps[this.sent] < this.batchMs)) return null;
    const message = { type: /** @type {'take.samples'} */ ('take.samples'), take: this.id,
      t: this.times.slice(this.sent, n), values: this.rows.slice(this.sent, n) };
    this.sent = n;
    return message;
  }

  /**
   * The samples of one path, as (times, values of that path).
   * @param {string} path
   * @returns {{times: number[], values: number[][]}}
   */
  channel(path) {
    const j = this.paths.indexOf(path);
    if (j < 0) return { times: [], values: [] };
    const lo = this.dims.slice(0, j).reduce((a, b) => a + b, 0);
    return { times: this.times, values: this.rows.map((r) => r.slice(lo, lo + this.dims[j])) };
  }
}
