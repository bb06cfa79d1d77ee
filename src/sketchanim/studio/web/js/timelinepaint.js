// @ts-check
/**
 * Painting the timeline's parts on its canvas (timeline.js lays them out and says where):
 * the time ruler, an object's header row, a lane (a curve's takes as blocks over its knots,
 * a discrete track's steps or events), the selected range and a drag's readout. A drag in
 * progress is drawn where it would put what it moves (retimehandles.js maps the times).
 */
import { mapping, moved } from './retimehandles.js';
import { changes } from './timelinelanes.js';
import { tickStep } from './timescale.js';

/** @typedef {import('./retimehandles.js').TimeDrag} TimeDrag */
/** @typedef {import('./timelinelanes.js').LaneRow} LaneRow */

/** Width of the label column, in CSS pixels. */
export const LABEL = 150;
/** Height of the time ruler, in CSS pixels. */
export const RULER = 20;

const COLORS = { replace: '#3f6fb8', additive: '#3f9a6a', muted: '#4a4f59', knot: 'rgba(255,255,255,0.35)',
  steps: '#c98f3a', event: '#e8b04b', selection: 'rgba(232, 176, 75, 0.18)', lane: '#1c1f25', laneAlt: '#1a1d22' };

/**
 * @typedef {object} Look   What the rows are painted with.
 * @property {(t: number) => number} x   a time's canvas x (CSS pixels)
 * @property {number} w                  the canvas's width
 * @property {string | null} lane        the selected lane's path
 * @property {string | null} selected    the selected object
 * @property {TimeDrag | null} drag      the drag in progress
 */

/**
 * The ruler: a tick and its time every round step, and whether snap is on.
 * @param {CanvasRenderingContext2D} g
 * @param {(t: number) => number} x
 * @param {number} t0
 * @param {number} t1
 * @param {number} w
 * @param {string} note   what the label column says (snap)
 */
export function paintRuler(g, x, t0, t1, w, note) {
  g.fillStyle = '#1f232a';
  g.fillRect(0, 0, w, RULER);
  const step = tickStep((w - LABEL) / (t1 - t0));
  g.fillStyle = '#8b93a3';
  g.strokeStyle = '#3a404c';
  g.beginPath();
  for (let t = Math.ceil(t0 / step) * step; t <= t1; t += step) {
    const xt = Math.round(x(t)) + 0.5;
    g.moveTo(xt, RULER - 8);
    g.lineTo(xt, RULER);
    g.fillText(`${+t.toFixed(3)}s`, xt + 3, 7);
  }
  g.stroke();
  g.fillText(note, 8, RULER / 2);
}

/**
 * An object's header row: its fold triangle, its name, its lane count when folded.
 * @param {CanvasRenderingContext2D} g
 * @param {import('./timelinelanes.js').GroupRow} row
 * @param {Look} look
 */
export function paintGroup(g, row, look) {
  const selected = row.object === look.selected;
  g.fillStyle = selected ? '#3a3324' : '#23272f';
  g.fillRect(0, row.y, look.w, row.height);
  g.fillStyle = selected ? '#e8b04b' : '#d5dae3';
  const mid = row.y + row.height / 2;
  g.beginPath();
  if (row.folded) {
    g.moveTo(8, mid - 4); g.lineTo(13, mid); g.lineTo(8, mid + 4);
  } else {
    g.moveTo(6, mid - 3); g.lineTo(14, mid - 3); g.lineTo(10, mid + 3);
  }
  g.fill();
  g.font = '600 11px system-ui, sans-serif';
  g.fillText(row.object, 20, mid);
  g.font = '10px system-ui, sans-serif';
  g.fillStyle = '#8b93a3';
  if (row.folded) g.fillText(`${row.count} lane${row.count === 1 ? '' : 's'}`, LABEL - 50, mid);
}

/**
 * A lane: its label, its takes or steps, its knots; drawn moved as the drag previews.
 * @param {CanvasRenderingContext2D} g
 * @param {LaneRow} row
 * @param {Look} look
 * @param {boolean} odd     the lane's shade
 * @param {string} kind     its attribute type's name (bool, enum, event: how steps are drawn)
 */
