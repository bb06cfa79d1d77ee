// @ts-check
/**
 * A walker in the 3D view: its humanoid (walk.js `humanoid`) as a capsule figure -- a cylinder
 * for each bone, a sphere at each joint, a ball for the head -- in the pose rigs.js derives
 * (walk.js `worldPoints`), and its goal as a ground marker: a green ring on the floor with a
 * tick pointing where the body faces. The marker and the body both grab `<name>.goal` (the
 * viewport drags it in the ground plane). `behindText` words walk.js's `behind` spans.
 */
import * as THREE from 'three';
import { goalMaterial, grabMaterial, handleScale } from './chainview.js';
import * as walker from './walk.js';

/** The figure's colours: bones, joints, head. */
const COLOURS = { bone: 0xc7b08a, joint: 0xe8dcc6, head: 0xe8dcc6 };
/** The marker's ring (inner, outer radius, metres), its tick's length, the disc that grabs it. */
const MARKER = { inner: 0.24, outer: 0.3, tick: 0.22, grab: 0.34 };
const UP = new THREE.Vector3(0, 1, 0);

/** @typedef {ReturnType<typeof walker.humanoid>} Skeleton */

/**
 * What the animator is told where a walker's marker outran its fastest run.
 * @param {string} name
 * @param {[number, number, number][]} spans  (start s, end s, fastest path speed m/s)
 * @returns {string}
 *
 * @example
 * behindText('bob', [[1.2, 2, 9.14]]);
 * // 'bob falls behind its marker from 1.20 s to 2.00 s (the path goes 9.1 m/s, faster than it runs)'
 */
export function behindText(name, spans) {
  const when = spans.map(([a, b]) => `from ${a.toFixed(2)} s to ${b.toFixed(2)} s`).join(', ');
  const fastest = Math.max(...spans.map((s) => s[2]));
  return `${name} falls behind its marker ${when} (the path goes ${fastest.toFixed(1)} m/s, faster than it runs)`;
}

export class WalkerView {
  /**
   * @param {string} name
   * @param {THREE.Scene} scene where the marker goes (the figure is `root`'s, which the viewport adds)
   */
  constructor(name, scene) {
    this.name = name;
    this.root = new THREE.Group();
    this.root.name = name;
    /** the figure (hidden while there is no pose: the marker stays, to be grabbed) */
    this.figure = new THREE.Group();
    this.root.add(this.figure);
    this.bone = new THREE.MeshStandardMaterial({ color: COLOURS.bone, roughness: 0.6 });
    this.jointMaterial = new THREE.MeshStandardMaterial({ color: COLOURS.joint, roughness: 0.5 });
    this.cylinder = new THREE.CylinderGeometry(1, 1, 1, 12);
    this.sphere = new THREE.SphereGeometry(1, 16, 10);
    /** @type {Skeleton | null} */
    this.skeleton = null;
    /** @type {(THREE.Mesh | null)[]} a joint's bone from its parent (null: the root's) */
    this.bones = [];
    /** @type {THREE.Mesh[]} */
    this.joints = [];
    this.head = new THREE.Mesh(this.sphere, new THREE.MeshStandardMaterial({ color: COLOURS.head, roughness: 0.5 }));
    this.head.userData = { object: name, attr: 'goal' };
    this.figure.add(this.head);
    // the marker: a ring on the floor, a tick where the body faces, a flat disc grabs it
    this.goal = new THREE.Group();
    this.goal.name = `${name}.goal`;
    const over = goalMaterial();
    this.ring = new THREE.Mesh(new THREE.RingGeometry(MARKER.inner, MARKER.outer, 48), over);
    this.ring.rotation.x = -Math.PI / 2;
    this.facing = new THREE.Group();
    this.tick = new THREE.Mesh(new THREE.ConeGeometry(0.07, MARKER.tick, 3), over);
    this.tick.rotation.x = Math.PI / 2;               // the cone points along +z, flat on the floor
    this.tick.position.z = MARKER.outer + MARKER.tick / 2 - 0.02;
    this.tick.scale.set(1, 1, 0.25);
    this.facing.add(this.tick);
    this.disc = new THREE.Mesh(new THREE.CircleGeometry(MARKER.grab, 24), grabMaterial());
    this.disc.rotation.x = -Math.PI / 2;
    for (const m of [this.ring, this.tick, this.disc]) {
      m.renderOrder = 20;
      m.userData = { object: name, attr: 'goal', handle: true };
    }
    this.goal.add(this.ring, this.facing, this.disc);
    scene.add(this.goal);
    /** @type {Float64Array} the joints drawn last (world) */
    this.points = new Float64Array(0);
  }

