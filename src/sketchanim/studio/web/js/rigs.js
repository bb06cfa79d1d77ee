// @ts-check
/**
 * Rigs: the derived poses of the page's chains and walkers (anim/scene.py RIGS). A rig's pose is
 * a pure function of its goal's curve: the goal (a chain's in its base's frame, goal - base; a
 * walker's ground marker in the world) sampled at the ticks k / RATE from 0 as the player plays
 * it (evaluate.js), solved tick by tick (ik.js `step`, walk.js `start` / `advance`), each tick's
 * pose cached per object, the cache extended forward lazily as playback passes its end and thrown
 * away when the goal's curve, the base's or the rig's structure attributes change (but for the
 * ticks before a curve's first changed control point acts: `changedFrom`). The pose at a
 * time is its two neighbouring ticks' poses, slerped per joint (and the walker's root lerped).
 *
 * As the model has it (anim/rigs.py LEAD), the solver first runs LEAD ticks on the goal of tick 0,
 * from the rest pose, so that at time 0 the figure has come to rest on its goal (a chain holds
 * it, a walker stands).
 *
 * While the goal (or a chain's base) is performed live -- held by this page's performer or
 * recorded by another page -- the figure steps from the state shown last toward the live goal at
 * the tick rate: the ticks elapsed since the last frame, the goal interpolated between the last
 * live value and this one, so it follows the hand with no lag beyond the solver's.
 *
 * No three.js here: the viewport's chainview.js and walkerview.js draw what this computes.
 */
import { evaluate, pack } from './evaluate.js';
import * as ik from './ik.js';
import * as walker from './walk.js';

/** Ticks per second of every derived pose (ik.js RATE; walk.js steps at the same rate). */
export const RATE = ik.RATE;
/** Ticks solved on the goal's first value before time 0, from the rest pose (anim/rigs.py LEAD). */
export const LEAD = 2 * RATE;
/** Ticks the cache grows by at least when playback passes its end (a quarter second). */
const CHUNK = RATE / 4;
/** Ticks between the states kept to resume a simulation from (a live grab starting mid-way, a curve changed from a time on). */
const CHECKPOINT = RATE / 4;
/** The most ticks a live figure steps in one frame (a stalled page catches up no further). */
const LIVE_MAX = RATE / 2;

/** @typedef {import('./evaluate.js').Curve} Curve */
/** @typedef {'chain' | 'walker'} RigKind */

/**
 * What the rigs read of the page.
 * @typedef {object} RigScene
 * @property {(path: string) => Curve | null} curveOf  the curve of `path` as shown (a motion path's preview, else its track)
 * @property {(path: string) => any} valueOf           its value now (a live one while held)
 * @property {(path: string) => boolean} live          whether `path` is being performed now
 */

/**
 * A rig's pose at one time.
 * @typedef {object} Pose
 * @property {Float64Array} rotations  J local rotations (x, y, z, w)
 * @property {Float64Array | null} root a walker's hips in the world (a chain: null)
 */

/**
 * One rig kind's tick-by-tick simulation.
 * @typedef {object} Motion
 * @property {(goal: Float64Array) => any} first           the state of tick 0
 * @property {(state: any, goal: Float64Array) => any} next the state of the next tick
 * @property {(state: any) => Pose} pose                   a state's pose (not copied)
 * @property {(state: any) => {since: number, speed: number} | null} lag  the tick since which the goal
 *   outruns the figure and the fastest goal speed since (m/s), or null: it keeps up
 * @property {ReturnType<typeof ik.chainFromSlots>} [chain]        a chain's structure
 * @property {ReturnType<typeof walker.humanoid>} [skeleton]       a walker's
 */

/**
 * A chain's simulation, from its structure attributes (8 slots each).
 * @param {number[]} lengths
 * @param {number[]} limits  degrees
 * @param {number[]} hinges  1 hinge, 0 ball
 * @returns {Motion & {chain: ReturnType<typeof ik.chainFromSlots>}}
 *
 * @example
 * const m = chainMotion([0.5, 0.5, 0, 0, 0, 0, 0, 0], Array(8).fill(150), Array(8).fill(0));
 * m.chain.lengths.length;   // 2
 */
