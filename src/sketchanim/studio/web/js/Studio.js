// @ts-check
/**
 * The page's studio: the client state, its signals (signals.js) and the operations on it.
 * The server is the single source of truth for the scene, the tracks and the history; the
 * studio mirrors them from the server's messages (messages.js), plays the tracks itself every
 * frame, and sends edits and takes. Its parts: the transport (Transport.js) and the performer
 * (Performer.js). Panels read the state, listen to the signals and change the state only
 * through the studio's methods (and its parts').
 */
import { evaluate, pack, stepValue, valueOf } from './evaluate.js';
import { cuesOf, passed } from './events.js';
import { Performer } from './Performer.js';
import { Signals } from './signals.js';
import { Transport } from './Transport.js';

/** @typedef {import('./messages.js').AttrType} AttrType */
/** @typedef {import('./messages.js').SceneObject} SceneObject */
/** @typedef {import('./messages.js').CurveTrack} CurveTrack */
/** @typedef {import('./messages.js').StepsTrack} StepsTrack */
/** @typedef {import('./messages.js').Track} Track */
/** @typedef {import('./messages.js').ServerMessage} ServerMessage */
/** @typedef {import('./messages.js').PageMessage} PageMessage */
/** @typedef {import('./messages.js').TakePiece} TakePiece */
/** @typedef {import('./take.js').TakeSampler} TakeSampler */
/**
 * A strip the timeline draws above its lanes, on the same time axis (the sound's waveform):
 * `draw` paints `area` (canvas pixels) for the times `t0`..`t1` across its width.
 * @typedef {{ id: string, label: string, height: number,
 *   draw: (ctx: CanvasRenderingContext2D, area: {x: number, y: number, width: number, height: number}, t0: number, t1: number) => void }} TimelineStrip
 */
/**
 * @typedef {object} TimeRange   The range selected in the timeline: times `t0` < `t1` over the lanes of `paths`.
 * @property {string[]} paths
 * @property {number} t0
 * @property {number} t1
 */
/** @typedef {Pick<import('./Connection.js').Connection, 'connect' | 'send' | 'connected'>} Link  what the studio needs of a connection */
/** @typedef {import('./messages.js').Saved} Saved */
/**
 * @typedef {object} Lock   Why this page cannot record now (the banner over the view says it).
 * @property {'read-only' | 'remote'} kind  a read-only project (no edits either), or another page's take
 * @property {string} text    the banner's
 * @property {string} title   the REC button's tooltip
 */
/**
 * @typedef {object} TakeLog   A take the page sent, for the curve view, tests and benchmarks.
 * @property {string} id
 * @property {TakeSampler} sampler
 * @property {number} released   performance.now() of the release
 * @property {number | null} final performance.now() when the final curve arrived
 * @property {string | null} label History's label (null: refused or cancelled)
 * @property {number | null} serverMs the server's time from the release's message to the final curve
 */

/**
 * @typedef {object} PointSelection   A selected control point (`index` into the curve's `coef`) or key
 *   (`index` into its `knots`: a key sits at a distinct knot) of the curve of `path`.
 * @property {string} path
 * @property {'point' | 'key'} kind
 * @property {number} index
 */

/**
 * The selection after the scene's objects went from `before` to `after`: the same object; the
 * one it became when it alone went and one object came (a rename, its undo or redo); else none.
 * @param {string | null} selected
 * @param {string[]} before
 * @param {string[]} after
 * @returns {string | null}
 *
 * @example
 * renamedSelection('box', ['box', 'ball'], ['crate', 'ball']);    // 'crate'
 */
export function renamedSelection(selected, before, after) {
  if (selected === null || after.includes(selected)) return selected;
  const gone = before.filter((n) => !after.includes(n));
  const came = after.filter((n) => !before.includes(n));
  return gone.length === 1 && gone[0] === selected && came.length === 1 ? came[0] : null;
}

/**
 * Whether two knot vectors are the same (then a curve's point and key indices still name the same points).
 * @param {number[]} a
 * @param {number[]} b
 */
function sameKnots(a, b) {
  return a.length === b.length && a.every((t, i) => t === b[i]);
}

/** The close code of a socket the server closed for a frame over its transport limit (16 MiB). */
export const TOO_BIG = 1009;

