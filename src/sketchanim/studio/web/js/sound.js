// @ts-check
/**
 * The project's sounds in the page: the import button (a hidden file input,
 * `data-testid="import-audio"`, posting the file to `POST /api/sounds`), each sound's row
 * (its status: a missing or changed file shows a notice; its offset; beats; remove), a mute
 * toggle, the waveform as a timeline strip, and playback following the transport.
 *
 * Playback: an `HTMLAudioElement` per sound (src = its URL), following the transport every
 * frame (`syncStep`, pure): at speed s > 0 `playbackRate = s` with `preservesPitch` (the pitch
 * is kept below and above 1x), re-seeked when it drifts more than one frame of the project's
 * frame rate from `transport.time - offset`. A seek lands late by what the element takes to
 * start (some 80 ms in Chromium): each seek's landing is measured and the next one aims that
 * much ahead (`lead`, real seconds, times the speed); at a negative speed (playing backwards) and
 * outside the sound it is paused (silent); paused with the transport. Recording follows the
 * same clock, so the sound plays through the count-in and at the capture speed. Scrubbing
 * (the transport's time changing while paused) plays a grain of 60 ms at the new time through
 * WebAudio (`AudioBufferSourceNode.start(0, offset, 0.06)`), at most one per 40 ms.
 */
import { el } from './dom.js';
import { drawWaveform, peakPyramid } from './waveform.js';

/** @typedef {import('./messages.js').SoundInfo} SoundInfo */
/** @typedef {import('./waveform.js').Pyramid} Pyramid */

/** Seconds of a scrub's grain. */
export const GRAIN = 0.06;
/** Least milliseconds between two grains. */
export const GRAIN_GAP = 40;
/** The playback rates an audio element takes (Chromium's range); beyond them the sound is paused. */
export const RATES = /** @type {const} */ ([0.0625, 16]);
/** Least milliseconds between two re-seeks (a seek takes a while to land: measured again after). */
export const SEEK_GAP = 250;
/** Milliseconds after a seek before its landing is measured (the element's start-up). */
export const SETTLE = 200;
/** Real seconds: a seek landing further off than this was a stalled page (not learnt from). */
export const STALL = 0.3;
/** How many drift measurements a sound keeps (for the tests and the benchmark). */
const KEEP = 20000;

/**
 * @typedef {object} SyncInput   The transport and an audio element, at a frame.
 * @property {number} time        transport seconds
 * @property {boolean} playing    the transport runs
 * @property {number} speed       transport seconds per real second
 * @property {number} offset      where the sound starts on the timeline (s)
 * @property {number} duration    the sound's seconds
 * @property {number} position    the audio element's currentTime (s)
 * @property {boolean} paused     the audio element is paused
 * @property {number} frame       seconds of one frame (the re-seek threshold)
 */

/**
 * @typedef {object} SyncStep   What to do to the audio element.
 * @property {'pause' | 'play' | 'seek' | 'keep'} action  pause it; seek and play it; seek it (drifted); leave it
 * @property {number} at          the sound's time it should be at now (s)
 * @property {number} rate        its playback rate
 * @property {number | null} drift   position - at while it plays (s), null when it should not play
 */

/**
 * What the audio element of a sound must do to follow the transport.
 * @param {SyncInput} s
 * @returns {SyncStep}
 *
 * @example
 * syncStep({time: 2, playing: true, speed: 0.5, offset: 1, duration: 5, position: 1.2, paused: false, frame: 1 / 24});
 * // {action: 'seek', at: 1, rate: 0.5, drift: 0.2...}: more than a frame off
 */
export function syncStep(s) {
  const at = s.time - s.offset;
  const audible = s.playing && s.speed >= RATES[0] && s.speed <= RATES[1] && at >= 0 && at < s.duration;
  if (!audible) return { action: s.paused ? 'keep' : 'pause', at, rate: s.speed, drift: null };
  if (s.paused) return { action: 'play', at, rate: s.speed, drift: null };
  const drift = s.position - at;
  return { action: Math.abs(drift) > s.frame ? 'seek' : 'keep', at, rate: s.speed, drift };
}