export function chainMotion(lengths, limits, hinges) {
  const chain = ik.chainFromSlots(lengths, limits, hinges);
  /** @param {{pose: Float64Array, goal: Float64Array | null}} state @param {Float64Array} goal */
  const next = (state, goal) => ({ pose: ik.step(chain, state.pose, goal, state.goal ?? undefined), goal: Float64Array.from(goal) });
  return {
    chain, next,
    first: (goal) => next({ pose: ik.rest(chain), goal: null }, goal),
    pose: (state) => ({ rotations: state.pose, root: null }),
    lag: () => null,
  };
}

/**
 * A walker's simulation: a humanoid `height` metres tall.
 * @param {number} height
 * @returns {Motion & {skeleton: ReturnType<typeof walker.humanoid>}}
 *
 * @example
 * walkerMotion(1.75).skeleton.names[0];   // 'hips'
 */
export function walkerMotion(height) {
  const skeleton = walker.humanoid(height);
  return {
    skeleton,
    first: (goal) => walker.start(skeleton, goal),
    next: (state, goal) => walker.advance(state, goal),
    pose: (state) => ({ rotations: state.rotations, root: state.root }),
    lag: (state) => (state.behindSince >= 0 ? { since: state.behindSince, speed: state.behindSpeed } : null),
  };
}

/**
 * The unit quaternion between `a` (at offset `i`) and `b` (at `j`) at `f` in [0, 1], the short
 * way round, into `out` at `o`: spherical where they differ, normalised linear where they are
 * within 1e-6 rad (no division by a vanishing sine).
 * @param {ArrayLike<number>} a @param {number} i
 * @param {ArrayLike<number>} b @param {number} j
 * @param {number} f
 * @param {Float64Array} out @param {number} o
 *
 * @example
 * const out = new Float64Array(4);
 * slerp([0, 0, 0, 1], 0, [0, 0, 1, 0], 0, 0.5, out, 0);   // out: [0, 0, 0.7071…, 0.7071…]
 */
export function slerp(a, i, b, j, f, out, o) {
  let dot = a[i] * b[j] + a[i + 1] * b[j + 1] + a[i + 2] * b[j + 2] + a[i + 3] * b[j + 3];
  const sign = dot < 0 ? -1 : 1;
  dot *= sign;
  let wa = 1 - f;
  let wb = f * sign;
  if (dot < 1 - 5e-13) {
    const theta = Math.acos(Math.min(dot, 1));
    const s = Math.sin(theta);
    wa = Math.sin((1 - f) * theta) / s;
    wb = (Math.sin(f * theta) / s) * sign;
  }
  let norm = 0;
  for (let c = 0; c < 4; c++) {
    out[o + c] = wa * a[i + c] + wb * b[j + c];
    norm += out[o + c] * out[o + c];
  }
  norm = Math.sqrt(norm);
  for (let c = 0; c < 4; c++) out[o + c] /= norm;
}

/**
 * The goal a rig solves for at each tick, from its goal's (and a chain's base's) curves or values.
 * @param {Curve | number[]} goal   its curve, or its constant value
 * @param {Curve | number[] | null} base  a chain's base (the goal is taken in its frame), or null
 * @returns {(k: number, out: Float64Array) => Float64Array} the goal at tick k into `out`
 *
 * @example
 * goalSampler([1, 2, 3], [1, 0, 0])(5, new Float64Array(3));   // [0, 2, 3]
 */
export function goalSampler(goal, base) {
  /** @param {Curve | number[]} c @returns {(t: number) => ArrayLike<number>} */
  const source = (c) => {
    if (Array.isArray(c)) return () => c;
    const packed = pack([c]);
    return (t) => evaluate(packed, t);
  };
  const g = source(goal);
  const b = base ? source(base) : null;
  return (k, out) => {
    const t = k / RATE;
    const v = g(t);
    for (let c = 0; c < 3; c++) out[c] = v[c];
    if (b) {
      const w = b(t);
      for (let c = 0; c < 3; c++) out[c] -= w[c];
    }
    return out;
  };
}

/**
 * The earliest time at which curve (or value) `b` may differ from `a`: Infinity for the same
 * one; for two curves of the same order and knots, the first knot past the curve's start where
 * the first control point that differs starts acting (before it both evaluate alike: point i of
 * an order-k curve acts on (knots[i], knots[i + k]), and evaluation holds the start's value
 * before it); else -Infinity (anything may differ).
 * @param {Curve | number[] | null} a
 * @param {Curve | number[] | null} b
 * @returns {number}
 *
 * @example
 * const c = {path: 'a.goal', order: 2, knots: [0, 0, 1, 2, 2], coef: [[0, 0, 0], [1, 0, 0], [2, 0, 0]]};
 * changedFrom(c, {...c, coef: [[0, 0, 0], [1, 0, 0], [3, 0, 0]]});   // 1
 * changedFrom(c, {...c, coef: [[9, 0, 0], [1, 0, 0], [2, 0, 0]]});   // -Infinity
 */