export class Studio {
  /** @param {Link} connection */
  constructor(connection) {
    this.connection = connection;
    this.signals = new Signals();
    /** The project file's name. */
    this.project = '';
    /** @type {SceneObject[]} */
    this.objects = [];
    /** @type {Map<string, AttrType>} */
    this.types = new Map();
    /** @type {Map<string, any>} the scene's current values, by path */
    this.values = new Map();
    /** @type {Map<string, any>} the scene's values as the server holds them (no track playing, no hold) */
    this.served = new Map();
    /** @type {import('./messages.js').TakeInProgress | null} the take another page is recording (this one cannot) */
    this.remoteTake = null;
    /** The project cannot be written: it plays and exports; this page sends no edits. */
    this.readOnly = false;
    /** @type {Saved} whether everything is on disk (the server keeps what is not, and retries) */
    this.saved = { type: 'saved', ok: true, error: null, since: null };
    /** @type {Map<string, Track>} */
    this.tracks = new Map();
    this.packed = pack([]);
    /** @type {StepsTrack[]} the discrete tracks that hold values (bools, enums) */
    this.steps = [];
    /** @type {import('./events.js').Cues} the event tracks' events, merged: they fire as playback passes them */
    this.cues = cuesOf([]);
    /** Transport seconds up to which events have fired (where the playhead was at the last frame, or was sought to). */
    this.firedTo = 0;
    /** @type {[number, number]} */
    this.span = [0, 0];
    /** @type {Map<string, import('./resolution.js').ToleranceSetting>} the animator's take tolerances, by path (the project keeps them) */
    this.tolerances = new Map();
    /** @type {import('./messages.js').HistoryLabels} */
    this.history = { undo: [], redo: [], can_undo: false, can_redo: false };
    this.ready = false;
    this.loaded = false;
    /** @type {string | null} the selected object (the viewport, the outliner, the curve editor and the motion paths share it) */
    this.selected = null;
    /** @type {PointSelection[]} the selected control points and keys (shared by the curve editor and the motion paths) */
    this.points = [];
    /** The project's frame rate: the transport counts frames in it, edits snap to its frames when `snap` is on. */
    this.fps = 24;
    /** Whether edits in time (knots inserted, the playhead dragged) snap to frames. */
    this.snap = false;
    /** The attribute the curve view shows. */
    this.attribute = 'position';
    /** @type {TakeLog[]} */
    this.takes = [];
    /** @type {Map<string, TakePiece[]>} pieces of the growing curve of the take in progress, by path */
    this.pieces = new Map();
    /** @type {((path: string, value: any) => void)[]} what draws values (the viewport) */
    this.sinks = [];
    /** @type {import('./messages.js').ErrorReply[]} the server's error replies, oldest first */
    this.errors = [];
    /** @type {import('./messages.js').Notice[]} the server's notices, oldest first */
    this.notices = [];
    /** Milliseconds the last frame's playback took (evaluate and write the values). */
    this.playMs = 0;
    /** @type {TimelineStrip[]} strips the timeline draws above its lanes, in order */
    this.strips = [];
    /** @type {TimeRange | null} the range selected in the timeline (Delete deletes it) */
    this.timeRange = null;
    /** @type {import('./messages.js').SoundInfo[]} the project's sounds (sound.js plays them) */
    this.sounds = [];
    this.transport = new Transport(this);
    this.performer = new Performer(this);
    connection.connect((m) => this.receive(m), (open, code) => this.connectionChanged(open, code));
  }

  /**
   * The socket opened, or closed (with its close code): reconnecting is the Connection's
   * job. A take this page was recording ends with the socket (the server keeps it).
   * @param {boolean} open
   * @param {number} [code]
   */
  connectionChanged(open, code) {
    if (!open && this.performer.grab?.take) this.performer.ended('gone');    // the server ends it as the socket goes
    if (code === TOO_BIG) this.tell('error', 'a message was too large for the connection (over 16 MiB): it was reset and reconnects', 'connection');
    this.signals.emit('connection', open);
  }

  /**
   * Show the animator a notice: the server's, or one the page itself found.
   * @param {import('./messages.js').NoticeLevel} level
   * @param {string} text
   * @param {string} source
   */
  tell(level, text, source) {
    /** @type {import('./messages.js').Notice} */
    const notice = { type: 'notice', level, text, source };
    this.notices.push(notice);
    this.signals.emit('notice', notice);
  }