/**
 * The mean of an AudioBuffer's channels.
 * @param {AudioBuffer} buffer
 */
function mono(buffer) {
  const out = new Float32Array(buffer.length);
  for (let c = 0; c < buffer.numberOfChannels; c++) {
    const data = buffer.getChannelData(c);
    for (let i = 0; i < out.length; i++) out[i] += data[i] / buffer.numberOfChannels;
  }
  return out;
}

/** One sound loaded in the page: its element, its decoded samples and their peaks. */
class LoadedSound {
  /**
   * @param {SoundInfo} info
   * @param {AudioBuffer} buffer
   */
  constructor(info, buffer) {
    this.info = info;
    this.buffer = buffer;
    this.pyramid = peakPyramid(mono(buffer), buffer.sampleRate);
    this.audio = new Audio(info.url);
    this.audio.preservesPitch = true;
    this.audio.preload = 'auto';
    /** performance.now() of the last re-seek */
    this.seeked = -Infinity;
    /** whether the last seek's landing is still to be measured */
    this.landing = false;
    /** real seconds a seek lands late (learnt from each landing; a seek aims this far ahead) */
    this.lead = 0;
    /** @type {number[]} drift (s) measured at each frame it played */
    this.drifts = [];
    /** @type {number[]} transport time of each measurement */
    this.times = [];
    this.seeks = 0;
  }
}

