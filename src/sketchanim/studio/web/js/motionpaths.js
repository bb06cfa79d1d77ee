// @ts-check
/**
 * Motion paths in the 3D view: where an animated position (a `<object>.position` curve, or a
 * chain's or walker's performed `<object>.goal`) goes
 * over the range around the playhead (pathgeometry.js: ±2 s, or the loop range), a line with
 * a tick at each frame (their spacing shows the speed) and the playhead's frame highlighted;
 * the selected object's, or every animated object's. The curve's control points acting on
 * that range are handles: hovering one highlights it, a click selects it (the point selection
 * the curve editor shares; Shift adds), a drag moves the selected points in the plane facing
 * the view through the grabbed one. While dragging, the path, and the object when the
 * playhead is in the changed span, show the moved curve in the page only; the release sends
 * one `curve.points` (one History step). Esc during the drag cancels it (nothing is sent).
 * Geometry is rebuilt only when a path's curve, range, frame rate or playhead frame changed.
 */
import * as THREE from 'three';
import { valuesAt } from './evaluate.js';
import { frameAt, framesIn, pathRange, pointsActing, spanTimes, withPoints } from './pathgeometry.js';

/** @typedef {import('./messages.js').CurveTrack} CurveTrack */
/** @typedef {import('./Studio.js').PointSelection} PointSelection */

const COLOURS = { path: 0x4dd0e1, now: 0xffffff, handle: 0x4dd0e1, hover: 0xffffff, selected: 0xffc640, hull: 0x7d8597, outline: 0x0b0d10 };
/** Pixel sizes: a tick, the playhead's frame, a handle and its dark rim. */
const SIZES = { tick: 4, now: 7, handle: 9, outline: 13 };
/** CSS pixels from a handle's centre that still grab it. */
const GRAB = 8;
/** CSS pixels the pointer moves before a press on a handle is a drag (not a click). */
const SLOP = 3;
/** The attributes whose curves are paths in space: an object's position, a rig's goal. */
const PATHS = ['position', 'goal'];
/** Line samples per frame (the path is smooth between ticks). */
const SAMPLES_PER_FRAME = 4;

/**
 * @typedef {object} Shown   What one path drawing shows now (its geometry is rebuilt when this changes).
 * @property {CurveTrack} curve
 * @property {number} t0
 * @property {number} t1
 * @property {number} fps
 * @property {number} frame  the playhead's
 */

/**
 * @typedef {object} PointDrag   Control points being dragged.
 * @property {THREE.Plane} plane   faces the view, through the grabbed point
 * @property {THREE.Vector3} start where the press met the plane
 * @property {{path: string, index: number, from: number[]}[]} points  the points moved, where they were
 * @property {PointSelection} grabbed
 * @property {boolean} shift
 * @property {boolean} moved     the pointer went past the slop
 * @property {number} x
 * @property {number} y
 * @property {number} pointer
 */

/** The materials of every path (drawn over the scene, after the ghosts). */
function materials() {
  const over = { depthTest: false, depthWrite: false, transparent: true };
  return {
    line: new THREE.LineBasicMaterial({ color: COLOURS.path, ...over }),
    hull: new THREE.LineBasicMaterial({ color: COLOURS.hull, opacity: 0.6, ...over }),
    tick: new THREE.PointsMaterial({ color: COLOURS.path, size: SIZES.tick, sizeAttenuation: false, ...over }),
    now: new THREE.PointsMaterial({ color: COLOURS.now, size: SIZES.now, sizeAttenuation: false, ...over }),
    outline: new THREE.PointsMaterial({ color: COLOURS.outline, size: SIZES.outline, sizeAttenuation: false, ...over }),
    handle: new THREE.PointsMaterial({ size: SIZES.handle, sizeAttenuation: false, vertexColors: true, ...over }),
  };
}

/**
 * A buffer geometry of points end to end (xyz rows).
 * @param {ArrayLike<number>} xyz
 */
function pointsGeometry(xyz) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(Array.from(xyz), 3));
  return g;
}