  /**
   * Why this page cannot record now (and, for a read-only project, edit), or null.
   * @returns {Lock | null}
   */
  get lock() {
    if (this.readOnly) {
      return { kind: 'read-only', text: 'read-only project: plays and exports; edits are refused',
        title: 'Read-only project: takes cannot be recorded' };
    }
    if (this.remoteTake) {
      return { kind: 'remote', text: '● recording in another tab · shown here read-only',
        title: 'Another tab is recording a take: this one records once it ends' };
    }
    return null;
  }

  /** @param {PageMessage} message */
  send(message) {
    this.connection.send(message);
  }

  // -- the server's messages --------------------------------------------------------------

  /**
   * One message from the server.
   * @param {ServerMessage} m
   */
  receive(m) {
    switch (m.type) {
      case 'state': this.loadState(m); break;
      case 'tracks':
        for (const track of m.changed) {
          const before = this.tracks.get(track.path);
          if (before?.kind !== 'curve' || track.kind !== 'curve' || !sameKnots(before.knots, track.knots)) {
            this.points = this.points.filter((q) => q.path !== track.path);     // its indices name other points now
          }
          this.tracks.set(track.path, track);
        }
        for (const path of m.removed) this.tracks.delete(path);
        this.points = this.points.filter((q) => this.tracks.has(q.path));
        this.span = m.span;
        this.repack();
        this.signals.emit('tracks');
        break;
      case 'values': this.receiveValues(m.values); break;
      case 'preview': this.receiveValues({ [m.path]: m.value }); break;
      case 'history':
        this.history = m;
        this.signals.emit('history');
        break;
      case 'take.piece': {
        const list = this.pieces.get(m.path) ?? [];
        list.push(m);
        this.pieces.set(m.path, list);
        if (this.remoteTake?.take === m.take) this.showPiece(m);
        break;
      }
      case 'take.running': this.remoteBegan(m); break;
      case 'take.ended': {
        if (this.remoteTake?.take === m.take) this.remoteEnded();
        if (this.performer.grab?.take?.id === m.take) this.performer.ended(m.reason ?? 'end');
        const log = this.takes.find((l) => l.id === m.take);
        if (log) {
          log.final = performance.now();
          log.label = m.label;
          log.serverMs = m.ms;
        }
        if (!this.performer.grab?.take) this.pieces.clear();
        break;
      }
      case 'transport': this.transport.receive(m); break;
      case 'tolerances':
        this.tolerances = new Map(Object.entries(m.tolerances));
        this.signals.emit('tolerances');
        break;
      case 'ready':
        this.ready = true;
        this.signals.emit('ready');
        break;
      case 'error':
        if (m.ref === 'take.begin') this.performer.refused();
        this.errors.push(m);
        this.signals.emit('error', m);
        break;
      case 'notice': this.tell(m.level, m.text, m.source); break;
      case 'saved': this.keepSaved(m); break;
      case 'settings': this.keepSettings(m); break;
      case 'reduced': this.signals.emit('reduced', m); break;
      case 'samples': this.signals.emit('samples', m); break;
      case 'track.piece': this.signals.emit('piece', m); break;
      case 'sounds': this.keepSounds(m.sounds); break;
      case 'beats': this.signals.emit('beats', m); break;
      case 'take.started': case 'pong': case 'ack': case 'exported': break;    // nothing to show
      default: {
        /** @type {never} */
        const unknown = m;          // tsc: every server message is handled above
        console.warn('unknown message from the server', unknown);
      }
    }
  }

  /** @param {import('./messages.js').StateSnapshot} m */
  loadState(m) {
    const before = this.objects.map((o) => o.name);
    this.project = m.project;
    this.objects = m.objects;
    this.types.clear();
    this.values.clear();
    this.served.clear();
    for (const o of this.objects) {
      for (const a of o.attributes) {
        this.types.set(`${o.name}.${a.name}`, a.type);
        this.values.set(`${o.name}.${a.name}`, a.value);
        this.served.set(`${o.name}.${a.name}`, a.value);
      }
    }
    const own = this.performer.grab?.take?.id;
    this.remoteTake = m.take && m.take.take !== own && !this.takes.some((l) => l.id === m.take?.take) ? m.take : null;
    this.readOnly = !!m.read_only;
    if (m.saved) this.keepSaved(m.saved);
    if (m.settings) this.keepSettings(m.settings);
    if (m.sounds) this.sounds = m.sounds;
    this.tracks = new Map(m.tracks.map((t) => [t.path, t]));
    this.span = m.span;
    this.tolerances = new Map(Object.entries(m.tolerances));
    this.history = m.history;
    this.ready = this.ready || m.ready;
    if (!this.loaded) this.transport.receive(m.transport);
    this.selected = renamedSelection(this.selected, before, this.objects.map((o) => o.name));
    this.points = this.points.filter((q) => this.tracks.get(q.path)?.kind === 'curve');
    this.repack();
    this.loaded = true;
    this.signals.emit('state');
    for (const [path, value] of this.values) this.draw(path, value);
    if (this.ready) this.signals.emit('ready');
    this.signals.emit('lock');
  }

