// @ts-check
/**
 * Onion skin in the 3D view: see-through copies ("ghosts") of the selected object, or of
 * every animated object, where its tracks have it a few frames before the playhead (tinted
 * warm) and after it (tinted green): `count` ghosts each side, `every` frames apart
 * (pathgeometry.js `ghostTimes`), fading with their distance from the playhead. Evaluated from
 * the tracks (a curve moved in the motion paths' preview included) with evaluate.js; a ghost
 * whose time is outside the object's animation is not drawn. A chain or a walker is ghosted as
 * lines along its segments or bones in the pose rigs.js plays at the ghost's time (its goal's
 * curve's, and a chain's base's). Rebuilt only when the objects, their curves (a rig's pose
 * cache), the frame rate or the playhead's frame changed.
 */
import * as THREE from 'three';
import { ChainView } from './chainview.js';
import { evaluate, pack, valueOf } from './evaluate.js';
import { frameAt, ghostTimes } from './pathgeometry.js';
import { WalkerView } from './walkerview.js';

/** The attributes a ghost takes from the tracks (the others are the object's as it is now). */
const POSE = ['position', 'orientation', 'scale'];
/** A rig's: its goal, and a chain's base (its pose follows from them). */
const RIG_POSE = ['goal', 'position'];
const TINTS = { before: 0xff7a6b, after: 0x7ee08a };
/** The nearest ghost's opacity (the farthest fade towards 0). */
const OPACITY = 0.5;

/**
 * @typedef {object} Ghost   One ghost, as the test hook reports it.
 * @property {string} name     the object's
 * @property {'before' | 'after'} side
 * @property {number} time
 * @property {number[]} position
 */

export class OnionSkin {
  /**
   * @param {import('./viewport.js').Viewport} viewport
   * @param {import('./viewtoggles.js').ViewToggles} toggles
   * @param {(path: string) => import('./messages.js').CurveTrack | null} curveOf the curve of a path as the view shows it
   */
  constructor(viewport, toggles, curveOf) {
    this.viewport = viewport;
    this.studio = viewport.studio;
    this.toggles = toggles;
    this.curveOf = curveOf;
    /** Ghosts each side of the playhead. */
    this.count = 3;
    /** Frames between ghosts. */
    this.every = 4;
    this.group = new THREE.Group();
    this.group.name = 'onion skin';
    viewport.scene.add(this.group);
    /** @type {Record<'before' | 'after', THREE.MeshBasicMaterial[]>} the j-th ghost's of each side */
    this.materials = { before: [], after: [] };
    /** @type {Record<'before' | 'after', THREE.LineBasicMaterial[]>} a rig ghost's lines, the same tints */
    this.lines = { before: [], after: [] };
    /** @type {unknown[]} what the ghosts were built from */
    this.key = [];
    /** @type {Ghost[]} */
    this.ghosts = [];
    this.studio.signals.on('frame', () => this.update());
  }

  /**
   * The material of the j-th ghost (0: nearest) on a side.
   * @param {'before' | 'after'} side
   * @param {number} j
   */
  material(side, j) {
    const list = this.materials[side];
    while (list.length <= j) {
      const fade = OPACITY * (1 - list.length / Math.max(this.count, 1));
      list.push(new THREE.MeshBasicMaterial({ color: TINTS[side], transparent: true, opacity: fade, depthWrite: false }));
    }
    return list[j];
  }

  /**
   * The line material of the j-th rig ghost on a side (the tint and fade of `material`).
   * @param {'before' | 'after'} side
   * @param {number} j
   */
  lineMaterial(side, j) {
    const list = this.lines[side];
    while (list.length <= j) {
      const m = this.material(side, list.length);
      list.push(new THREE.LineBasicMaterial({ color: m.color, transparent: true, opacity: m.opacity, depthWrite: false }));
    }
    return list[j];
  }

  /** The objects ghosted, each with its pose curves: the selected one, or every animated one (the toggle). */
  animated() {
    const s = this.studio;
    const names = this.toggles.on.all ? [...this.viewport.nodes.keys()] : s.selected ? [s.selected] : [];
    return names.map((name) => ({ name, curves: (this.viewport.nodes.get(name)?.rig ? RIG_POSE : POSE).map((a) => this.curveOf(`${name}.${a}`)) }))
      .filter((o) => this.viewport.nodes.has(o.name) && o.curves.some(Boolean));
  }

