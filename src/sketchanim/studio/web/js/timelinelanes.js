// @ts-check
/**
 * The timeline's rows, as pure geometry: a header row per object with animated attributes
 * (folded or not), under it a lane per animated attribute; what lies under a point of the
 * lanes (a take block, its retime handle, a lane's body); times snapped to frames.
 */

/** @typedef {import('./messages.js').Track} Track */
/** @typedef {import('./messages.js').TakeSpanInfo} TakeSpanInfo */

/** Height of an object's header row, in CSS pixels. */
export const GROUP_HEIGHT = 18;
/** Height of a lane, in CSS pixels. */
export const LANE_HEIGHT = 18;
/** Pixels either side of a block's right edge that grab its retime handle. */
export const HANDLE_PIXELS = 5;

/**
 * @typedef {object} GroupRow   An object's header row.
 * @property {'group'} kind
 * @property {string} object
 * @property {boolean} folded
 * @property {number} count   its animated attributes
 * @property {number} y       top, in the lanes' coordinates (0 at the first row, before scrolling)
 * @property {number} height
 */
/**
 * @typedef {object} LaneRow   An animated attribute's lane.
 * @property {'lane'} kind
 * @property {string} object
 * @property {string} path
 * @property {Track} track
 * @property {number} y
 * @property {number} height
 */
/** @typedef {GroupRow | LaneRow} Row */

/**
 * The rows for the scene's objects (in their order) and their tracks: a header per object
 * that has a track, its lanes (in the object's attribute order) unless it is folded.
 * @param {{name: string, attributes: {name: string}[]}[]} objects
 * @param {Map<string, Track>} tracks
 * @param {Set<string>} folded   the objects whose lanes are hidden
 * @returns {Row[]}
 *
 * @example
 * const track = { path: 'box.on', kind: 'steps', times: [], values: [] };
 * layoutRows([{ name: 'box', attributes: [{ name: 'on' }] }], new Map([['box.on', track]]), new Set())
 *   .map((r) => r.kind);     // ['group', 'lane']
 */
export function layoutRows(objects, tracks, folded) {
  /** @type {Row[]} */
  const rows = [];
  let y = 0;
  for (const o of objects) {
    const lanes = o.attributes.map((a) => `${o.name}.${a.name}`).filter((p) => tracks.has(p));
    if (!lanes.length) continue;
    const fold = folded.has(o.name);
    rows.push({ kind: 'group', object: o.name, folded: fold, count: lanes.length, y, height: GROUP_HEIGHT });
    y += GROUP_HEIGHT;
    if (fold) continue;
    for (const path of lanes) {
      rows.push({ kind: 'lane', object: o.name, path, track: /** @type {Track} */ (tracks.get(path)), y, height: LANE_HEIGHT });
      y += LANE_HEIGHT;
    }
  }
  return rows;
}

/**
 * The row at height `y` of the lanes (their coordinates), or null.
 * @param {Row[]} rows
 * @param {number} y
 * @returns {Row | null}
 */
export function rowAt(rows, y) {
  return rows.find((r) => y >= r.y && y < r.y + r.height) ?? null;
}

/**
 * @typedef {object} Hit   What a press in a lane's body lands on.
 * @property {'take' | 'scale' | 'lane'} what  a take's block, its right edge (the retime handle), the lane elsewhere
 * @property {number} take  the take's index (-1 for `lane`)
 */

/**
 * What lies at time `t` (`pixel` seconds per pixel) in a lane of `track`: the topmost
 * (latest) take block there, or its retime handle near its right edge, else the lane.
 * @param {Track} track
 * @param {number} t
 * @param {number} pixel
 * @returns {Hit}
 *
 * @example
 * // a curve with takes over 1..2 s and 1.5..3 s, at 0.01 s a pixel:
 * hitTake(track, 1.2, 0.01);    // {what: 'take', take: 0}
 * hitTake(track, 2.98, 0.01);   // {what: 'scale', take: 1}: its retime handle
 */
export function hitTake(track, t, pixel) {
  if (track.kind !== 'curve') return { what: 'lane', take: -1 };
  const grip = HANDLE_PIXELS * pixel;
  for (let i = track.takes.length - 1; i >= 0; i -= 1) {
    const take = track.takes[i];
    if (Math.abs(t - take.end) <= grip && t >= take.start) return { what: 'scale', take: i };
    if (t >= take.start && t <= take.end) return { what: 'take', take: i };
  }
  return { what: 'lane', take: -1 };
}

/**
 * A time difference snapped to whole frames of `fps` (when `snap`), else as it is.
 * @param {number} dt seconds
 * @param {number} fps
 * @param {boolean} snap
 *
 * @example
 * snapDelta(0.53, 24, true);   // 0.5416666666666666 (13 frames)
 */
export function snapDelta(dt, fps, snap) {
  return snap ? Math.round(dt * fps) / fps : dt;
}

/**
 * The time scale that takes a span from `pivot`..`end` to `pivot`..`to` (null when `to`
 * is not after `pivot`: a span cannot turn around).
 * @param {number} pivot
 * @param {number} end
 * @param {number} to
 * @returns {number | null}
 *
 * @example
 * scaleFactor(1, 3, 5);   // 2
 */
export function scaleFactor(pivot, end, to) {
  const f = (to - pivot) / (end - pivot);
  return end > pivot && to > pivot && Number.isFinite(f) ? f : null;
}

/**
 * The times of a discrete track where its value changes (the first always), with the value
 * from then on: what the lane draws as steps.
 * @param {number[]} times
 * @param {any[]} values
 * @returns {{t: number, value: any}[]}
 *
 * @example
 * changes([0, 1, 2, 3], [true, true, false, true]).map((c) => c.t);   // [0, 2, 3]
 */
export function changes(times, values) {
  /** @type {{t: number, value: any}[]} */
  const out = [];
  for (let i = 0; i < times.length; i += 1) {
    if (!out.length || out[out.length - 1].value !== values[i]) out.push({ t: times[i], value: values[i] });
  }
  return out;
}