  /**
   * Whether everything is on disk, as the server says (in `state` and `saved`; the
   * server's notices say when saves fail and when they work again).
   * @param {Saved} m
   */
  keepSaved(m) {
    this.saved = m;
    this.signals.emit('saved', m);
  }

  /**
   * The project's settings, as the server says (in `state` and `settings`).
   * @param {import('./messages.js').SettingsInfo} m
   */
  keepSettings(m) {
    this.fps = m.fps;
    this.signals.emit('projectSettings');
  }

  /**
   * The span playback covers: the tracks' and the sounds' (each from its offset for its
   * duration); the transport stops at its end, the timeline shows it.
   * @returns {[number, number]}
   */
  get playSpan() {
    const sounds = this.sounds.filter((s) => s.status !== 'missing');
    if (!sounds.length) return this.span;
    const empty = this.span[1] <= this.span[0];
    return [Math.min(empty ? Infinity : this.span[0], ...sounds.map((s) => s.offset)),
      Math.max(empty ? -Infinity : this.span[1], ...sounds.map((s) => s.offset + s.duration))];
  }

  /**
   * The project's sounds, as the server says (in `state` and `sounds`).
   * @param {import('./messages.js').SoundInfo[]} sounds
   */
  keepSounds(sounds) {
    this.sounds = sounds;
    this.signals.emit('sounds');
  }

  /**
   * Another page began a take: this page shows it as its pieces come (read-only) and
   * records nothing until it ends.
   * @param {import('./messages.js').TakeInProgress} take
   */
  remoteBegan(take) {
    this.remoteTake = take;
    if (!this.performer.grab?.take) this.pieces.clear();
    this.signals.emit('lock');
  }

  /** The other page's take ended: its track comes in a `tracks` message. */
  remoteEnded() {
    const paths = this.remoteTake?.paths ?? [];
    this.remoteTake = null;
    this.revert(paths);
    this.signals.emit('lock');
  }

  /**
   * The latest value of another page's take: where its newest piece ends.
   * @param {TakePiece} piece
   */
  showPiece(piece) {
    if (this.performer.holds(piece.path)) return;
    const last = piece.coef[piece.coef.length - 1];
    const norm = piece.rotation ? Math.hypot(...last) : 1;
    const value = last.map((x) => x / norm);
    this.values.set(piece.path, value);
    this.draw(piece.path, value);
  }

  /**
   * Show the server's values of `paths` again (held or not): a track's at the transport's
   * time, else the scene's. What a hold that stored nothing leaves.
   * @param {string[]} paths
   */
  revert(paths) {
    for (const path of paths) {
      const value = this.served.get(path);
      if (value === undefined) continue;
      this.values.set(path, value);
      this.draw(path, value);
    }
    this.writeTracks(this.transport.time, paths);
    this.signals.emit('values', paths);
  }

  /** @param {Record<string, any>} values */
  receiveValues(values) {
    for (const [path, value] of Object.entries(values)) {
      this.served.set(path, value);
      if (this.performer.holds(path)) continue;                 // the performer holds it
      this.values.set(path, value);
      this.draw(path, value);
    }
    this.signals.emit('values', Object.keys(values));
  }

  repack() {
    const curves = [...this.tracks.values()].filter((t) => t.kind === 'curve');
    this.packed = pack(curves);
    const steps = /** @type {StepsTrack[]} */ ([...this.tracks.values()].filter((t) => t.kind === 'steps'));
    this.steps = steps.filter((t) => this.types.get(t.path)?.name !== 'event');
    this.cues = cuesOf(steps.filter((t) => this.types.get(t.path)?.name === 'event'));
    this.writeTracks(this.transport.time);
  }