/** One path's drawing: line, ticks, the playhead's frame, the control polygon, the handles. */
class PathDrawing {
  /**
   * @param {THREE.Group} parent
   * @param {ReturnType<typeof materials>} m
   */
  constructor(parent, m) {
    this.group = new THREE.Group();
    this.line = new THREE.Line(new THREE.BufferGeometry(), m.line);
    this.hull = new THREE.Line(new THREE.BufferGeometry(), m.hull);
    this.ticks = new THREE.Points(new THREE.BufferGeometry(), m.tick);
    this.now = new THREE.Points(new THREE.BufferGeometry(), m.now);
    this.outline = new THREE.Points(new THREE.BufferGeometry(), m.outline);
    this.handles = new THREE.Points(new THREE.BufferGeometry(), m.handle);
    [this.hull, this.line, this.ticks, this.now, this.outline, this.handles].forEach((o, i) => {
      o.renderOrder = 10 + i;
      o.frustumCulled = false;
      this.group.add(o);
    });
    parent.add(this.group);
    /** @type {Shown | null} */
    this.shown = null;
    /** @type {number[]} the handles' control points (indices into coef) */
    this.indices = [];
    this.tickCount = 0;
  }

  /**
   * Show `next` (rebuilding the geometry only if it differs from what is shown).
   * @param {Shown} next
   */
  show(next) {
    const s = this.shown;
    if (s && s.curve === next.curve && s.t0 === next.t0 && s.t1 === next.t1 && s.fps === next.fps && s.frame === next.frame) return false;
    this.shown = next;
    const { curve, t0, t1, fps, frame } = next;
    const ticks = framesIn(t0, t1, fps);
    this.tickCount = ticks.length;
    const playhead = frame / fps;
    const within = playhead >= t0 - 1e-9 && playhead <= t1 + 1e-9;
    this.indices = pointsActing(curve, t0, t1);
    const hull = this.indices.flatMap((i) => curve.coef[i]);
    this.set(this.line, valuesAt(curve, spanTimes(t0, t1, 1 / (fps * SAMPLES_PER_FRAME))));
    this.set(this.ticks, valuesAt(curve, ticks));
    this.set(this.now, within ? valuesAt(curve, [playhead]) : []);
    this.set(this.hull, hull);
    this.set(this.outline, hull);
    this.set(this.handles, hull);
    this.handles.geometry.setAttribute('color', new THREE.Float32BufferAttribute(new Float32Array(hull.length), 3));
    return true;
  }

  /**
   * @param {THREE.Line | THREE.Points} object
   * @param {ArrayLike<number>} xyz
   */
  set(object, xyz) {
    object.geometry.dispose();
    object.geometry = pointsGeometry(xyz);
  }

  /**
   * Colour the handles: selected, hovered, or plain.
   * @param {Set<number>} selected
   * @param {number | null} hover
   */
  colour(selected, hover) {
    const attr = /** @type {THREE.BufferAttribute | undefined} */ (this.handles.geometry.getAttribute('color'));
    if (!attr) return;
    const c = new THREE.Color();
    this.indices.forEach((index, i) => {
      c.setHex(index === hover ? COLOURS.hover : selected.has(index) ? COLOURS.selected : COLOURS.handle);
      attr.setXYZ(i, c.r, c.g, c.b);
    });
    attr.needsUpdate = true;
  }

  dispose() {
    this.group.removeFromParent();
    for (const o of [this.line, this.hull, this.ticks, this.now, this.outline, this.handles]) o.geometry.dispose();
  }
}

/**
 * Whether two selections name the same point.
 * @param {PointSelection} a
 * @param {PointSelection} b
 */
const same = (a, b) => a.path === b.path && a.kind === b.kind && a.index === b.index;

export class MotionPaths {
  /**
   * @param {import('./viewport.js').Viewport} viewport
   * @param {import('./viewtoggles.js').ViewToggles} toggles
   */
  constructor(viewport, toggles) {
    this.viewport = viewport;
    this.studio = viewport.studio;
    this.toggles = toggles;
    this.materials = materials();
    this.group = new THREE.Group();
    this.group.name = 'motion paths';
    viewport.scene.add(this.group);
    /** @type {Map<string, PathDrawing>} by path */
    this.drawings = new Map();
    /** @type {Map<string, CurveTrack>} curves shown moved (a drag, or a move sent whose tracks are not back yet), by path */
    this.preview = new Map();
    /** @type {PointSelection | null} the handle under the pointer */
    this.hover = null;
    /** @type {PointDrag | null} */
    this.drag = null;
    const s = this.studio;
    s.signals.on('frame', () => this.update());
    s.signals.on('points', () => this.recolour());
    s.signals.on('tracks', () => { if (!this.drag) this.settle(); });
    s.signals.on('error', (m) => { if (m.ref === 'curve.points' && !this.drag) this.settle(); });
    viewport.renderer.domElement.addEventListener('pointerleave', () => this.hovering(null));
    window.addEventListener('keydown', (e) => {          // before the shortcuts (Esc also deselects)
      if (e.key === 'Escape' && this.cancel()) {
        e.preventDefault();
        e.stopImmediatePropagation();
      }
    }, { capture: true });
  }

