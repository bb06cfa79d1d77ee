// @ts-check
/**
 * A chain in the 3D view: a base disc at its `position`, a cylinder per segment with a sphere at
 * each joint (the pose rigs.js derives, drawn from ik.js `points`), and its goal as a handle of
 * its own: a bright green ball in a ring that faces the view, drawn over everything, joined to the
 * chain's tip by a thin line (how far the tip is from the goal). Pressing on the goal grabs
 * `<name>.goal`; pressing on the body or the base grabs `<name>.position` (userData.attr).
 */
import * as THREE from 'three';
import * as ik from './ik.js';

/** The colours of a rig: the body, its joints, the goal (every rig's goal is this green), the tip line. */
export const RIG_COLOURS = { body: 0x9fb6d6, joint: 0xf2cc8f, base: 0x7d8aa0, goal: 0x3dff8f, line: 0x3dff8f };
/** Radius of the goal's ball, its ring, and the invisible ball that grabs it (scene units). */
const GOAL = { ball: 0.07, ring: 0.16, grab: 0.19 };
const UP = new THREE.Vector3(0, 1, 0);

/** The goal handle's look, shared by chains and walkers' markers: drawn over the scene. */
export function goalMaterial() {
  return new THREE.MeshBasicMaterial({ color: RIG_COLOURS.goal, depthTest: false, depthWrite: false, transparent: true });
}

/** CSS pixels a goal handle's ring spans at least, however far the view (it stays grabbable). */
export const HANDLE_PX = 10;

/**
 * The scale of a goal handle of `radius` scene units so that it spans HANDLE_PX pixels at least,
 * `pixel` scene units a pixel where it is (1: near enough already).
 * @param {number} radius
 * @param {number} pixel
 *
 * @example
 * handleScale(0.16, 0.001);   // 1
 * handleScale(0.16, 0.032);   // 2
 */
export function handleScale(radius, pixel) {
  return Math.max(1, (HANDLE_PX * pixel) / radius);
}

/** An invisible mesh material: what the pointer grabs around a thin handle. */
export function grabMaterial() {
  return new THREE.MeshBasicMaterial({ visible: false });
}

