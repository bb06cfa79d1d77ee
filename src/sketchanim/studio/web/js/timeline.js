// @ts-check
/**
 * The timeline: a time ruler (scrub, Shift-drag: the loop range), the strips other panels
 * put above the lanes (`studio.strips`: the sound's waveform), then a header row per
 * animated object (click it to fold or unfold its lanes; the selected object's highlighted)
 * and a lane per animated attribute: a curve's takes as blocks (name, span, mode; muted
 * ones greyed) over its knots as ticks, a discrete track's values as steps (bool, enum)
 * or diamonds (events). Drawn on one canvas, only when something changed or the playhead moved.
 *
 * Gestures (retimehandles.js holds their state): drag a take's block to move the take; drag
 * its right edge to stretch it about its start (Ctrl: about the playhead); Alt-drag a lane
 * to move its whole track (the selected lanes' if it is in the range); drag on a lane's empty
 * time, or Shift-drag anywhere in the lanes, to select a range (across lanes too), then
 * Delete deletes it, Ctrl+C / Ctrl+X copy / cut it (the selected lane's), Ctrl+V pastes at
 * the playhead on the selected lane (a double-click selects the loop range on a lane, else its
 * whole track); the range's right edge stretches the selected tracks
 * about its start. A drag previews in the page, sends one message on release (one undo
 * step), snaps to frames when snap is on; Esc drops it. The wheel scrolls the lanes.
 */
import { fitCanvas } from './canvas.js';
import { beginDrag, dragTo, released, selectedRange } from './retimehandles.js';
import { GROUP_HEIGHT, HANDLE_PIXELS, LANE_HEIGHT, hitTake, layoutRows, rowAt } from './timelinelanes.js';
import { LABEL, RULER, paintGroup, paintLane, paintRange, paintReadout, paintRuler } from './timelinepaint.js';
import { viewRange } from './timescale.js';

/** @typedef {import('./retimehandles.js').TimeDrag} TimeDrag */
/** @typedef {import('./timelinelanes.js').Row} Row */
/** @typedef {import('./timelinelanes.js').LaneRow} LaneRow */
/** @typedef {import('./messages.js').TrackPieceInfo} Clipboard */

