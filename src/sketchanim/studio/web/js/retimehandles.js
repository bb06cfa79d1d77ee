// @ts-check
/**
 * The timeline's drags in time, as pure state: what a press grabbed (a take's block, its
 * retime handle, a whole track, the range selection's handle, a range being selected),
 * what it previews as the pointer moves (snapped to frames when asked), and the one
 * message its release sends (one History step). Esc drops a drag: nothing is sent.
 */
import { scaleFactor, snapDelta } from './timelinelanes.js';

/** @typedef {import('./messages.js').PageMessage} PageMessage */

/**
 * @typedef {object} TimeDrag   A drag in the timeline's lanes.
 * @property {'take' | 'scale' | 'track' | 'range-scale' | 'select'} kind
 *   move a take, stretch a take (its handle), move whole tracks, stretch whole tracks (the
 *   range selection's handle), select a range
 * @property {string[]} paths   the tracks it moves (one for a take)
 * @property {number} take      the take's index (-1: none)
 * @property {number} from      the time pressed
 * @property {number} start     the span being moved or stretched: its start and end
 * @property {number} end
 * @property {number} pivot     the time a stretch keeps
 * @property {number} to        the time the pointer is at (snapped as the drag's result is)
 * @property {number} by        a move's shift in seconds (whole frames when snapped)
 */

/**
 * A drag beginning at time `from` on the span `start`..`end` (a take's, a track's, the range's).
 * @param {TimeDrag['kind']} kind
 * @param {string[]} paths
 * @param {number} take
 * @param {number} from
 * @param {number} start
 * @param {number} end
 * @param {number} [pivot]   what a stretch keeps (the span's start if not given)
 * @returns {TimeDrag}
 */
export function beginDrag(kind, paths, take, from, start, end, pivot = start) {
  return { kind, paths, take, from, start, end, pivot, to: from, by: 0 };
}

/**
 * `drag` with the pointer at time `t`: a move by whole frames of `fps` (`snap`), a stretch's
 * new end on a frame, a range's other end on a frame.
 * @param {TimeDrag} drag
 * @param {number} t
 * @param {number} fps
 * @param {boolean} snap
 * @returns {TimeDrag}
 */
export function dragTo(drag, t, fps, snap) {
  if (drag.kind === 'take' || drag.kind === 'track') {
    const by = snapDelta(t - drag.from, fps, snap);
    return { ...drag, to: drag.from + by, by };
  }
  return { ...drag, to: snap ? Math.round(t * fps) / fps : t };
}

/**
 * How `drag` maps times as it is now: time t goes to pivot + factor (t - pivot) + shift.
 * @param {TimeDrag} drag
 * @returns {{factor: number, pivot: number, shift: number}}
 *
 * @example
 * mapping(dragTo(beginDrag('take', ['box.position'], 0, 1, 1, 2), 1.53, 24, true));   // {factor: 1, pivot: 0, shift: 0.5416666666666666}: 13 frames
 */
export function mapping(drag) {
  if (drag.kind === 'take' || drag.kind === 'track') return { factor: 1, pivot: 0, shift: drag.by };
  if (drag.kind === 'select') return { factor: 1, pivot: 0, shift: 0 };
  return { factor: scaleFactor(drag.pivot, drag.end, drag.to) ?? 1, pivot: drag.pivot, shift: 0 };
}

/**
 * A time as `drag` moves it now (for the preview).
 * @param {TimeDrag} drag
 * @param {number} t
 */
export function moved(drag, t) {
  const m = mapping(drag);
  return m.pivot + m.factor * (t - m.pivot) + m.shift;
}

/**
 * The range a `select` drag covers, ordered (null if it covers no time).
 * @param {TimeDrag} drag
 * @returns {[number, number] | null}
 */
export function selectedRange(drag) {
  const a = Math.min(drag.from, drag.to);
  const b = Math.max(drag.from, drag.to);
  return b > a ? [a, b] : null;
}

/**
 * The message the release of `drag` sends (null: nothing moved, or a range selection).
 * @param {TimeDrag} drag
 * @returns {PageMessage | null}
 *
 * @example
 * released(dragTo(beginDrag('scale', ['box.position'], 1, 3, 1, 3), 5, 24, true));
 * // {type: 'take.edit', path: 'box.position', take: 1, op: 'scale', factor: 2, pivot: 1}
 */
export function released(drag) {
  const { factor, pivot, shift } = mapping(drag);
  if (drag.kind === 'select' || (factor === 1 && shift === 0)) return null;
  const path = drag.paths[0];
  switch (drag.kind) {
    case 'take': return { type: 'take.edit', path, take: drag.take, op: 'shift', by: shift };
    case 'scale': return { type: 'take.edit', path, take: drag.take, op: 'scale', factor, pivot };
    case 'track': return { type: 'track.retime', paths: drag.paths, shift };
    default: return { type: 'track.retime', paths: drag.paths, factor, pivot };
  }
}