  // -- values ---------------------------------------------------------------------------

  /**
   * Draw values with `sink` from now on (the viewport).
   * @param {(path: string, value: any) => void} sink
   */
  addSink(sink) {
    this.sinks.push(sink);
  }

  /**
   * Show a value (the viewport and whoever listens draw it).
   * @param {string} path
   * @param {any} value
   */
  draw(path, value) {
    for (const sink of this.sinks) sink(path, value);
  }

  /**
   * Change a value in the page only (a drag in progress, playback).
   * @param {string} path
   * @param {any} value
   */
  setLocal(path, value) {
    this.values.set(path, value);
    this.performer.moved(path);
    this.draw(path, value);
  }

  /**
   * An undoable edit of one value (sent to the server; one History entry, merged with
   * the previous one when `merge` is the same key).
   * @param {string} path
   * @param {any} value
   * @param {string} label
   * @param {string | null} [merge]
   */
  set(path, value, label, merge = null) {
    if (this.readOnly) {
      this.revert([path]);                                     // the banner says why; nothing is sent
      return;
    }
    this.setLocal(path, value);
    this.send({ type: 'set', path, value, label, merge });
  }

  /**
   * Key the discrete attribute `path` to `value` (an event: its label or null) at the transport's
   * time at `stamp` (the input event's timeStamp), snapped to a frame when snap is on: one
   * History entry. What toggling, picking a value or marking a cue does while the transport
   * plays, or once the attribute has a track.
   * @param {string} path
   * @param {boolean | string | null} value
   * @param {number} stamp performance.now() of the input event
   */
  key(path, value, stamp) {
    if (this.readOnly) {
      this.revert([path]);
      return;
    }
    if (this.types.get(path)?.name !== 'event') this.setLocal(path, value);
    this.send({ type: 'track.key', path, time: this.snapped(this.transport.timeAt(stamp)), value });
  }

  /**
   * Mark a cue (an event) on the selected object at the transport's time at `stamp`.
   * @param {number} stamp performance.now() of the key press
   */
  cue(stamp) {
    if (this.selected) this.key(`${this.selected}.cue`, null, stamp);
    else this.tell('warning', 'select an object to mark a cue on (M marks one at the playhead)', 'cue');
  }

  /**
   * Set the tolerance takes of `path` are recorded within (null: what the input resolves,
   * `DEFAULT_STEPS` of it); the project keeps it (not a History step).
   * @param {string} path
   * @param {import('./resolution.js').ToleranceSetting | null} setting
   */
  setTolerance(path, setting) {
    if (!this.readOnly) this.send({ type: 'tolerance.set', path, amount: setting ? setting.amount : null, unit: setting ? setting.unit : 'px' });
  }

  /** @param {string} name */
  objectOf(name) {
    return this.objects.find((o) => o.name === name) ?? null;
  }

  /** @param {string | null} name */
  select(name) {
    if (name !== this.selected) this.selectPoints([]);
    this.selected = name;
    const obj = name ? this.objectOf(name) : null;
    if (obj && (obj.kind === 'chain' || obj.kind === 'walker') && this.attribute === 'position') this.attribute = 'goal';   // what a rig is performed by
    if (obj && !obj.attributes.some((a) => a.name === this.attribute && a.type.continuous)) {
      this.attribute = obj.attributes.find((a) => a.type.continuous)?.name ?? 'position';
    }
    this.signals.emit('selection', name);
  }

  /**
   * Select control points and keys (replacing the selection; [] clears it).
   * @param {PointSelection[]} points
   */
  selectPoints(points) {
    this.points = points;
    this.signals.emit('points', points);
  }

  /**
   * Delete what is selected: the timeline's range (the timeline hears the `command` signal), the selected keys and points (their knots removed, by the curve
   * editor, which hears the `command` signal), else the selected object (undoable).
   */
  deleteSelection() {
    if (this.timeRange) this.signals.emit('command', 'delete-range');
    else if (this.points.length) this.signals.emit('command', 'delete-points');
    else if (this.selected) this.removeObject(this.selected);
  }

  /** Snap edits in time to frames on / off (the `projectSettings` signal tells the panels). */
  toggleSnap() {
    this.snap = !this.snap;
    this.signals.emit('projectSettings');
  }

