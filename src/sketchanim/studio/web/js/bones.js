// @ts-check
/**
 * Bones in the 3D view: a line from each object with a `parent` attribute (an imported clip's
 * joint, studio/clips.py) to the object it names, between the two objects' positions as drawn
 * now (playback, a grab, a take) — one three.js LineSegments whose vertices are rewritten every
 * frame. Which pairs to join is read again when the objects change (the `state` message).
 */
import * as THREE from 'three';

/** The attribute naming an object's parent object (anim/scene.py BONE_PARENT). */
const PARENT = 'parent';

export class Bones {
  /** @param {import('./viewport.js').Viewport} viewport */
  constructor(viewport) {
    this.viewport = viewport;
    this.studio = viewport.studio;
    /** @type {[string, string][]} child and parent object names */
    this.pairs = [];
    this.lines = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xd8dee9 }));
    this.lines.name = 'bones';
    this.lines.frustumCulled = false;
    viewport.scene.add(this.lines);
    this.studio.signals.on('state', () => this.build());
    this.studio.signals.on('frame', () => this.update());
  }

  /** The pairs of the objects there are; a fresh vertex buffer for them. */
  build() {
    const names = new Set(this.studio.objects.map((o) => o.name));
    this.pairs = this.studio.objects.flatMap((o) => o.attributes
      .filter((a) => a.name === PARENT && names.has(a.value))
      .map((a) => /** @type {[string, string]} */ ([o.name, a.value])));
    this.lines.geometry.dispose();
    this.lines.geometry = new THREE.BufferGeometry();
    this.lines.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(this.pairs.length * 6), 3));
    this.update();
  }

  /** Each bone's ends at its two objects' positions now (a hidden end: the bone collapsed). */
  update() {
    const position = /** @type {THREE.BufferAttribute} */ (this.lines.geometry.getAttribute('position'));
    if (!position) return;
    const nodes = this.viewport.nodes;
    this.pairs.forEach(([child, parent], i) => {
      const a = nodes.get(child)?.root;
      const b = nodes.get(parent)?.root;
      if (!a || !b) return;
      const end = a.visible && b.visible ? b.position : a.position;
      position.setXYZ(2 * i, a.position.x, a.position.y, a.position.z);
      position.setXYZ(2 * i + 1, end.x, end.y, end.z);
    });
    position.needsUpdate = true;
    this.lines.geometry.computeBoundingSphere();
  }

  /** What the tests read: each bone's child, parent and two ends. */
  report() {
    const position = this.lines.geometry.getAttribute('position');
    return this.pairs.map(([child, parent], i) => ({
      child, parent,
      from: [position.getX(2 * i), position.getY(2 * i), position.getZ(2 * i)],
      to: [position.getX(2 * i + 1), position.getY(2 * i + 1), position.getZ(2 * i + 1)],
    }));
  }
}