export function changedFrom(a, b) {
  if (a === b) return Infinity;
  if (!a || !b || Array.isArray(a) || Array.isArray(b) || a.order !== b.order || a.knots.length !== b.knots.length
    || a.coef.length !== b.coef.length || a.knots.some((t, i) => t !== b.knots[i])) return -Infinity;
  const i = a.coef.findIndex((row, r) => row.length !== b.coef[r].length || row.some((x, c) => x !== b.coef[r][c]));
  if (i < 0) return Infinity;
  return a.knots[i] > a.knots[a.order - 1] ? a.knots[i] : -Infinity;
}

/**
 * The cached ticks of one rig's simulation, grown on demand.
 */
export class PoseCache {
  /**
   * @param {Motion} motion
   * @param {(k: number, out: Float64Array) => Float64Array} sample the goal at tick k
   * @param {number} [lead] ticks solved on the goal of tick 0 before tick 0 (the model's LEAD by default)
   */
  constructor(motion, sample, lead = LEAD) {
    this.motion = motion;
    this.sample = sample;
    this.lead = lead;
    /** @type {Float64Array[]} each step's rotations (step j: tick j - lead) */
    this.rotations = [];
    /** @type {Float64Array[]} each step's root (a walker's) */
    this.roots = [];
    /** @type {any[]} the state of steps 0, CHECKPOINT, 2 CHECKPOINT, ... (copies) */
    this.checkpoints = [];
    /** @type {any} the state of the last step cached */
    this.state = null;
    /** @type {[number, number, number][]} the spans the goal outran the figure, ended so far (s, s, m/s; as walk.js `walk`) */
    this.behind = [];
    this.goal = new Float64Array(3);
  }

  /** Ticks cached, from tick 0. */
  get count() {
    return Math.max(this.rotations.length - this.lead, 0);
  }

  /**
   * Cache ticks up to `k` at least (and a CHUNK ahead of the last ones cached, when it grows).
   * @param {number} k
   */
  ensure(k) {
    const want = this.lead + k;
    const from = this.rotations.length;
    if (want < from) return;
    const to = Math.max(want, from + CHUNK - 1);
    const m = this.motion;
    for (let j = from; j <= to; j++) {
      const goal = this.sample(Math.max(j - this.lead, 0), this.goal);
      const lag = j === 0 ? null : m.lag(this.state);
      this.state = j === 0 ? m.first(goal) : m.next(this.state, goal);
      if (lag && !m.lag(this.state)) this.behind.push([(lag.since - this.lead) / RATE, (j - 1 - this.lead) / RATE, lag.speed]);   // to the last tick behind
      if (j % CHECKPOINT === 0) this.checkpoints.push(structuredClone(this.state));
      const pose = m.pose(this.state);
      this.rotations.push(Float64Array.from(pose.rotations));
      if (pose.root) this.roots.push(Float64Array.from(pose.root));
    }
  }

  /**
   * Take over the steps of `old` (the same motion and lead, on goals equal up to tick `last`) up
   * to the checkpoint at or before it: the simulation goes on from that checkpoint's state.
   * @param {PoseCache} old
   * @param {number} last
   */
  adopt(old, last) {
    const c = Math.floor(Math.min(this.lead + last, old.rotations.length - 1) / CHECKPOINT);
    if (c < 0 || !old.checkpoints.length) return;
    const j = c * CHECKPOINT;
    this.rotations = old.rotations.slice(0, j + 1);
    this.roots = old.roots.slice(0, j + 1);
    this.checkpoints = old.checkpoints.slice(0, c + 1);
    this.state = structuredClone(old.checkpoints[c]);
    // spans that ended (a step not behind) by step j; one still open there is in the state
    this.behind = old.behind.filter((span) => Math.round(span[1] * RATE) + this.lead + 1 <= j);
  }

  /**
   * Where the goal outran the figure over the ticks cached (a span still open ends at the last).
   * @returns {[number, number, number][]}
   */
  spans() {
    const lag = this.rotations.length ? this.motion.lag(this.state) : null;
    return lag ? [...this.behind, [(lag.since - this.lead) / RATE, (this.rotations.length - 1 - this.lead) / RATE, lag.speed]]
      : [...this.behind];
  }

