// @ts-check
/**
 * The transport bar: record, punch-in or additive, smoothing, count-in, capture speed, loop recording;
 * stop, play / pause, one frame back / on, the time and the frame, speed, loop; the project's
 * frame rate and snapping to frames; what is being recorded; undo and redo.
 */
import { choice, el } from './dom.js';
import { SMOOTHING } from './Performer.js';
import { formatTolerance } from './resolution.js';
import { formatTime } from './timescale.js';

/** The frame rates the menu offers (frames per second; the server's protocol.FRAME_RATES; a project's own is added). */
export const FRAME_RATES = [12, 15, 23.976, 24, 25, 29.97, 30, 48, 50, 59.94, 60, 120];

export class TransportBar {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} bar
   */
  constructor(studio, bar) {
    this.studio = studio;
    const t = studio.transport;
    const p = studio.performer;
    this.recordButton = el('button', { class: 'record', 'data-testid': 'record', title: 'Record mode (R): every grab is a take' });
    this.recordButton.innerHTML = '<span class="dot"></span><span class="label">REC</span>';
    this.recordButton.addEventListener('click', () => t.setRecord(!t.record));
    const stopButton = el('button', { 'data-testid': 'stop', title: 'Stop (Enter): back to the start' }, '■');
    stopButton.addEventListener('click', () => t.stop());
    this.playButton = el('button', { class: 'play', 'data-testid': 'play', title: 'Play / pause (Space)' }, '▶');
    this.playButton.addEventListener('click', () => t.togglePlay());
    this.clockText = el('span', { class: 'clock', 'data-testid': 'time' }, '0:00.00');
    this.frameText = el('span', { class: 'frame', 'data-testid': 'frame', title: 'The frame the playhead is on (at the project\'s frame rate)' }, '0');
    const back = el('button', { class: 'step', 'data-testid': 'frame-back', title: 'One frame back (←)' }, '◂');
    back.addEventListener('click', () => t.stepFrames(-1));
    const on = el('button', { class: 'step', 'data-testid': 'frame-on', title: 'One frame on (→)' }, '▸');
    on.addEventListener('click', () => t.stepFrames(1));
    const fps = choice('fps', FRAME_RATES.map((r) => [String(r), String(r)]), String(studio.fps), (v) => studio.setFps(Number(v)), 'fps');
    fps.wrap.title = "The project's frame rate: frame numbers, ← / → steps and snapping count in it (every tab shows it)";
    this.fps = fps.select;
    this.snapButton = el('button', { class: 'toggle', 'data-testid': 'snap', title: 'Snap edits in time (knots, the playhead) to frames (Shift+S)' }, 'snap');
    this.snapButton.addEventListener('click', () => studio.toggleSnap());
    this.loopButton = el('button', { class: 'toggle', 'data-testid': 'loop', title: 'Loop the range (L); shift-drag on the timeline sets it' }, '⟲ loop');
    this.loopButton.addEventListener('click', () => t.toggleLoop());
    const speed = choice('speed', [['0.25', '¼×'], ['0.5', '½×'], ['1', '1×'], ['2', '2×'], ['-1', '−1×']], '1',
      (v) => t.setSpeed(Number(v)), 'speed');
    this.speed = speed.select;
    const mode = choice('layer', [['replace', 'punch-in'], ['additive', 'additive']], p.mode,
      (v) => p.setMode(/** @type {import('./messages.js').LayerMode} */ (v)), 'mode');
    this.mode = mode.select;
    const smooth = choice('smooth', SMOOTHING.map(([s, name]) => [String(s), name]), String(p.smoothing),
      (v) => p.setSmoothing(Number(v)), 'smoothing');
    smooth.wrap.title = 'Smooth each take before it is reduced (the raw samples are kept; the tolerance holds against the smoothed ones)';
    this.smooth = smooth.select;
    const countIn = choice('count-in', [['0', 'off'], ['1', '1 s'], ['2', '2 s'], ['4', '4 s']], '0',
      (v) => t.setCountIn(Number(v)), 'count-in');
    this.countIn = countIn.select;
    const capture = choice('capture', [['1', '1×'], ['0.5', '½×'], ['0.25', '¼×']], '1',
      (v) => t.setCaptureSpeed(Number(v)), 'capture-speed');
    capture.wrap.title = 'Perform with the transport at a fraction of real time; the motion plays at full speed';
    this.capture = capture.select;
    const loopRec = el('label', { class: 'field check', title: 'While looping, each pass is a take; the last one is kept' });
    this.loopRecord = el('input', { type: 'checkbox', 'data-testid': 'loop-record' });
    this.loopRecord.addEventListener('change', () => p.setLoopRecord(this.loopRecord.checked));
    loopRec.append(this.loopRecord, 'loop rec');
    this.undoButton = el('button', { 'data-testid': 'undo', title: 'Undo (Ctrl+Z)' }, '↶ undo');
    this.undoButton.addEventListener('click', () => studio.undo());
    this.redoButton = el('button', { 'data-testid': 'redo', title: 'Redo (Ctrl+Shift+Z)' }, '↷ redo');
    this.redoButton.addEventListener('click', () => studio.redo());
    this.status = el('span', { class: 'take-status', 'data-testid': 'take-status' });
    const signals = studio.signals;
    const group = (/** @type {HTMLElement[]} */ ...items) => { const g = el('div', { class: 'group' }); g.append(...items); return g; };
    /** Where the sounds' controls go (js/sound.js): after the playback group, in its row. */
    this.soundSlot = el('div', { id: 'sound', class: 'sound', 'data-testid': 'sound' });
    bar.append(group(this.recordButton, mode.wrap, smooth.wrap, countIn.wrap, capture.wrap, loopRec), group(fps.wrap, this.snapButton),
      group(stopButton, back, this.playButton, on, this.clockText, this.frameText, speed.wrap, this.loopButton),
      this.soundSlot, this.status, group(this.undoButton, this.redoButton));
    signals.on('history', () => this.showHistory());
    signals.on('state', () => this.showHistory());
    signals.on('record', () => this.showTransport());
    signals.on('transport', () => this.showTransport());
    signals.on('settings', () => this.showSettings());
    signals.on('lock', () => { this.showTransport(); this.showHistory(); });
    signals.on('frame', () => this.showTime());
    signals.on('projectSettings', () => this.showProjectSettings());
    signals.on('state', () => this.showProjectSettings());
    signals.on('lock', () => this.showProjectSettings());
  }

  /** The project's frame rate (as the server holds it) and whether edits snap to frames. */
  showProjectSettings() {
    const s = this.studio;
    if (![...this.fps.options].some((o) => o.value === String(s.fps))) {
      this.fps.append(el('option', { value: String(s.fps) }, String(s.fps)));     // a project's own rate, off the list
    }
    this.fps.value = String(s.fps);
    this.fps.disabled = s.readOnly;
    this.snapButton.classList.toggle('on', s.snap);
    this.snapButton.setAttribute('aria-pressed', String(s.snap));
  }

  /** Undo and redo: what they would do (the History is the server's, in memory: it reaches
   * back to when the studio started); disabled in a read-only project. */
  showHistory() {
    const { history: h, readOnly } = this.studio;
    this.undoButton.disabled = !h.can_undo || readOnly;
    this.redoButton.disabled = !h.can_redo || readOnly;
    const since = ' · undo reaches back to when the studio started';
    this.undoButton.title = readOnly ? 'Read-only project: nothing to undo'
      : h.can_undo ? `Undo ${h.undo[h.undo.length - 1]} (Ctrl+Z)${since}` : `Nothing to undo${since}`;
    this.redoButton.title = readOnly ? 'Read-only project: nothing to redo'
      : h.can_redo ? `Redo ${h.redo[h.redo.length - 1]} (Ctrl+Shift+Z)` : 'Nothing to redo';
  }

  showTransport() {
    const t = this.studio.transport;
    this.recordButton.classList.toggle('on', t.record);
    this.recordButton.setAttribute('aria-pressed', String(t.record));
    document.body.classList.toggle('recording', t.record);
    this.playButton.textContent = t.clock.playing ? '❚❚' : '▶';
    this.loopButton.classList.toggle('on', !!t.clock.loop);
    this.speed.value = String(t.playSpeed);
    const lock = this.studio.lock;
    this.recordButton.disabled = !!lock && !t.record;
    this.recordButton.title = lock ? lock.title : 'Record mode (R): every grab is a take';
  }

  showSettings() {
    const { transport: t, performer: p } = this.studio;
    this.mode.value = p.mode;
    this.smooth.value = String(p.smoothing);
    this.countIn.value = String(t.countIn);
    this.capture.value = String(t.captureSpeed);
    this.loopRecord.checked = p.loopRecord;
  }

  /** Each frame: the time, and what is being recorded. */
  showTime() {
    const { transport: t, performer: p } = this.studio;
    this.clockText.textContent = formatTime(t.time);
    this.frameText.textContent = String(t.frame);
    const counting = t.countingIn;
    const take = p.grab?.take;
    const remote = this.studio.remoteTake;
    this.status.textContent = counting > 0 ? `count-in ${counting.toFixed(1)} s`
      : take ? `● recording ${take.paths.join(', ')} · ${take.times.length} samples${tolerances(take)}${smoothed(take)}`
        : remote ? `◌ recording in another tab: ${remote.paths.join(', ')} (shown here, read-only)`
        : t.record ? 'record mode: grab something to record it' : '';
    this.status.classList.toggle('live', !!take);
    this.status.classList.toggle('remote', !take && !!remote);
  }
}

/**
 * Whether the server smooths the take, as the status shows it (" · smoothed 0.05 s").
 * @param {import('./take.js').TakeSampler} take
 */
function smoothed(take) {
  return take.smoothing > 0 ? ` · smoothed ${take.smoothing} s` : '';
}

/**
 * The tolerances a take was sent with, as the status shows them (" · tol 2 px = 0.03").
 * @param {import('./take.js').TakeSampler} take
 */
function tolerances(take) {
  return Object.entries(take.tolerance).map(([path, t]) => {
    const which = take.paths.length > 1 ? ` (${path.slice(path.indexOf('.') + 1)})` : '';
    return ` · ${formatTolerance(t, t.input, t.unit)}${which}`;
  }).join('');
}