  /**
   * The curve of `path` as the view shows it: moved in a preview, else the track's.
   * @param {string} path
   * @returns {CurveTrack | null}
   */
  curveOf(path) {
    const track = this.studio.tracks.get(path);
    return this.preview.get(path) ?? (track?.kind === 'curve' ? track : null);
  }

  /** The position (and goal) paths to show: the selected object's, or every object's (the toggle). */
  paths() {
    const s = this.studio;
    if (!this.toggles.on.paths) return [];
    const names = this.toggles.on.all ? [...this.viewport.nodes.keys()] : s.selected ? [s.selected] : [];
    return names.filter((n) => this.viewport.nodes.has(n))
      .flatMap((n) => PATHS.map((a) => `${n}.${a}`)).filter((p) => this.curveOf(p));
  }

  /** Each frame: draw the paths shown (rebuilt only where something changed). */
  update() {
    const s = this.studio;
    const shown = new Set();
    let rebuilt = false;
    for (const path of this.paths()) {
      const curve = /** @type {CurveTrack} */ (this.curveOf(path));
      const range = pathRange(s.transport.time, s.fps, s.transport.clock.loop, curve.start, curve.end);
      if (!range) continue;
      shown.add(path);
      let drawing = this.drawings.get(path);
      if (!drawing) {
        drawing = new PathDrawing(this.group, this.materials);
        this.drawings.set(path, drawing);
      }
      rebuilt = drawing.show({ curve, t0: range[0], t1: range[1], fps: s.fps, frame: frameAt(s.transport.time, s.fps) }) || rebuilt;
    }
    for (const [path, drawing] of this.drawings) {
      if (shown.has(path)) continue;
      drawing.dispose();
      this.drawings.delete(path);
    }
    if (this.hover && !this.handleAt(this.hover)) this.hover = null;
    if (rebuilt) this.recolour();
    if (this.drag?.moved) this.showMoved();
  }

  recolour() {
    for (const [path, drawing] of this.drawings) {
      const selected = new Set(this.studio.points.filter((q) => q.path === path && q.kind === 'point').map((q) => q.index));
      drawing.colour(selected, this.hover?.path === path ? this.hover.index : null);
    }
  }

  /**
   * Where a handle is in the scene, if it is shown.
   * @param {PointSelection} point
   * @returns {THREE.Vector3 | null}
   */
  handleAt(point) {
    const drawing = this.drawings.get(point.path);
    const curve = drawing?.shown?.curve;
    if (!curve || point.kind !== 'point' || !drawing.indices.includes(point.index)) return null;
    return new THREE.Vector3(...curve.coef[point.index]);
  }

  /**
   * The page coordinates of a handle (for tests and tools), or null if it is not shown.
   * @param {string} path
   * @param {number} index
   * @returns {{x: number, y: number} | null}
   */
  handleScreen(path, index) {
    const at = this.handleAt({ path, kind: 'point', index });
    return at ? this.viewport.pageOf(at) : null;
  }

  /**
   * The handle under the pointer (the nearest within GRAB pixels), if any.
   * @param {PointerEvent} e
   * @returns {PointSelection | null}
   */
  pick(e) {
    let best = null;
    let nearest = GRAB;
    for (const [path, drawing] of this.drawings) {
      for (const index of drawing.indices) {
        const p = this.viewport.pageOf(/** @type {THREE.Vector3} */ (this.handleAt({ path, kind: 'point', index })));
        const d = Math.hypot(p.x - e.clientX, p.y - e.clientY);
        if (d <= nearest) {
          nearest = d;
          best = { path, kind: /** @type {const} */ ('point'), index };
        }
      }
    }
    return best;
  }

  // -- the pointer (the viewport hands its events here first) ------------------------------

