// @ts-check
/**
 * The studio page: connects to the server, builds the panels, binds the keys and runs the
 * frame loop (every animation frame: the studio's step — the transport from
 * performance.now(), playback of every track, the performer's samples — then drawing).
 */
import { Connection } from './Connection.js';
import { ClipImport } from './clipimport.js';
import { CueFlash } from './cueflash.js';
import { CurveEditor } from './curveeditor.js';
import { ExportDialog } from './exportdialog.js';
import { FilesDialog } from './filesdialog.js';
import { Header } from './header.js';
import { Help } from './help.js';
import { Inspector } from './inspector.js';
import { Layers } from './layers.js';
import { LockBanner } from './banner.js';
import { bindKeyboard, studioActions } from './keyboard.js';
import { Notices } from './notices.js';
import { Outliner } from './outliner.js';
import { SaveStatus } from './savestatus.js';
import { SoundPanel } from './sound.js';
import { Studio } from './Studio.js';
import { Timeline } from './timeline.js';
import { TransportBar } from './transportbar.js';
import { Viewport } from './viewport.js';

const $ = (/** @type {string} */ id) => /** @type {HTMLElement} */ (document.getElementById(id));

const connection = new Connection(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
const studio = new Studio(connection);
new Header(studio, $('project'), $('status'));
new SaveStatus(studio, $('save-status'));
const viewport = new Viewport(studio, $('viewport'));
new Notices(studio, $('notices'));
new LockBanner(studio, $('viewport'));
const cueFlash = new CueFlash(studio, $('viewport'));
new Outliner(studio, $('outliner'), viewport);
new ClipImport(studio, $('outliner'));
new Inspector(studio, $('inspector'));
new Layers(studio, $('inspector'));
const transportBar = new TransportBar(studio, $('transport'));
const timeline = new Timeline(studio, /** @type {HTMLCanvasElement} */ ($('timeline')));
const sounds = new SoundPanel(studio, transportBar.soundSlot);
const curveEditor = new CurveEditor(studio, $('curves'));
const header = /** @type {HTMLElement} */ (document.querySelector('header.top'));
new FilesDialog(studio, header, window);            // the dialogs before the keys: their Escape goes first
new ExportDialog(header, window);
new Help(studio, header, window);   // before the keys: its Escape goes first
bindKeyboard(window, studioActions(studio, viewport));

/** Per-frame timings (ms) of the last frames, for benchmarks: playback (evaluate every track,
 * write the values), the whole frame's script (playback, sampling, panels, render calls),
 * the render calls alone, the interval between frames, and each frame's time (performance.now()). */
const stats = { play: /** @type {number[]} */ ([]), script: /** @type {number[]} */ ([]), render: /** @type {number[]} */ ([]),
  interval: /** @type {number[]} */ ([]), stamps: /** @type {number[]} */ ([]) };
const KEEP = 600;
let previous = 0;

/** @param {number[]} list @param {number} value */
function keep(list, value) {
  list.push(value);
  if (list.length > KEEP) list.shift();
}

/** Every animation frame, stamped with performance.now() when the frame's script runs (the
 * time the sampled values are true; the frame's own timestamp can be older when the main thread
 * was busy). */
function frame() {
  const now = performance.now();
  const start = now;
  studio.frame(now);
  const before = performance.now();
  viewport.render();
  keep(stats.play, studio.playMs);
  keep(stats.render, performance.now() - before);
  keep(stats.script, performance.now() - start);
  if (previous) keep(stats.interval, now - previous);
  keep(stats.stamps, now);
  previous = now;
  if (studio.loaded && studio.ready && viewport.drawn > 0 && document.body.dataset.ready !== 'true') {
    document.body.dataset.ready = 'true';
  }
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);

// A tab in the background gets no frames: a take ends at its last sample.
document.addEventListener('visibilitychange', () => { if (document.hidden) studio.hidden(); });
window.addEventListener('blur', () => {
  if (studio.performer.grab && !viewport.drag && !viewport.pad) studio.performer.release();
});

Object.assign(window, { studio, viewport, curveEditor, cueFlash, timeline, sounds, studioStats: stats });