  /**
   * A time snapped to the project's frames when `snap` is on (else as it is).
   * @param {number} t
   */
  snapped(t) {
    return this.snap ? Math.round(t * this.fps) / this.fps : t;
  }

  /**
   * Show one attribute of the selected object in the curve view.
   * @param {string} attribute
   */
  showAttribute(attribute) {
    this.attribute = attribute;
    this.signals.emit('attribute', attribute);
  }

  /**
   * The first name `stem1`, `stem2`, ... no object has.
   * @param {string} stem
   */
  freeName(stem) {
    const names = new Set(this.objects.map((o) => o.name));
    let i = 1;
    while (names.has(`${stem}${i}`)) i += 1;
    return `${stem}${i}`;
  }

  /**
   * Add an object (undoable), named `object1`, `object2`, ... (the first name free), at
   * `position` if given.
   * @param {import('./messages.js').ObjectKind} [kind]
   * @param {[number, number, number] | null} [position]
   */
  addObject(kind = 'object', position = null) {
    if (this.readOnly) return;
    this.send(position ? { type: 'object.add', name: this.freeName(kind), kind, position }
      : { type: 'object.add', name: this.freeName(kind), kind });
  }

  /** @param {string} name remove the object and its tracks (undoable) */
  removeObject(name) {
    if (!this.readOnly) this.send({ type: 'object.remove', name });
  }

  /** @param {string} name @param {string} to rename the object, its tracks with it (undoable) */
  renameObject(name, to) {
    if (!this.readOnly) this.send({ type: 'object.rename', name, to });
  }

  /** @param {string} name copy the object and its tracks under a free name (undoable) */
  duplicateObject(name) {
    if (!this.readOnly) this.send({ type: 'object.duplicate', name, to: this.freeName(name.replace(/\d+$/, '') || name) });
  }

  // -- curve edits (each one History step; previews stay in the page) ----------------------

  /**
   * Move control points (one History step, whatever the number of points and curves).
   * @param {{path: string, index: number, value: number[]}[]} edits
   * @param {string | null} [label]
   */
  movePoints(edits, label = null) {
    if (!this.readOnly && edits.length) this.send({ type: 'curve.points', edits, label });
  }

  /**
   * Set a curve's value and / or slope at `time` (a key or its handle dragged; one History step).
   * @param {string} path
   * @param {number} time
   * @param {number[] | null} value
   * @param {number[] | null} slope
   */
  moveKey(path, time, value, slope) {
    if (!this.readOnly) this.send({ type: 'curve.key', path, time, value, slope });
  }

  /**
   * Insert knots at times `insert` and remove interior knots `remove` (indices into `knots`), one History step.
   * @param {string} path
   * @param {number[]} insert
   * @param {number[]} remove
   */
  editKnots(path, insert, remove) {
    if (!this.readOnly) this.send({ type: 'curve.knots', path, insert, remove });
  }

  /**
   * Re-reduce tracks from their raw takes within `tol` (the attribute's units): `preview`
   * asks only for the would-be curves (the `reduced` signal brings them), else one History step.
   * @param {string[]} paths
   * @param {number} tol
   * @param {boolean} preview
   */
  reduceTracks(paths, tol, preview) {
    if (!this.readOnly || preview) this.send({ type: 'track.reduce', paths, tol, preview });
  }

  /** @param {string} path ask for the samples the curve keeps (the `samples` signal brings them) */
  askSamples(path) {
    this.send({ type: 'track.samples', path });
  }

  /**
   * Change a take of a track (rename, mute, solo, delete, move, keep a loop pass): the
   * track is composed again from its takes (one History step).
   * @param {string} path
   * @param {number} take its index in the track's takes
   * @param {import('./messages.js').TakeOp} op
   * @param {{name?: string, to?: number}} [args]
   */
  editTake(path, take, op, args = {}) {
    if (!this.readOnly) this.send({ type: 'take.edit', path, take, op, name: args.name ?? null, to: args.to ?? null });
  }

  /** @param {number} fps the project's frame rate (a project setting, not History) */
  setFps(fps) {
    if (!this.readOnly) this.send({ type: 'settings', fps });
  }

  /** Undo the last History step (the server's History reaches back to when the studio started). */
  undo() {
    if (!this.performer.grab && !this.readOnly) this.send({ type: 'undo' });
  }

  redo() {
    if (!this.performer.grab && !this.readOnly) this.send({ type: 'redo' });
  }