  /**
   * A press: on a handle, select it and start a drag (true: the press is taken).
   * @param {PointerEvent} e
   */
  press(e) {
    const s = this.studio;
    const hit = s.performer.grab ? null : this.pick(e);
    if (!hit) return false;
    const name = hit.path.slice(0, hit.path.lastIndexOf('.'));
    if (s.selected !== name) s.select(name);
    const had = s.points.some((q) => same(q, hit));
    if (!had) s.selectPoints(e.shiftKey ? [...s.points, hit] : [hit]);
    if (s.readOnly) return true;
    const grabbed = /** @type {THREE.Vector3} */ (this.handleAt(hit));
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(this.viewport.camera.getWorldDirection(new THREE.Vector3()), grabbed);
    const points = s.points.filter((q) => q.kind === 'point' && this.handleAt(q)).map((q) => ({
      path: q.path, index: q.index, from: /** @type {CurveTrack} */ (this.curveOf(q.path)).coef[q.index] }));
    const start = this.viewport.ray(e).ray.intersectPlane(plane, new THREE.Vector3()) ?? grabbed;
    this.drag = { plane, start, points, grabbed: hit, shift: e.shiftKey, moved: false, x: e.clientX, y: e.clientY, pointer: e.pointerId };
    this.viewport.orbit.enabled = false;
    this.viewport.renderer.domElement.setPointerCapture(e.pointerId);
    return true;
  }

  /**
   * A move: drags the points, or highlights the handle under the pointer (true: a drag has it).
   * @param {PointerEvent} e
   */
  move(e) {
    const drag = this.drag;
    if (!drag) {
      this.hovering(this.viewport.drag || this.viewport.transform.dragging ? null : this.pick(e));
      return false;
    }
    if (!drag.moved && Math.hypot(e.clientX - drag.x, e.clientY - drag.y) < SLOP) return true;
    const at = this.viewport.ray(e).ray.intersectPlane(drag.plane, new THREE.Vector3());
    if (!at) return true;
    drag.moved = true;
    const delta = at.sub(drag.start);
    /** @type {Map<string, Map<number, number[]>>} */
    const moved = new Map();
    for (const p of drag.points) {
      const rows = moved.get(p.path) ?? new Map();
      rows.set(p.index, p.from.map((x, i) => x + delta.getComponent(i)));
      moved.set(p.path, rows);
    }
    for (const [path, rows] of moved) {
      const track = /** @type {CurveTrack} */ (this.studio.tracks.get(path));
      this.preview.set(path, withPoints(track, rows));
    }
    this.showMoved();
    return true;
  }

  /**
   * Highlight the handle under the pointer (null: none).
   * @param {PointSelection | null} hit
   */
  hovering(hit) {
    if ((hit?.path ?? null) === (this.hover?.path ?? null) && hit?.index === this.hover?.index) return;
    this.hover = hit;
    this.viewport.renderer.domElement.style.cursor = hit ? 'grab' : '';
    this.recolour();
  }

  /**
   * The release: sends the move (one History step), or, for a click, keeps the selection
   * to the clicked point (true: the release was the drag's).
   */
  lift() {
    const drag = this.drag;
    if (!drag) return false;
    this.end(drag);
    const s = this.studio;
    if (drag.moved) {
      s.movePoints(drag.points.map((p) => ({ path: p.path, index: p.index,
        value: /** @type {CurveTrack} */ (this.preview.get(p.path)).coef[p.index] })));
    } else if (!drag.shift && s.points.length > 1) s.selectPoints([drag.grabbed]);
    return true;
  }

  /** Esc or a cancelled pointer: the drag ends, nothing is sent (true: there was one). */
  cancel() {
    const drag = this.drag;
    if (!drag) return false;
    this.end(drag);
    this.settle();
    return true;
  }

  /** @param {PointDrag} drag */
  end(drag) {
    this.drag = null;
    this.viewport.orbit.enabled = true;
    const canvas = this.viewport.renderer.domElement;
    if (canvas.hasPointerCapture(drag.pointer)) canvas.releasePointerCapture(drag.pointer);
  }

  /** The objects of moved curves drawn where the moved curve has them at the playhead (the page only). */
  showMoved() {
    const t = this.studio.transport.time;
    for (const [path, curve] of this.preview) this.studio.draw(path, Array.from(valuesAt(curve, [t])));
  }

  /** The previews go (the tracks came, or the move was refused or cancelled): the tracks' values drawn again. */
  settle() {
    const paths = [...this.preview.keys()];
    this.preview.clear();
    for (const path of paths) this.studio.draw(path, this.studio.values.get(path));
  }

  /**
   * What the paths show, for tests: each path's range, ticks, the playhead's frame and handles.
   * @returns {{path: string, t0: number, t1: number, frame: number, ticks: number, handles: number[]}[]}
   */
  report() {
    return [...this.drawings].map(([path, d]) => {
      const s = /** @type {Shown} */ (d.shown);
      return { path, t0: s.t0, t1: s.t1, frame: s.frame, ticks: d.tickCount, handles: [...d.indices] };
    });
  }
}
