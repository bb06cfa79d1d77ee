// @ts-check
/**
 * The studio page: connects to the server, builds the panels and runs the frame loop
 * (every animation frame: the transport from performance.now(), playback of every track,
 * the performer's samples, drawing).
 */
import { Connection } from './Connection.js';
import { CurveView } from './curves.js';
import { Inspector } from './inspector.js';
import { Outliner } from './outliner.js';
import { Studio } from './Studio.js';
import { Timeline } from './timeline.js';
import { Viewport } from './viewport.js';

const $ = (/** @type {string} */ id) => /** @type {HTMLElement} */ (document.getElementById(id));

const connection = new Connection(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
const studio = new Studio(connection);
const viewport = new Viewport(studio, $('viewport'));
new Outliner(studio, $('outliner'));
new Inspector(studio, $('inspector'));
new Timeline(studio, $('transport'), /** @type {HTMLCanvasElement} */ ($('timeline')));
new CurveView(studio, $('curves'));

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
window.addEventListener('blur', () => { if (studio.grab && !viewport.drag && !viewport.pad) studio.release(); });

const status = $('status');
const showStatus = () => {
  status.textContent = !connection.connected ? 'reconnecting…' : studio.ready ? 'ready' : 'warming up…';
  status.className = connection.connected && studio.ready ? 'ok' : 'wait';
};
connection.on('open', showStatus);
connection.on('close', showStatus);
studio.on('ready', showStatus);
studio.on('state', showStatus);
let errorTimer = 0;
studio.on('error', (m) => {
  const box = $('error');
  box.textContent = `${m.code}: ${m.message}`;
  box.hidden = false;
  clearTimeout(errorTimer);
  errorTimer = window.setTimeout(() => { box.hidden = true; }, 6000);
});
connection.on('state', (m) => { $('project').textContent = m.project; });

window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
  const key = e.key.toLowerCase();
  if ((e.ctrlKey || e.metaKey) && key === 'z') {
    e.preventDefault();
    if (e.shiftKey) studio.redo(); else studio.undo();
  } else if ((e.ctrlKey || e.metaKey) && key === 'y') {
    e.preventDefault();
    studio.redo();
  } else if (e.ctrlKey || e.metaKey || e.altKey) {
    return;
  } else if (key === 'r') {
    studio.setRecord(!studio.record);
  } else if (key === ' ') {
    e.preventDefault();
    if (studio.clock.playing) studio.pause(); else studio.play();
  } else if (key === 'enter') {
    studio.stop();
  } else if (key === 'l') {
    $('transport').querySelector('[data-testid="loop"]')?.dispatchEvent(new MouseEvent('click'));
  } else if (key === 'c') {
    viewport.previewCamera = !viewport.previewCamera;
  } else if (key === 'escape') {
    studio.select(null);
  }
});

Object.assign(window, { studio, viewport, studioStats: stats });