  /** Each frame: the ghosts, rebuilt only when what they show changed. */
  update() {
    const s = this.studio;
    const objects = this.toggles.on.onion ? this.animated() : [];
    const key = [s.fps, frameAt(s.transport.time, s.fps), this.count, this.every,
      ...objects.flatMap((o) => [o.name, ...o.curves, ...(this.viewport.nodes.get(o.name)?.pick.map((m) => m.geometry) ?? []),
        this.viewport.rigs.rigs.get(o.name)?.cache])];
    if (key.length === this.key.length && key.every((k, i) => k === this.key[i])) return;
    this.key = key;
    this.build(objects);
  }

  /** @param {ReturnType<OnionSkin['animated']>} objects */
  build(objects) {
    for (const ghost of [...this.group.children]) {
      ghost.removeFromParent();           // geometry and materials are shared: kept (a rig ghost's lines are its own)
      if (ghost instanceof THREE.LineSegments) ghost.geometry.dispose();
    }
    this.ghosts = [];
    const s = this.studio;
    const times = ghostTimes(s.transport.time, s.fps, this.count, this.every);
    for (const { name, curves } of objects) {
      const node = /** @type {import('./viewport.js').Node} */ (this.viewport.nodes.get(name));
      if (node.rig) {
        this.rigGhosts(node, curves, times);
        continue;
      }
      const present = /** @type {import('./messages.js').CurveTrack[]} */ (curves.filter(Boolean));
      const packed = pack(present);
      const [start, end] = /** @type {[number, number]} */ (packed.span);
      for (const side of /** @type {const} */ (['before', 'after'])) {
        times[side].forEach((t, j) => {
          if (t < start - 1e-9 || t > end + 1e-9) return;
          evaluate(packed, t);
          const ghost = new THREE.Group();
          ghost.position.copy(node.root.position);
          ghost.quaternion.copy(node.root.quaternion);
          ghost.scale.copy(node.root.scale);
          present.forEach((c, i) => {
            const v = valueOf(packed, i);
            if (c.path.endsWith('.position')) ghost.position.set(v[0], v[1], v[2]);
            else if (c.path.endsWith('.orientation')) ghost.quaternion.set(v[0], v[1], v[2], v[3]);
            else ghost.scale.set(v[0], v[1], v[2]);
          });
          for (const mesh of node.pick) {
            const copy = new THREE.Mesh(mesh.geometry, this.material(side, j));
            copy.position.copy(mesh.position);
            copy.quaternion.copy(mesh.quaternion);
            copy.scale.copy(mesh.scale);
            ghost.add(copy);
          }
          this.group.add(ghost);
          this.ghosts.push({ name, side, time: t, position: ghost.position.toArray() });
        });
      }
    }
  }

  /**
   * A chain's or walker's ghosts: lines along its pose at each ghost time within its curves' span.
   * @param {import('./viewport.js').Node} node
   * @param {(import('./messages.js').CurveTrack | null)[]} curves  its goal's and a chain's base's
   * @param {{before: number[], after: number[]}} times
   */
  rigGhosts(node, curves, times) {
    const present = /** @type {import('./messages.js').CurveTrack[]} */ (curves.filter(Boolean));
    const [start, end] = /** @type {[number, number]} */ (pack(present).span);
    const motion = this.viewport.rigs.rigs.get(node.name)?.motion;
    const base = curves[1] ? pack([curves[1]]) : null;
    for (const side of /** @type {const} */ (['before', 'after'])) {
      times[side].forEach((t, j) => {
        if (t < start - 1e-9 || t > end + 1e-9 || !motion) return;
        const pose = this.viewport.rigs.playedAt(node.name, t);
        if (!pose) return;
        const at = base ? evaluate(base, t) : this.studio.values.get(`${node.name}.position`);
        const xyz = motion.chain ? ChainView.segments(motion.chain, pose, at)
          : motion.skeleton ? WalkerView.segments(motion.skeleton, pose) : [];
        const ghost = new THREE.LineSegments(new THREE.BufferGeometry(), this.lineMaterial(side, j));
        ghost.geometry.setAttribute('position', new THREE.Float32BufferAttribute(xyz, 3));
        this.group.add(ghost);
        this.ghosts.push({ name: node.name, side, time: t, position: xyz.slice(0, 3) });
      });
    }
  }

  /**
   * The ghosts drawn, for tests.
   * @returns {Ghost[]}
   */
  report() {
    return this.ghosts.map((g) => ({ ...g, position: [...g.position] }));
  }
}