  /**
   * The state of tick `k` (a copy: simulated again from the checkpoint before it).
   * @param {number} k
   */
  stateAt(k) {
    this.ensure(k);
    const j = this.lead + k;
    const c = Math.floor(j / CHECKPOINT);
    let state = structuredClone(this.checkpoints[c]);
    const goal = new Float64Array(3);
    for (let i = c * CHECKPOINT + 1; i <= j; i++) state = this.motion.next(state, this.sample(Math.max(i - this.lead, 0), goal));
    return state;
  }

  /**
   * The pose at time `t` (seconds; before 0: tick 0's), between its two neighbouring ticks.
   * @param {number} t
   * @returns {Pose}
   */
  at(t) {
    const x = Math.max(t, 0) * RATE;
    const k = Math.floor(x);
    const f = x - k;
    this.ensure(k + 1);
    const j = this.lead + k;
    const a = this.rotations[j];
    const b = this.rotations[j + 1];
    const rotations = new Float64Array(a.length);
    for (let o = 0; o < a.length; o += 4) slerp(a, o, b, o, f, rotations, o);
    let root = null;
    if (this.roots.length) {
      const ra = this.roots[j];
      const rb = this.roots[j + 1];
      root = new Float64Array(3);
      for (let c = 0; c < 3; c++) root[c] = ra[c] + (rb[c] - ra[c]) * f;
    }
    return { rotations, root };
  }
}

/**
 * A figure following a live goal.
 * @typedef {object} Live
 * @property {any} state     the state shown last
 * @property {Float64Array} goal  the live goal it stepped to last (the rig's frame)
 * @property {number} stamp  performance.now() of its last frame (ms)
 * @property {number} ticks  ticks owed (the fraction of a tick since the last step)
 */

/**
 * One rig of the page: its kind, the paths it reads, its cache and its live figure.
 * @typedef {object} Rig
 * @property {string} name
 * @property {RigKind} kind
 * @property {any[]} key       what its cache was made from (a change throws it away)
 * @property {Motion | null} motion  null: its structure is no chain (the error says why)
 * @property {string} error
 * @property {PoseCache | null} cache
 * @property {Live | null} live
 * @property {(Curve | number[] | null)[]} sources  its goal and base (curves or values) the cache was made from
 */

/** Where an object of a kind is, by kind (else its `position`): a walker is at its goal. */
export const PLACED = { walker: 'goal' };

/** The structure attributes of each kind (a change of one makes a new simulation). */
export const STRUCTURE = { chain: ['lengths', 'limits', 'hinges'], walker: ['height'] };

export class Rigs {
  /** @param {RigScene} scene */
  constructor(scene) {
    this.scene = scene;
    /** @type {Map<string, Rig>} */
    this.rigs = new Map();
  }

  /**
   * The rigs there are now (the others' caches go).
   * @param {{name: string, kind: string}[]} objects
   */
  keep(objects) {
    const names = new Set();
    for (const o of objects) {
      if (o.kind !== 'chain' && o.kind !== 'walker') continue;
      names.add(o.name);
      const rig = this.rigs.get(o.name);
      if (!rig || rig.kind !== o.kind) {
        this.rigs.set(o.name, { name: o.name, kind: o.kind, key: [], motion: null, error: '', cache: null, live: null, sources: [null, null] });
      }
    }
    for (const name of this.rigs.keys()) if (!names.has(name)) this.rigs.delete(name);
  }

  /**
   * The paths a rig's goal (in its frame) is made of: its goal, and a chain's base.
   * @param {Rig} rig
   */
  paths(rig) {
    return rig.kind === 'chain' ? [`${rig.name}.goal`, `${rig.name}.position`] : [`${rig.name}.goal`];
  }