export class ChainView {
  /**
   * @param {string} name
   * @param {THREE.Scene} scene where the goal handle goes (the body is `root`'s, which the viewport adds)
   */
  constructor(name, scene) {
    this.name = name;
    this.root = new THREE.Group();
    this.root.name = name;
    this.body = new THREE.MeshStandardMaterial({ color: RIG_COLOURS.body, roughness: 0.6, emissive: 0x1c2533 });
    this.jointMaterial = new THREE.MeshStandardMaterial({ color: RIG_COLOURS.joint, roughness: 0.5, emissive: 0x2a2214 });
    this.base = new THREE.Mesh(new THREE.CylinderGeometry(0.2, 0.24, 0.05, 32), new THREE.MeshStandardMaterial({ color: RIG_COLOURS.base, roughness: 0.8 }));
    this.base.position.y = 0.025;
    this.base.userData = { object: name, attr: 'position' };
    this.root.add(this.base);
    this.cylinder = new THREE.CylinderGeometry(1, 1, 1, 16);
    this.sphere = new THREE.SphereGeometry(1, 20, 12);
    /** @type {THREE.Mesh[]} */
    this.segments = [];
    /** @type {THREE.Mesh[]} */
    this.joints = [];
    // the goal: a ball and a ring facing the view (drawn over the scene), a larger invisible ball grabs it
    this.goal = new THREE.Group();
    this.goal.name = `${name}.goal`;
    const over = goalMaterial();
    this.ball = new THREE.Mesh(new THREE.SphereGeometry(GOAL.ball, 20, 12), over);
    this.ring = new THREE.Mesh(new THREE.TorusGeometry(GOAL.ring, 0.016, 8, 48), over);
    this.grab = new THREE.Mesh(new THREE.SphereGeometry(GOAL.grab, 12, 8), grabMaterial());
    for (const m of [this.ball, this.ring, this.grab]) {
      m.renderOrder = 20;
      m.userData = { object: name, attr: 'goal', handle: true };
      this.goal.add(m);
    }
    scene.add(this.goal);
    this.line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
      new THREE.LineDashedMaterial({ color: RIG_COLOURS.line, dashSize: 0.05, gapSize: 0.04, depthTest: false, transparent: true, opacity: 0.8 }));
    this.line.renderOrder = 19;
    this.line.frustumCulled = false;
    scene.add(this.line);
    /** @type {Float64Array} the joints drawn last (base frame; base, joints, tip) */
    this.points = new Float64Array(0);
  }

  /** What the pointer grabs: the body and the base (the base's position), the goal handle (the goal). */
  get pick() {
    return [this.base, ...this.segments, ...this.joints, this.ball, this.ring, this.grab];
  }

  /**
   * Make the meshes of `count` segments (when the number of joints changed).
   * @param {number} count
   */
  resize(count) {
    if (this.segments.length === count) return;
    for (const m of [...this.segments, ...this.joints]) m.removeFromParent();
    this.segments = Array.from({ length: count }, () => new THREE.Mesh(this.cylinder, this.body));
    this.joints = Array.from({ length: count + 1 }, () => new THREE.Mesh(this.sphere, this.jointMaterial));
    for (const m of [...this.segments, ...this.joints]) {
      m.userData = { object: this.name, attr: 'position' };
      this.root.add(m);
    }
  }

  /**
   * Draw the pose (null: the structure is no chain: the base and the goal alone).
   * @param {ReturnType<typeof ik.chainFromSlots> | null} chain
   * @param {import('./rigs.js').Pose | null} pose
   */
  show(chain, pose) {
    if (!chain || !pose) {
      this.resize(0);
      this.points = new Float64Array(0);
      this.tip(this.root.position);
      return;
    }
    const n = chain.lengths.length;
    this.resize(n);
    const p = ik.points(chain, pose.rotations);
    this.points = p;
    const a = new THREE.Vector3();
    const b = new THREE.Vector3();
    for (let i = 0; i <= n; i++) {
      // a taper from base to tip: joints a little wider than their segments
      const r = 0.07 - (0.035 * i) / n;
      this.joints[i].position.set(p[i * 3], p[i * 3 + 1], p[i * 3 + 2]);
      this.joints[i].scale.setScalar(r * 1.35);
      if (i === n) break;
      a.set(p[i * 3], p[i * 3 + 1], p[i * 3 + 2]);
      b.set(p[i * 3 + 3], p[i * 3 + 4], p[i * 3 + 5]);
      const seg = this.segments[i];
      const length = a.distanceTo(b);
      seg.position.copy(a).add(b).multiplyScalar(0.5);
      seg.quaternion.setFromUnitVectors(UP, b.sub(a).normalize());
      seg.scale.set(r, length, r);
    }
    this.tip(new THREE.Vector3(p[n * 3], p[n * 3 + 1], p[n * 3 + 2]).add(this.root.position));
  }

  /**
   * The line from the chain's tip (world) to its goal.
   * @param {THREE.Vector3} tip
   */
  tip(tip) {
    const position = /** @type {THREE.BufferAttribute} */ (this.line.geometry.getAttribute('position'));
    position.setXYZ(0, tip.x, tip.y, tip.z);
    position.setXYZ(1, this.goal.position.x, this.goal.position.y, this.goal.position.z);
    position.needsUpdate = true;
    this.line.computeLineDistances();
  }

  /**
   * Each frame: the ring faces the view, at least HANDLE_PX wide; hidden with the chain.
   * @param {THREE.Camera} camera
   * @param {number} pixel scene units a pixel spans at the goal
   */
  face(camera, pixel) {
    this.ring.quaternion.copy(camera.quaternion);
    this.goal.scale.setScalar(handleScale(GOAL.ring, pixel));
    this.goal.visible = this.root.visible;
    this.line.visible = this.root.visible;
  }

  /**
   * The segments of `chain` in `pose` standing at `base` (world), end to end (an onion skin ghost).
   * @param {ReturnType<typeof ik.chainFromSlots>} chain
   * @param {import('./rigs.js').Pose} pose
   * @param {ArrayLike<number>} base
   * @returns {number[]} pairs of points, xyz each
   */
  static segments(chain, pose, base) {
    const p = ik.points(chain, pose.rotations);
    const out = [];
    for (let i = 0; i < chain.lengths.length; i++) {
      for (const j of [i, i + 1]) out.push(p[j * 3] + base[0], p[j * 3 + 1] + base[1], p[j * 3 + 2] + base[2]);
    }
    return out;
  }

  /** The chain's joints in the world (base, joints, tip), for tests. */
  world() {
    const o = this.root.position;
    return Array.from({ length: this.points.length / 3 }, (_, i) => [this.points[i * 3] + o.x, this.points[i * 3 + 1] + o.y, this.points[i * 3 + 2] + o.z]);
  }

  dispose() {
    this.root.removeFromParent();
    this.goal.removeFromParent();
    this.line.removeFromParent();
  }
}