  /** What the pointer grabs: the figure and the marker (both the goal). */
  get pick() {
    return [...this.bones.filter((b) => b !== null), ...this.joints, this.head, this.ring, this.tick, this.disc];
  }

  /**
   * Make the figure's meshes for `skeleton` (when it changed).
   * @param {Skeleton} skeleton
   */
  build(skeleton) {
    if (this.skeleton === skeleton) return;
    this.skeleton = skeleton;
    for (const m of [...this.bones, ...this.joints]) m?.removeFromParent();
    const data = { object: this.name, attr: 'goal' };
    this.bones = skeleton.parents.map((p) => {
      if (p < 0) return null;
      const m = new THREE.Mesh(this.cylinder, this.bone);
      m.userData = data;
      this.figure.add(m);
      return m;
    });
    this.joints = skeleton.names.map(() => {
      const m = new THREE.Mesh(this.sphere, this.jointMaterial);
      m.userData = data;
      this.figure.add(m);
      return m;
    });
  }

  /**
   * Draw the pose (null: the marker alone).
   * @param {Skeleton | null} skeleton
   * @param {import('./rigs.js').Pose | null} pose
   */
  show(skeleton, pose) {
    if (!skeleton || !pose || !pose.root) {
      this.figure.visible = false;
      return;
    }
    this.figure.visible = true;
    this.build(skeleton);
    const p = walker.worldPoints(skeleton, pose.rotations, pose.root);
    this.points = p;
    const height = Math.max(...Array.from({ length: p.length / 3 }, (_, i) => p[i * 3 + 1])) - Math.min(...Array.from({ length: p.length / 3 }, (_, i) => p[i * 3 + 1]));
    const r = Math.max(height, 0.5) * 0.022;
    const a = new THREE.Vector3();
    const b = new THREE.Vector3();
    skeleton.parents.forEach((parent, j) => {
      this.joints[j].position.set(p[j * 3], p[j * 3 + 1], p[j * 3 + 2]);
      this.joints[j].scale.setScalar(r * 1.3);
      if (parent < 0) return;
      a.set(p[parent * 3], p[parent * 3 + 1], p[parent * 3 + 2]);
      b.set(p[j * 3], p[j * 3 + 1], p[j * 3 + 2]);
      const bone = /** @type {THREE.Mesh} */ (this.bones[j]);
      const length = a.distanceTo(b);
      bone.visible = length > 1e-6;
      bone.position.copy(a).add(b).multiplyScalar(0.5);
      if (bone.visible) bone.quaternion.setFromUnitVectors(UP, b.sub(a).normalize());
      bone.scale.set(r, length, r);
    });
    const head = skeleton.names.indexOf('head');
    this.head.visible = head >= 0;
    if (head >= 0) {
      this.head.position.set(p[head * 3], p[head * 3 + 1] + height * 0.05, p[head * 3 + 2]);
      this.head.scale.setScalar(height * 0.065);
    }
    // the tick: where the hips face (+z at rest), on the floor
    const q = pose.rotations;
    const forward = new THREE.Vector3(0, 0, 1).applyQuaternion(new THREE.Quaternion(q[0], q[1], q[2], q[3]));
    if (Math.hypot(forward.x, forward.z) > 1e-6) this.facing.rotation.y = Math.atan2(forward.x, forward.z);
  }

  /**
   * Each frame: the marker at least HANDLE_PX wide (chainview.js).
   * @param {number} pixel scene units a pixel spans at the marker
   */
  fit(pixel) {
    this.goal.scale.setScalar(handleScale(MARKER.outer, pixel));
  }

  /**
   * The bones of `skeleton` in `pose`, end to end (an onion skin ghost).
   * @param {Skeleton} skeleton
   * @param {import('./rigs.js').Pose} pose
   * @returns {number[]} pairs of points, xyz each
   */
  static segments(skeleton, pose) {
    const p = walker.worldPoints(skeleton, pose.rotations, /** @type {Float64Array} */ (pose.root));
    return skeleton.parents.flatMap((parent, j) => (parent < 0 ? []
      : [p[parent * 3], p[parent * 3 + 1], p[parent * 3 + 2], p[j * 3], p[j * 3 + 1], p[j * 3 + 2]]));
  }

  /** The walker's joints in the world, for tests. */
  world() {
    const p = this.points;
    return Array.from({ length: p.length / 3 }, (_, i) => [p[i * 3], p[i * 3 + 1], p[i * 3 + 2]]);
  }

  dispose() {
    this.root.removeFromParent();
    this.goal.removeFromParent();
  }
}