  /**
   * The rig's cache, made again if what it was made from changed.
   * @param {Rig} rig
   */
  refresh(rig) {
    const sc = this.scene;
    const structure = STRUCTURE[rig.kind].map((a) => sc.valueOf(`${rig.name}.${a}`));
    const [goalPath, basePath] = this.paths(rig);
    const goal = sc.curveOf(goalPath) ?? sc.valueOf(goalPath);
    const base = basePath ? sc.curveOf(basePath) ?? sc.valueOf(basePath) : null;
    // curves by identity (a new track is a new object), values by content
    const key = [...structure.map((v) => JSON.stringify(v)), Array.isArray(goal) ? JSON.stringify(goal) : goal,
      Array.isArray(base) ? JSON.stringify(base) : base];
    if (key.length === rig.key.length && key.every((k, i) => k === rig.key[i])) return;
    const n = structure.length;
    const same = rig.motion && rig.cache && key.slice(0, n).every((k, i) => k === rig.key[i]);
    // a curve changed from some time on (a control point moved): the ticks before it are kept
    const from = same ? Math.min(changedFrom(rig.sources[0], goal), changedFrom(rig.sources[1], base)) : -Infinity;
    const old = rig.cache;
    rig.key = key;
    rig.sources = [goal, base];
    rig.cache = null;
    if (!same) {
      rig.motion = null;
      rig.error = '';
      try {
        rig.motion = rig.kind === 'chain' ? chainMotion(structure[0], structure[1], structure[2]) : walkerMotion(structure[0][0]);
      } catch (e) {
        rig.error = e instanceof Error ? e.message : String(e);
        return;
      }
    }
    const motion = /** @type {Motion} */ (rig.motion);
    rig.cache = new PoseCache(motion, goalSampler(goal, base));
    if (old && from > 0) rig.cache.adopt(old, Math.ceil(from * RATE) - 1);
  }

  /**
   * The pose rig `name` plays at time `t` (its curves', whether or not it is performed live now:
   * what onion skin ghosts show), or null.
   * @param {string} name
   * @param {number} t
   * @returns {Pose | null}
   */
  playedAt(name, t) {
    const rig = this.rigs.get(name);
    if (!rig) return null;
    if (!rig.live) this.refresh(rig);
    return rig.cache ? rig.cache.at(t) : null;
  }

  /**
   * The live goal of a rig now (its frame), from the values shown.
   * @param {Rig} rig
   */
  liveGoal(rig) {
    const [goalPath, basePath] = this.paths(rig);
    const g = this.scene.valueOf(goalPath);
    const b = basePath ? this.scene.valueOf(basePath) : [0, 0, 0];
    return Float64Array.from([0, 1, 2], (c) => g[c] - b[c]);
  }

  /**
   * The pose of rig `name` to show at transport time `t` and clock time `now` (ms), or null
   * (no such rig, or its structure is no chain).
   * @param {string} name
   * @param {number} t
   * @param {number} now performance.now()
   * @returns {Pose | null}
   */
  poseAt(name, t, now) {
    const rig = this.rigs.get(name);
    if (!rig) return null;
    const live = this.paths(rig).some((p) => this.scene.live(p));
    if (!live || !rig.live) this.refresh(rig);           // a live goal's moving value makes no new cache
    if (!rig.cache || !rig.motion) return null;
    if (!live) {
      rig.live = null;
      return rig.cache.at(t);
    }
    const goal = this.liveGoal(rig);
    if (!rig.live) {
      const k = Math.floor(Math.max(t, 0) * RATE);
      rig.live = { state: rig.cache.stateAt(k), goal: rig.cache.sample(k, new Float64Array(3)), stamp: now, ticks: 0 };
    }
    const figure = rig.live;
    figure.ticks = Math.min(figure.ticks + ((now - figure.stamp) / 1000) * RATE, LIVE_MAX);
    figure.stamp = now;
    const n = Math.floor(figure.ticks);
    figure.ticks -= n;
    const from = figure.goal;
    const at = new Float64Array(3);
    for (let i = 1; i <= n; i++) {
      for (let c = 0; c < 3; c++) at[c] = from[c] + ((goal[c] - from[c]) * i) / n;
      figure.state = rig.motion.next(figure.state, at);
    }
    if (n) figure.goal = goal;
    const pose = rig.motion.pose(figure.state);
    return { rotations: Float64Array.from(pose.rotations), root: pose.root ? Float64Array.from(pose.root) : null };
  }

  /**
   * Where a walker's goal outran its fastest run, over `until` seconds at least: simulated that
   * far, `most` ticks more at most this call (null: not there yet; call again).
   * @param {string} name
   * @param {number} until
   * @param {number} [most]
   * @returns {[number, number, number][] | null}
   */
  behindUntil(name, until, most = Infinity) {
    const rig = this.rigs.get(name);
    if (!rig) return [];
    this.refresh(rig);
    if (!rig.cache || !rig.motion) return [];
    const want = Math.ceil(Math.max(until, 0) * RATE);
    rig.cache.ensure(Math.min(want, rig.cache.count + most - 1));
    return rig.cache.count > want ? rig.cache.spans() : null;
  }
}