export class SoundPanel {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} container
   */
  constructor(studio, container) {
    this.studio = studio;
    this.container = container;
    /** @type {Map<string, LoadedSound>} the sounds loaded, by name */
    this.loaded = new Map();
    /** @type {Map<string, string>} the sha256 each name was loaded (or is loading) at */
    this.loading = new Map();
    this.muted = false;
    /** @type {AudioContext | null} for the scrub's grains (made at the first) */
    this.context = null;
    this.lastTime = 0;
    this.lastGrain = -Infinity;
    this.grains = 0;
    /** @type {string} the last import's outcome (the panel shows it) */
    this.message = '';
    this.build();
    studio.signals.on('sounds', () => this.update());
    studio.signals.on('state', () => this.update());
    studio.signals.on('frame', (now) => this.follow(now));
  }

  build() {
    this.input = el('input', { type: 'file', accept: 'audio/*', 'data-testid': 'import-audio', hidden: '' });
    this.input.addEventListener('change', () => {
      const file = this.input?.files?.[0];
      if (file) this.upload(file);
      if (this.input) this.input.value = '';
    });
    const pick = el('button', { type: 'button', 'data-testid': 'import-audio-button', title: 'Import a sound (WAV, OGG, FLAC, MP3) into the project' }, '♪ import');
    pick.addEventListener('click', () => this.input?.click());
    this.mute = el('button', { type: 'button', 'data-testid': 'sound-mute', title: 'Mute the sound (playback stays in sync)' }, 'mute');
    this.mute.addEventListener('click', () => this.setMuted(!this.muted));
    this.list = el('span', { class: 'sound-list', 'data-testid': 'sound-list' });
    this.status = el('span', { class: 'sound-status', 'data-testid': 'sound-status', role: 'status' });
    this.container.append(pick, this.input, this.mute, this.list, this.status);
    this.update();
  }

  /**
   * Post `file` to the server as a sound of the project; a refusal is shown here and as a notice.
   * @param {File} file
   */
  async upload(file) {
    if (this.studio.readOnly) return this.show('read-only project: sounds cannot be imported', true);
    this.show(`importing ${file.name}…`, false);
    let reply;
    try {
      reply = await fetch(`/api/sounds?name=${encodeURIComponent(file.name)}`, { method: 'POST', body: file });
    } catch (err) {
      return this.show(`${file.name}: the upload failed (${err})`, true);
    }
    if (reply.ok) return this.show(`imported ${file.name}`, false);
    let detail = `${reply.status} ${reply.statusText}`;
    try {
      detail = (await reply.json()).detail ?? detail;
    } catch { /* not JSON: the status says it */ }
    this.show(`not imported: ${detail}`, true);
  }

  /**
   * @param {string} text
   * @param {boolean} error
   */
  show(text, error) {
    this.message = text;
    if (this.status) {
      this.status.textContent = text;
      this.status.classList.toggle('error', error);
    }
    if (error) this.studio.tell('error', text, 'sound');
  }

  /** @param {boolean} muted */
  setMuted(muted) {
    this.muted = muted;
    for (const s of this.loaded.values()) s.audio.muted = muted;
    this.mute?.classList.toggle('on', muted);
    if (this.mute) this.mute.textContent = muted ? 'muted' : 'mute';
  }

  /** The studio's sounds changed: rows rebuilt, new or changed files loaded, gone ones dropped. */
  update() {
    if (!this.list) return;
    const sounds = this.studio.sounds;
    this.list.replaceChildren(...sounds.map((s) => this.row(s)));
    for (const [name, loaded] of this.loaded) {
      const now = sounds.find((s) => s.name === name);
      if (!now || now.sha256 !== loaded.info.sha256 || now.status === 'missing') this.drop(name);
      else loaded.info = now;
    }
    for (const s of sounds) {
      if (s.status !== 'ok' && this.loading.get(s.name) !== `${s.sha256}:${s.status}`) {
        this.studio.tell('warning', s.status === 'missing'
          ? `sound ${s.name}: its file ${s.path} is missing from the project's folder`
          : `sound ${s.name}: its file ${s.path} changed since it was imported (its checksum differs)`, 'sound');
      }
      if (s.status !== 'missing' && this.loading.get(s.name) !== `${s.sha256}:${s.status}`) this.load(s);
      this.loading.set(s.name, `${s.sha256}:${s.status}`);
    }
    this.studio.strips = this.studio.strips.filter((strip) => !strip.id.startsWith('sound:') || this.loaded.has(strip.id.slice(6)));
  }

  /**
   * A sound's row: name, duration, status, offset, beats, remove.
   * @param {SoundInfo} s
   */
  row(s) {
    const row = el('span', { class: `sound-row ${s.status}`, 'data-sound': s.name,
      title: `${s.path} · sha256 ${s.sha256.slice(0, 12)}…` });
    const label = el('span', { class: 'sound-name' }, `♪ ${s.name} · ${s.duration.toFixed(2)} s${s.status === 'ok' ? '' : ` · ${s.status}`}`);
    const offset = el('input', { type: 'number', step: '0.01', value: String(s.offset), class: 'sound-offset',
      'data-testid': 'sound-offset', title: 'Where the sound starts on the timeline (s)' });
    offset.addEventListener('change', () => {
      const value = Number(offset.value);
      if (Number.isFinite(value) && !this.studio.readOnly) this.studio.send({ type: 'sound.set', name: s.name, offset: value });
    });
    const beats = el('button', { type: 'button', 'data-testid': 'sound-beats', title: 'Bake the onsets into an event track (beats.cue; undoable)' }, 'beats');
    beats.addEventListener('click', () => { if (!this.studio.readOnly) this.studio.send({ type: 'sound.beats', name: s.name }); });
    const remove = el('button', { type: 'button', 'data-testid': 'sound-remove', title: 'Remove the sound from the project (its file stays)' }, '✕');
    remove.addEventListener('click', () => { if (!this.studio.readOnly) this.studio.send({ type: 'sound.remove', name: s.name }); });
    row.append(label, offset, beats, remove);
    return row;
  }

  /**
   * Fetch, decode and show sound `s` (its waveform as a timeline strip).
   * @param {SoundInfo} s
   */
  async load(s) {
    try {
      const reply = await fetch(s.url);
      if (!reply.ok) throw new Error(`${reply.status} ${reply.statusText}`);
      const data = await reply.arrayBuffer();
      const buffer = await this.audioContext().decodeAudioData(data);
      const now = this.studio.sounds.find((x) => x.name === s.name);
      if (!now || now.sha256 !== s.sha256) return;                 // replaced or removed meanwhile
      this.drop(s.name);
      const loaded = new LoadedSound(now, buffer);
      loaded.audio.muted = this.muted;
      this.loaded.set(s.name, loaded);
      this.studio.strips = [...this.studio.strips.filter((strip) => strip.id !== `sound:${s.name}`), {
        id: `sound:${s.name}`, label: s.name, height: 28,
        draw: (g, area, t0, t1) => drawWaveform(g, area, loaded.pyramid, t0, t1, loaded.info.offset, '#57c7a4'),
      }];
    } catch (err) {
      this.show(`sound ${s.name}: the browser cannot play it (${err})`, true);
    }
  }

  /** @param {string} name */
  drop(name) {
    const loaded = this.loaded.get(name);
    if (!loaded) return;
    loaded.audio.pause();
    loaded.audio.removeAttribute('src');
    this.loaded.delete(name);
    this.studio.strips = this.studio.strips.filter((strip) => strip.id !== `sound:${name}`);
  }

  audioContext() {
    this.context ??= new AudioContext();
    return this.context;
  }

  /**
   * Every frame: each sound follows the transport; a paused transport's new time plays a grain.
   * @param {number} now performance.now()
   */
  follow(now) {
    const t = this.studio.transport;
    const frame = 1 / this.studio.fps;
    for (const s of this.loaded.values()) {
      const step = syncStep({ time: t.time, playing: t.clock.playing, speed: t.clock.speed, offset: s.info.offset,
        duration: s.buffer.duration, position: s.audio.currentTime, paused: s.audio.paused, frame });
      if (step.drift !== null && !s.audio.seeking && s.landing && now - s.seeked >= SETTLE) {
        // land on time next time (a landing off by more than STALL is a stalled page, not the element: not learnt)
        if (Math.abs(step.drift / step.rate) < STALL) s.lead = Math.min(STALL, Math.max(0, s.lead - step.drift / step.rate));
        s.landing = false;
      }
      if (step.drift !== null && !s.audio.seeking) {
        s.drifts.push(step.drift);
        s.times.push(t.time);
        if (s.drifts.length > KEEP) { s.drifts.shift(); s.times.shift(); }
      }
      if (s.audio.playbackRate !== step.rate && step.rate >= RATES[0] && step.rate <= RATES[1]) s.audio.playbackRate = step.rate;
      if (step.action === 'pause') s.audio.pause();
      else if (step.action === 'play') {
        this.seek(s, step, now);
        s.audio.play().catch((err) => this.show(`sound ${s.info.name}: the browser will not play it (${err.message})`, true));
      } else if (step.action === 'seek' && !s.audio.seeking && now - s.seeked > SEEK_GAP) {
        this.seek(s, step, now);
        s.seeks += 1;
      }
    }
    if (!t.clock.playing && t.time !== this.lastTime) this.grain(now, t.time);
    this.lastTime = t.time;
  }

  /**
   * Seek sound `s` to where the transport will be when the seek lands (`lead` ahead).
   * @param {LoadedSound} s
   * @param {SyncStep} step
   * @param {number} now performance.now()
   */
  seek(s, step, now) {
    s.audio.currentTime = Math.min(Math.max(0, step.at + s.lead * step.rate), s.buffer.duration);
    s.seeked = now;
    s.landing = true;
  }

  /**
   * A scrub's grain: GRAIN seconds of each sound at the transport's `time`.
   * @param {number} now performance.now()
   * @param {number} time
   */
  grain(now, time) {
    if (this.muted || now - this.lastGrain < GRAIN_GAP || !this.loaded.size) return;
    this.lastGrain = now;
    const context = this.audioContext();
    for (const s of this.loaded.values()) {
      const at = time - s.info.offset;
      if (at < 0 || at >= s.buffer.duration) continue;
      const source = context.createBufferSource();
      source.buffer = s.buffer;
      source.connect(context.destination);
      source.start(0, at, GRAIN);
      this.grains += 1;
    }
  }

  /** What the tests and the benchmark read: each sound's drift measurements and state. */
  report() {
    return [...this.loaded.values()].map((s) => ({ name: s.info.name, drifts: s.drifts, times: s.times, seeks: s.seeks, lead: s.lead,
      rate: s.audio.playbackRate, paused: s.audio.paused, muted: s.audio.muted, position: s.audio.currentTime,
      preservesPitch: s.audio.preservesPitch, peaks: s.pyramid.levels.length }));
  }
}