export function paintLane(g, row, look, odd, kind) {
  const { track, path, y, height } = row;
  const { x, w, drag } = look;
  const whole = drag && (drag.kind === 'track' || drag.kind === 'range-scale') && drag.paths.includes(path);
  const at = whole && drag ? (/** @type {number} */ t) => x(moved(drag, t)) : x;
  g.fillStyle = path === look.lane ? '#262c37' : row.object === look.selected ? '#202329' : odd ? COLORS.lane : COLORS.laneAlt;
  g.fillRect(0, y, w, height);
  g.fillStyle = path === look.lane ? '#ffffff' : '#b4bac6';
  g.fillText(path.slice(row.object.length + 1), 22, y + height / 2);
  const mid = y + height / 2;
  if (track.kind === 'steps') {
    paintSteps(g, track, at, y, height, w, kind);
    return;
  }
  g.fillStyle = '#3a404c';
  g.fillRect(at(track.start), mid - 1, Math.max(at(track.end) - at(track.start), 1), 2);
  track.takes.forEach((take, i) => {
    const one = drag && (drag.kind === 'take' || drag.kind === 'scale') && drag.paths[0] === path && drag.take === i;
    const [a, b] = one && drag ? [x(moved(drag, take.start)), x(moved(drag, take.end))] : [at(take.start), at(take.end)];
    if (one) {                                  // where it was, faint, under where it goes
      g.fillStyle = 'rgba(255,255,255,0.08)';
      g.fillRect(at(take.start), y + 2, at(take.end) - at(take.start), height - 4);
    }
    g.globalAlpha = take.muted ? 0.45 : 0.9;
    g.fillStyle = take.muted ? COLORS.muted : take.mode === 'additive' ? COLORS.additive : COLORS.replace;
    g.fillRect(a, y + 2, Math.max(b - a, 2), height - 4);
    g.globalAlpha = 1;
    g.fillStyle = one ? '#ffffff' : 'rgba(255,255,255,0.6)';
    g.fillRect(Math.max(b - 3, a), y + 2, 3, height - 4);           // the retime handle
    if (b - a > 30) {
      g.save();
      g.beginPath();
      g.rect(a, y, b - a - 4, height);
      g.clip();
      g.fillStyle = take.muted ? '#9aa0aa' : '#ffffff';
      g.fillText(`${take.name || `take ${i + 1}`}${take.mode === 'additive' ? ' +' : ''}${take.muted ? ' (muted)' : ''}`, a + 4, mid);
      g.restore();
    }
  });
  g.fillStyle = COLORS.knot;
  const k = track.order;
  let last = NaN;
  for (let i = k; i < track.knots.length - k; i += 1) {
    const t = track.knots[i];
    if (t === last) continue;
    last = t;
    g.fillRect(Math.round(at(t)), y + height - 4, 1, 3);
  }
}

/**
 * A discrete track: a bar where a bool is on, the value's text at each change of an enum,
 * a diamond per event.
 * @param {CanvasRenderingContext2D} g
 * @param {import('./messages.js').StepsTrack} track
 * @param {(t: number) => number} at
 * @param {number} y
 * @param {number} height
 * @param {number} w
 * @param {string} kind   the attribute type's name
 */
function paintSteps(g, track, at, y, height, w, kind) {
  const mid = y + height / 2;
  if (kind === 'event') {
    g.fillStyle = COLORS.event;
    for (const t of track.times) {
      const xt = at(t);
      g.beginPath();
      g.moveTo(xt, mid - 5); g.lineTo(xt + 4, mid); g.lineTo(xt, mid + 5); g.lineTo(xt - 4, mid);
      g.fill();
    }
    return;
  }
  const steps = changes(track.times, track.values);
  steps.forEach((step, i) => {
    const a = at(step.t);
    const b = i + 1 < steps.length ? at(steps[i + 1].t) : w;
    if (kind === 'bool') {
      if (step.value === true) {
        g.fillStyle = COLORS.steps;
        g.fillRect(a, y + 4, Math.max(b - a, 1), height - 8);
      }
    } else {
      g.fillStyle = COLORS.steps;
      g.fillText(String(step.value), a + 3, mid);
    }
    g.fillStyle = '#ffffff';
    g.fillRect(a, y + 2, 1, height - 4);
  });
}

/**
 * What the drag does, in the ruler by the pointer: the move in seconds and frames, or the stretch.
 * @param {CanvasRenderingContext2D} g
 * @param {Look} look
 * @param {number} fps
 */
export function paintReadout(g, look, fps) {
  const { drag, x, w } = look;
  if (!drag || drag.kind === 'select') return;
  const { factor, shift } = mapping(drag);
  const sign = shift >= 0 ? '+' : '';
  const text = drag.kind === 'take' || drag.kind === 'track'
    ? `${sign}${shift.toFixed(3)} s (${sign}${+(shift * fps).toFixed(2)} f)`
    : `×${factor.toFixed(3)} about ${drag.pivot.toFixed(3)} s`;
  g.font = '600 11px system-ui, sans-serif';
  const width = g.measureText(text).width + 10;
  const left = Math.min(Math.max(LABEL, x(drag.to) + 6), w - width);
  g.fillStyle = '#e8b04b';
  g.fillRect(left, 2, width, RULER - 4);
  g.fillStyle = '#15171b';
  g.fillText(text, left + 5, RULER / 2);
  g.font = '10px system-ui, sans-serif';
}

/**
 * The selected range over its lanes, with its retime handle at its right edge.
 * @param {CanvasRenderingContext2D} g
 * @param {import('./Studio.js').TimeRange} chosen
 * @param {LaneRow[]} lanes
 * @param {Look} look
 */
export function paintRange(g, chosen, lanes, look) {
  const stretching = look.drag?.kind === 'range-scale' ? look.drag : null;
  const a = look.x(stretching ? moved(stretching, chosen.t0) : chosen.t0);
  const b = look.x(stretching ? moved(stretching, chosen.t1) : chosen.t1);
  for (const row of lanes) {
    if (!chosen.paths.includes(row.path)) continue;
    g.fillStyle = COLORS.selection;
    g.fillRect(a, row.y, b - a, row.height);
    g.fillStyle = '#e8b04b';
    g.fillRect(a, row.y, 1, row.height);
    g.fillRect(b - 2, row.y, 2, row.height);
  }
}
