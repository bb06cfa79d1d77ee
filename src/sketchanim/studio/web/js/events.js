// @ts-check
/**
 * Events as playback passes them: an event track's events fire once each time the playhead
 * moves over them while playing (across the wrap of the loop range too), never while it is
 * scrubbed or sought — what the model's `Player.apply` returns, for the page.
 */

/**
 * @typedef {object} Fired   An event playback passed.
 * @property {string} path   the event attribute ("object.cue")
 * @property {number} time   its time, seconds
 * @property {string | null} label
 */

/**
 * @typedef {object} Cues   The events of every event track, merged in time order.
 * @property {number[]} times
 * @property {string[]} paths
 * @property {(string | null)[]} labels
 */

/**
 * The events of `tracks` (event tracks) merged in time order (a stable merge: at one time,
 * in the order of `tracks`, then of their keys).
 * @param {import('./evaluate.js').Steps[]} tracks
 * @returns {Cues}
 *
 * @example
 * cuesOf([{path: 'a.cue', times: [2], values: ['x']}, {path: 'b.cue', times: [1, 2], values: [null, 'y']}]);
 * // {times: [1, 2, 2], paths: ['b.cue', 'a.cue', 'b.cue'], labels: [null, 'x', 'y']}
 */
export function cuesOf(tracks) {
  const all = tracks.flatMap((t) => t.times.map((time, i) => ({ time, path: t.path, label: /** @type {string | null} */ (t.values[i]) })));
  all.sort((a, b) => a.time - b.time);
  return { times: all.map((e) => e.time), paths: all.map((e) => e.path), labels: all.map((e) => e.label) };
}

/**
 * The events of `cues` with `from < time <= to` (`from <= time` if `closed`), in time order.
 * @param {Cues} cues
 * @param {number} from
 * @param {number} to
 * @param {boolean} [closed]
 * @returns {Fired[]}
 *
 * @example
 * between({times: [1, 2, 3], paths: ['box.cue', 'box.cue', 'box.cue'], labels: ['a', 'b', null]}, 1, 3);
 * // [{path: 'box.cue', time: 2, label: 'b'}, {path: 'box.cue', time: 3, label: null}]
 */
export function between(cues, from, to, closed = false) {
  /** @type {Fired[]} */
  const out = [];
  for (let i = 0; i < cues.times.length; i++) {
    const t = cues.times[i];
    if ((closed ? t >= from : t > from) && t <= to) out.push({ path: cues.paths[i], time: t, label: cues.labels[i] });
  }
  return out;
}

/**
 * The events playback passed going from `from` to `to` at `speed` (transport seconds per
 * second), in the order it passed them: forwards those in `(from, to]`, backwards those in
 * `(to, from]`, as the model's player fires them. `laps`: how many times it went round the
 * loop range `loop` on the way (forwards: to the loop's end, from its start on, `laps - 1`
 * whole passes between; backwards the other way). From outside the range (the playhead
 * jumped into it) only what it passed inside fires.
 * @param {Cues} cues
 * @param {number} from
 * @param {number} to
 * @param {number} speed
 * @param {[number, number] | null} loop
 * @param {number} laps
 * @returns {Fired[]}
 *
 * @example
 * const cues = cuesOf([{path: 'box.cue', times: [0.5, 1.5], values: [null, 'hit']}]);
 * passed(cues, 1, 0.6, 1, [0.5, 2], 1).map((e) => e.time);   // [1.5, 0.5]: round the loop
 * passed(cues, 1.6, 0.4, -1, null, 0).map((e) => e.time);    // [1.5, 0.5]: backwards
 */
export function passed(cues, from, to, speed, loop, laps) {
  if (!laps) return speed >= 0 ? between(cues, from, to) : between(cues, to, from).reverse();
  if (!loop) return [];
  const inside = from >= loop[0] && from < loop[1];
  const whole = inside ? Array.from({ length: laps - 1 }, () => between(cues, loop[0], loop[1], true)) : [];
  if (speed >= 0) {
    return [...(inside ? between(cues, from, loop[1]) : []), ...whole.flat(), ...between(cues, loop[0], to, true)];
  }
  return [...(inside ? between(cues, loop[0], from, true).reverse() : []), ...whole.flatMap((pass) => pass.reverse()),
    ...between(cues, to, loop[1]).reverse()];
}