export class Timeline {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLCanvasElement} canvas
   */
  constructor(studio, canvas) {
    this.studio = studio;
    this.canvas = canvas;
    // Rasterised on the CPU, as the curve editor's canvases: many small marks through a
    // software GL flush for seconds (the first getContext's options stay the canvas's).
    canvas.getContext('2d', { willReadFrequently: true });
    /** @type {Set<string>} the objects whose lanes are folded */
    this.folded = new Set();
    /** @type {string | null} the lane Ctrl+V pastes on and Ctrl+C copies from */
    this.lane = null;
    /** Pixels the lanes are scrolled down by. */
    this.scroll = 0;
    /** @type {TimeDrag | null} the drag in the lanes in progress */
    this.drag = null;
    /** @type {Clipboard | null} the last piece copied (the page keeps the clipboard) */
    this.clipboard = null;
    /** Milliseconds the last draw took. */
    this.drawMs = 0;
    /** How many times it drew. */
    this.draws = 0;
    /** @type {Row[]} */
    this.rows = [];
    this.dirty = true;
    this.drawn = '';
    for (const name of /** @type {const} */ (['state', 'tracks', 'selection', 'attribute', 'projectSettings', 'transport', 'record', 'timeRange'])) {
      studio.signals.on(name, () => this.invalidate());
    }
    studio.signals.on('piece', (m) => { this.clipboard = m; });
    studio.signals.on('command', (c) => this.command(c));
    studio.signals.on('frame', () => this.draw());
    this.bind();
  }

  /** Draw again at the next frame (something the timeline shows changed). */
  invalidate() {
    this.dirty = true;
  }

  range() {
    const s = this.studio;
    return viewRange(s.playSpan, s.transport.clock.loop, s.transport.time);
  }

  /** The top of the lanes (below the ruler and the strips), in CSS pixels. */
  lanesTop() {
    return RULER + this.studio.strips.reduce((a, s) => a + s.height, 0);
  }

  /**
   * The time at a client x.
   * @param {number} x
   */
  timeAt(x) {
    const rect = this.canvas.getBoundingClientRect();
    const [t0, t1] = this.range();
    return t0 + ((x - rect.left - LABEL) / Math.max(rect.width - LABEL, 1)) * (t1 - t0);
  }

  /** Seconds per pixel on the time axis. */
  pixel() {
    const [t0, t1] = this.range();
    return (t1 - t0) / Math.max(this.canvas.clientWidth - LABEL, 1);
  }

  /**
   * The row at a client y (null: above the lanes or below the last).
   * @param {number} y
   */
  rowAtClient(y) {
    const top = this.canvas.getBoundingClientRect().top + this.lanesTop();
    return y < top ? null : rowAt(this.rows, y - top + this.scroll);
  }

  /**
   * The client point at time `t` in the middle of the row of `path` (a lane, or an object's
   * header), or null if it is not shown (folded, scrolled out of sight).
   * @param {string} path
   * @param {number} t
   * @returns {{x: number, y: number} | null}
   */
  where(path, t) {
    const row = this.rows.find((r) => (r.kind === 'lane' ? r.path : r.object) === path);
    const rect = this.canvas.getBoundingClientRect();
    const y = rect.top + this.lanesTop() + (row ? row.y - this.scroll + row.height / 2 : 0);
    if (!row || y < rect.top + this.lanesTop() || y > rect.bottom) return null;
    const [t0, t1] = this.range();
    return { x: rect.left + LABEL + ((t - t0) / (t1 - t0)) * (rect.width - LABEL), y };
  }

  /** @returns {LaneRow[]} */
  lanes() {
    return /** @type {LaneRow[]} */ (this.rows.filter((r) => r.kind === 'lane'));
  }

  // -- gestures -------------------------------------------------------------------------

  bind() {
    const c = this.canvas;
    const transport = this.studio.transport;
    /** @type {{loopFrom: number | null} | null} */
    let scrub = null;
    c.addEventListener('pointerdown', (e) => {
      c.setPointerCapture(e.pointerId);
      const rect = c.getBoundingClientRect();
      const t = this.timeAt(e.clientX);
      if (e.clientY - rect.top < this.lanesTop()) {
        scrub = { loopFrom: e.shiftKey ? t : null };
        if (!e.shiftKey) transport.seek(t);
        return;
      }
      const row = this.rowAtClient(e.clientY);
      if (!row) return;
      this.studio.select(row.object);
      if (row.kind === 'group') {
        if (e.clientX - rect.left < LABEL) this.fold(row.object);
        else transport.seek(t);
        return;
      }
      this.lane = row.path;
      this.studio.showAttribute(row.path.slice(row.object.length + 1));
      this.invalidate();
      if (e.clientX - rect.left >= LABEL) this.press(row, t, e);
    });
    c.addEventListener('pointermove', (e) => {
      const t = this.timeAt(e.clientX);
      if (scrub) {
        if (scrub.loopFrom === null) transport.seek(t);
        else transport.setLoop([Math.min(scrub.loopFrom, t), Math.max(scrub.loopFrom, t)]);
      } else if (this.drag) {
        this.move(t, e.clientY);
      } else {
        c.style.cursor = this.cursorAt(e);
      }
    });
    const end = (/** @type {PointerEvent} */ e) => {
      scrub = null;
      if (this.drag) this.release(e.type === 'pointerup', this.timeAt(e.clientX));
    };
    c.addEventListener('pointerup', end);
    c.addEventListener('pointercancel', end);
    c.addEventListener('dblclick', (e) => {        // a lane's range: the loop range, else its whole track
      const row = this.rowAtClient(e.clientY);
      if (!row || row.kind !== 'lane' || e.clientX - c.getBoundingClientRect().left < LABEL) return;
      const loop = this.studio.transport.clock.loop;
      const { track } = row;
      const span = loop ?? (track.kind === 'curve' ? [track.start, track.end] : [track.times[0] ?? 0, track.times.at(-1) ?? 0]);
      this.studio.selectRange(span[1] > span[0] ? { paths: [row.path], t0: span[0], t1: span[1] } : null);
    });
    c.addEventListener('wheel', (e) => {
      const rect = c.getBoundingClientRect();
      if (e.clientY - rect.top < this.lanesTop()) return;
      e.preventDefault();
      this.scrollBy(e.deltaY);
    }, { passive: false });
    // Esc drops a drag (before the studio's keys: it would deselect too); with a range selected, drops the range
    window.addEventListener('keydown', (e) => {
      if (e.key !== 'Escape' || (!this.drag && !this.studio.timeRange)) return;
      e.preventDefault();
      e.stopImmediatePropagation();
      if (this.drag) this.drag = null;
      else this.studio.selectRange(null);
      this.invalidate();
    }, { capture: true });
  }

  /**
   * The pointer's shape over the timeline: a stretch by a handle, a grab over a take's block,
   * a move with Alt, a pointer over the labels, the text cursor (scrub, select) elsewhere.
   * @param {PointerEvent} e
   */
  cursorAt(e) {
    const rect = this.canvas.getBoundingClientRect();
    const row = e.clientY - rect.top < this.lanesTop() ? null : this.rowAtClient(e.clientY);
    if (!row) return 'text';
    if (e.clientX - rect.left < LABEL || row.kind === 'group') return 'pointer';
    if (e.altKey) return 'move';
    const t = this.timeAt(e.clientX);
    const chosen = this.studio.timeRange;
    if (chosen && chosen.paths.includes(row.path) && Math.abs(t - chosen.t1) <= HANDLE_PIXELS * this.pixel()) return 'ew-resize';
    if (e.shiftKey) return 'text';
    const hit = hitTake(row.track, t, this.pixel());
    return hit.what === 'scale' ? 'ew-resize' : hit.what === 'take' ? 'grab' : 'text';
  }

  /**
   * A press at time `t` in the lane `row`: what it grabs.
   * @param {LaneRow} row
   * @param {number} t
   * @param {PointerEvent} e
   */
  press(row, t, e) {
    const { track, path } = row;
    const s = this.studio;
    const chosen = s.timeRange;
    const inRange = chosen !== null && chosen.paths.includes(path);
    const playhead = s.transport.time;
    const aboutPlayhead = e.ctrlKey || e.metaKey;
    if (s.readOnly) {                             // nothing moves; a range can still be selected and copied
      const from = s.snapped(t);
      this.drag = beginDrag('select', [path], -1, from, from, from);
      return;
    }
    if (inRange && chosen && Math.abs(t - chosen.t1) <= HANDLE_PIXELS * this.pixel() && !e.shiftKey) {
      this.drag = beginDrag('range-scale', chosen.paths, -1, t, chosen.t0, chosen.t1, aboutPlayhead ? playhead : chosen.t0);
      return;
    }
    const [start, end] = track.kind === 'curve' ? [track.start, track.end]
      : [track.times[0] ?? 0, track.times[track.times.length - 1] ?? 0];
    if (e.altKey) {
      this.drag = beginDrag('track', inRange && chosen ? chosen.paths : [path], -1, t, start, end);
      return;
    }
    const hit = e.shiftKey ? { what: 'lane', take: -1 } : hitTake(track, t, this.pixel());
    if (hit.what !== 'lane' && track.kind === 'curve') {
      const take = track.takes[hit.take];
      const pivot = hit.what === 'scale' && aboutPlayhead ? playhead : take.start;
      this.drag = beginDrag(hit.what === 'scale' ? 'scale' : 'take', [path], hit.take, t, take.start, take.end, pivot);
      return;
    }
    const from = s.snapped(t);
    this.drag = beginDrag('select', [path], -1, from, from, from);
  }

  /**
   * The pointer at time `t`, client y `y`, during a drag.
   * @param {number} t
   * @param {number} y
   */
  move(t, y) {
    const drag = this.drag;
    if (!drag) return;
    const s = this.studio;
    this.drag = dragTo(drag, t, s.fps, s.snap);
    if (drag.kind === 'select') {
      const lanes = this.lanes();
      const first = lanes.findIndex((r) => r.path === drag.paths[0]);
      const row = this.rowAtClient(y);
      const here = row && row.kind === 'lane' ? lanes.indexOf(row) : first;
      const [a, b] = [Math.min(first, here), Math.max(first, here)];
      this.drag = { ...this.drag, paths: [drag.paths[0], ...lanes.slice(a, b + 1).map((r) => r.path).filter((p) => p !== drag.paths[0])] };
      const span = selectedRange(this.drag);
      s.selectRange(span ? { paths: this.drag.paths, t0: span[0], t1: span[1] } : null);
    }
    this.invalidate();
  }

  /**
   * The drag ends: released (`send`) at time `t`, or cancelled.
   * @param {boolean} send
   * @param {number} t
   */
  release(send, t) {
    const drag = this.drag;
    this.drag = null;
    this.invalidate();
    if (!drag || !send) return;
    if (drag.kind === 'select') {
      if (!selectedRange(drag)) {               // a click: the playhead goes there, the range goes
        this.studio.selectRange(null);
        this.studio.transport.seek(t);
      }
      return;
    }
    const message = released(drag);
    if (message) this.studio.editInTime(message);
  }

  /** @param {string} object fold or unfold its lanes */
  fold(object) {
    if (this.folded.has(object)) this.folded.delete(object);
    else this.folded.add(object);
    this.invalidate();
  }

  /** @param {number} dy scroll the lanes by this many pixels */
  scrollBy(dy) {
    this.scroll = this.clamped(this.scroll + dy);
    this.invalidate();
  }

  /**
   * A scroll kept within the lanes (none when they all fit).
   * @param {number} scroll
   */
  clamped(scroll) {
    const last = this.rows[this.rows.length - 1];
    const total = last ? last.y + last.height : 0;
    return Math.min(Math.max(0, total - (this.canvas.clientHeight - this.lanesTop())), Math.max(0, scroll));
  }

  /**
   * The shortcuts the timeline acts on (keyboard.js): delete, copy, cut the selected range; paste.
   * @param {import('./keyboard.js').PanelCommand} command
   */
  command(command) {
    const s = this.studio;
    const chosen = s.timeRange;
    const lane = chosen && this.lane && chosen.paths.includes(this.lane) ? this.lane : chosen?.paths[0] ?? null;
    if (command === 'delete-range' && chosen) {
      s.cutRange(chosen.paths, chosen.t0, chosen.t1);
      s.selectRange(null);
    } else if ((command === 'copy' || command === 'cut') && chosen && lane) {
      s.copyRange(lane, chosen.t0, chosen.t1);
      if (command === 'cut') {
        s.cutRange([lane], chosen.t0, chosen.t1);
        s.selectRange(null);
      }
    } else if (command === 'paste' && this.clipboard && this.lane) {
      s.pasteRange(this.lane, s.snapped(s.transport.time), this.clipboard.piece, this.clipboard.length);
    }
  }

  // -- drawing ------------------------------------------------------------------------------

  /** What the picture depends on besides `dirty`: the playhead, the loop, the take in progress, the size. */
  key() {
    const s = this.studio;
    const { clock, time, record } = s.transport;
    const take = s.performer.grab?.take;
    return `${time}|${clock.loop}|${record}|${s.transport.countingIn}|${take?.last ?? ''}|${this.canvas.clientWidth}x${this.canvas.clientHeight}|${s.strips.length}`;
  }

  draw() {
    const key = this.key();
    if (!this.dirty && key === this.drawn) return;
    const began = performance.now();
    this.dirty = false;
    this.drawn = key;
    this.paint();
    this.draws += 1;
    this.drawMs = performance.now() - began;
  }

  /** Paint the whole timeline. */
  paint() {
    const s = this.studio;
    const { clock, time, record, punchFrom } = s.transport;
    const least = `${this.lanesTop() + GROUP_HEIGHT + LANE_HEIGHT}px`;      // the strips and a lane show in a small window
    if (this.canvas.style.minHeight !== least) this.canvas.style.minHeight = least;
    const { g, w, h } = fitCanvas(this.canvas);
    this.rows = layoutRows(s.objects, s.tracks, this.folded);
    g.fillStyle = '#17191e';
    g.fillRect(0, 0, w, h);
    const [t0, t1] = this.range();
    const width = Math.max(w - LABEL, 1);
    const x = (/** @type {number} */ t) => LABEL + ((t - t0) / (t1 - t0)) * width;
    g.font = '10px system-ui, sans-serif';
    g.textBaseline = 'middle';
    paintRuler(g, x, t0, t1, w, s.snap ? `snap ${+s.fps.toFixed(3)} fps` : 'snap off');
    let y = RULER;
    for (const strip of s.strips) {
      g.save();
      g.beginPath();
      g.rect(0, y, w, strip.height);
      g.clip();
      g.fillStyle = '#15171b';
      g.fillRect(LABEL, y, width, strip.height);
      strip.draw(g, { x: LABEL, y, width, height: strip.height }, t0, t1);
      g.fillStyle = '#8b93a3';
      g.fillText(strip.label, 8, y + strip.height / 2);
      g.restore();
      y += strip.height;
    }
    const top = y;
    this.scroll = this.clamped(this.scroll);
    g.save();
    g.beginPath();
    g.rect(0, top, w, h - top);
    g.clip();
    g.translate(0, top - this.scroll);
    /** @type {import('./timelinepaint.js').Look} */
    const look = { x, w, lane: this.lane, selected: s.selected, drag: this.drag };
    this.rows.forEach((row, i) => {
      if (row.y + row.height < this.scroll || row.y > this.scroll + h - top) return;
      if (row.kind === 'group') paintGroup(g, row, look);
      else paintLane(g, row, look, i % 2 === 1, s.types.get(row.path)?.name ?? '');
    });
    if (s.timeRange) paintRange(g, s.timeRange, this.lanes(), look);
    g.restore();
    paintReadout(g, look, s.fps);
    if (clock.loop) {
      g.fillStyle = 'rgba(90, 150, 255, 0.14)';
      g.fillRect(x(clock.loop[0]), 0, x(clock.loop[1]) - x(clock.loop[0]), h);
      g.fillStyle = '#5a96ff';
      g.fillRect(x(clock.loop[0]), 0, 2, h);
      g.fillRect(x(clock.loop[1]) - 2, 0, 2, h);
    }
    const take = s.performer.grab?.take;
    if (take && take.times.length) {
      g.fillStyle = '#ff4d4d';
      g.fillRect(x(take.times[0]), RULER - 5, Math.max(x(take.last) - x(take.times[0]), 2), 4);
    }
    if (s.transport.countingIn > 0) {
      g.fillStyle = 'rgba(255, 77, 77, 0.25)';
      g.fillRect(x(time), 0, x(punchFrom) - x(time), h);
    }
    g.fillStyle = '#2f343d';
    g.fillRect(LABEL - 1, 0, 1, h);
    g.fillStyle = record ? '#ff4d4d' : '#ffffff';
    g.fillRect(Math.round(x(time)) - 1, 0, 2, h);
  }
}