  // -- the timeline: retiming and the clipboard (each edit one History step) -------------

  /** @param {TimeRange | null} range select a range in the timeline (null: none) */
  selectRange(range) {
    this.timeRange = range;
    this.signals.emit('timeRange', range);
  }

  /**
   * Send a drag's move or stretch in time (a take's `take.edit` shift / scale, tracks' `track.retime`).
   * @param {PageMessage} message
   */
  editInTime(message) {
    if (!this.readOnly) this.send(message);
  }

  /**
   * Delete the motion of tracks over (t0, t1) (a curve bridged across).
   * @param {string[]} paths
   * @param {number} t0
   * @param {number} t1
   */
  cutRange(paths, t0, t1) {
    if (!this.readOnly) this.send({ type: 'track.cut', paths, t0, t1 });
  }

  /**
   * Copy a track's motion over (t0, t1): the `piece` signal brings it back.
   * @param {string} path
   * @param {number} t0
   * @param {number} t1
   */
  copyRange(path, t0, t1) {
    this.send({ type: 'track.copy', path, t0, t1 });
  }

  /**
   * Paste a copied piece on the track at `path` from time `at`.
   * @param {string} path
   * @param {number} at
   * @param {Track} piece
   * @param {number} length
   */
  pasteRange(path, at, piece, length) {
    if (!this.readOnly) this.send({ type: 'track.paste', path, at, piece, length });
  }

  // -- takes ------------------------------------------------------------------------------

  /** This page began a take: the curve pieces shown from now on are its. */
  beganTake() {
    this.pieces.clear();
  }

  /**
   * This page ended a take: kept in the log until its final curve arrives.
   * @param {TakeSampler} sampler
   * @param {number} released performance.now() of the release
   */
  endedTake(sampler, released) {
    this.takes.push({ id: sampler.id, sampler, released, final: null, label: null, serverMs: null });
  }

  // -- every frame ------------------------------------------------------------------------

  /**
   * Write every track's value at `time` into the scene, except what the performer holds
   * (but for `also`) and what another page's take records.
   * @param {number} time
   * @param {string[]} [also] held attributes written all the same
   */
  writeTracks(time, also = []) {
    const p = this.packed;
    const held = [...(this.performer.grab ? this.performer.grab.paths : []), ...(this.remoteTake?.paths ?? [])]
      .filter((path) => !also.includes(path));
    evaluate(p, time);
    for (let j = 0; j < p.paths.length; j++) {
      const path = p.paths[j];
      if (held.length && held.includes(path)) continue;
      const value = Array.from(valueOf(p, j));
      this.values.set(path, value);
      this.draw(path, value);
    }
    for (const steps of this.steps) {
      if (held.includes(steps.path)) continue;
      const value = stepValue(steps, time);
      if (value !== null && value !== this.values.get(steps.path)) {
        this.values.set(steps.path, value);
        this.draw(steps.path, value);
      }
    }
  }

  /**
   * One animation frame: the transport's time from the browser's clock, playback, and
   * the held attributes sampled into the take.
   * @param {number} now performance.now() of the frame
   */
  frame(now) {
    const dt = this.performer.lap(now);
    const clock = this.transport.clock;
    const wasPlaying = clock.playing;
    const { time, wrapped, laps, stopped } = this.transport.tick(now);
    if (wrapped) this.performer.wrapped(now);                  // a pass of the loop ends here
    const started = performance.now();
    if (clock.playing || wrapped || stopped) this.writeTracks(time);
    this.playMs = performance.now() - started;
    if ((wasPlaying || clock.playing) && this.cues.times.length) this.fire(this.firedTo, time, laps);
    this.firedTo = time;
    this.performer.step(dt, now, time);
    if (wasPlaying !== clock.playing) this.transport.send();
    this.signals.emit('frame', now);
  }

  /**
   * The events playback passed from `from` to `to` this frame fire (the `fired` signal).
   * @param {number} from
   * @param {number} to
   * @param {number} laps how many times it went round the loop range on the way
   */
  fire(from, to, laps) {
    const clock = this.transport.clock;
    const fired = passed(this.cues, from, to, clock.speed, clock.loop, laps);
    if (fired.length) this.signals.emit('fired', fired);
  }

  /** The page went to the background (no more frames): a take ends at its last sample. */
  hidden() {
    this.performer.release();
  }
}
