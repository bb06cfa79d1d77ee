// @ts-check
/**
 * The 3D view: the scene drawn with three.js (floor grid, objects, lights, cameras), with
 * direct manipulation (press on an object and drag: it follows the pointer in the plane
 * facing the view), translate / rotate / scale gizmos (W, E, S), orbit / pan / zoom, a
 * gamepad or 3D mouse moving and turning the selected object (a rig's goal: moving it), and a preview of the scene
 * camera's view in a corner, with motion paths (motionpaths.js: their control points dragged
 * here take the pointer first) and onion skin (onionskin.js) over it. Chains and walkers
 * (chainview.js, walkerview.js) are drawn in the pose rigs.js derives from their goal: pressing
 * on a chain's goal handle drags `<name>.goal`, on its body its base (`<name>.position`); a
 * walker's marker and body both drag its goal, in the ground plane (the marker's height); the
 * translate gizmo moves a chain's base and a walker's goal (rigs have no rotate or scale).
 * A hold tells the performer what its input resolves (a pixel at the grabbed point's depth,
 * the gizmo's degrees or scale per pixel, the stick's step) and marks every pointer event that moved it (coalesced events included) with its time.
 */
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { TransformControls } from 'three/addons/controls/TransformControls.js';
import { Bones } from './bones.js';
import { ChainView } from './chainview.js';
import { active, applyPad, padResolution, readPad } from './gamepad.js';
import { MotionPaths } from './motionpaths.js';
import { OnionSkin } from './onionskin.js';
import { pixelWorld, turnPerPixel } from './resolution.js';
import { PLACED, Rigs } from './rigs.js';
import { ViewToggles } from './viewtoggles.js';
import { WalkerView, behindText } from './walkerview.js';

const PALETTE = [0xe07a5f, 0x81b29a, 0xf2cc8f, 0x6d9dc5, 0xb388eb, 0xf28482, 0x84a59d];
/** three.js intensity (candela) of a light of intensity 1: a clear pool of light on the floor. */
const LIGHT_SCALE = 6;
/** Real seconds a device rests before its hold (and take) ends. */
const PAD_REST = 0.3;

/**
 * @typedef {object} Node  What draws one scene object.
 * @property {string} name
 * @property {string} kind
 * @property {THREE.Object3D} root     carries position, orientation, scale
 * @property {THREE.Mesh[]} pick       what the pointer can grab
 * @property {THREE.SpotLight} [light]
 * @property {THREE.PerspectiveCamera} [camera]
 * @property {THREE.PerspectiveCamera} [frustum] a short copy of the camera, drawn by the helper
 * @property {THREE.CameraHelper} [helper]
 * @property {ChainView | WalkerView} [rig]  a chain's or a walker's drawing
 */

/** The least |y| of the pointer's ray (unit) for a walker's level drag plane (about 3°; a flatter view drags in the view's plane, on the ground). */
const LEVEL = 0.05;
/** Ticks of a walker's walk simulated ahead each frame (about 2 ms) until its goal's track is covered. */
const AHEAD = 24;

/** @param {string} shape */
function geometry(shape) {
  switch (shape) {
    case 'sphere': return new THREE.SphereGeometry(0.45, 32, 16);
    case 'cone': return new THREE.ConeGeometry(0.45, 0.9, 32);
    case 'cylinder': return new THREE.CylinderGeometry(0.4, 0.4, 0.9, 32);
    case 'torus': return new THREE.TorusGeometry(0.35, 0.14, 16, 48);
    default: return new THREE.BoxGeometry(0.8, 0.8, 0.8);
  }
}

/** Whether WebGL runs on a software rasteriser (SwiftShader, llvmpipe): no GPU to spare. */
function softwareGL() {
  const gl = document.createElement('canvas').getContext('webgl2');
  const info = gl?.getExtension('WEBGL_debug_renderer_info');
  const name = gl && info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : '';
  gl?.getExtension('WEBGL_lose_context')?.loseContext();
  return /swiftshader|llvmpipe|software/i.test(name);
}

export class Viewport {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} container
   */
  constructor(studio, container) {
    this.studio = studio;
    this.container = container;
    const software = softwareGL();                        // a CPU rasteriser: cheaper settings keep frames coming
    this.renderer = new THREE.WebGLRenderer({ antialias: !software });
    this.renderer.setPixelRatio(software ? 1 : Math.min(window.devicePixelRatio, 2));
    this.renderer.domElement.dataset.testid = 'viewport';
    container.appendChild(this.renderer.domElement);
    this.insetFrame = document.createElement('div');
    this.insetFrame.className = 'inset';
    this.insetFrame.hidden = true;
    container.appendChild(this.insetFrame);
    this.insetKey = '';
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x1b1e24);
    this.scene.add(new THREE.GridHelper(20, 20, 0x6a7180, 0x353a44));
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(20, 20), new THREE.MeshStandardMaterial({ color: 0x23272f, roughness: 1 }));
    floor.rotation.x = -Math.PI / 2;
    floor.position.y = -0.002;
    this.scene.add(floor);
    this.scene.add(new THREE.HemisphereLight(0xdde6ff, 0x2a2520, 0.6));
    const sun = new THREE.DirectionalLight(0xffffff, 0.35);
    sun.position.set(3, 8, 5);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.05, 500);
    this.camera.position.set(4.5, 3.5, 7);
    this.orbit = new OrbitControls(this.camera, this.renderer.domElement);
    this.orbit.enableDamping = false;
    this.transform = new TransformControls(this.camera, this.renderer.domElement);
    this.transform.setSize(0.8);
    this.scene.add(this.transform.getHelper());
    this.selection = new THREE.BoxHelper(new THREE.Object3D(), 0xffc640);
    this.selection.visible = false;
    this.scene.add(this.selection);
    /** @type {Map<string, Node>} */
    this.nodes = new Map();
    this.raycaster = new THREE.Raycaster();
    this.previewCamera = true;
    this.aimed = false;
    /** @type {{name: string, path: string, plane: THREE.Plane, offset: THREE.Vector3, x: number, y: number, ground: number | null} | null} */
    this.drag = null;
    /** @type {{idle: number} | null} the device's hold */
    this.pad = null;
    /** performance.now() clock time of the last pointer event on the canvas (the gizmo's moves are marked with it) */
    this.eventStamp = 0;
    this.drawn = 0;
    this.toggles = new ViewToggles(studio, container);
    this.paths = new MotionPaths(this, this.toggles);
    this.onion = new OnionSkin(this, this.toggles, (path) => this.paths.curveOf(path));
    this.rigs = new Rigs({
      curveOf: (path) => this.paths.curveOf(path),
      valueOf: (path) => studio.values.get(path),
      live: (path) => studio.performer.holds(path) || !!studio.remoteTake?.paths.includes(path),
    });
    /** @type {Map<string, string>} the notice told last, by walker (its `behind`) or rig structure (told again only when it changes) */
    this.told = new Map();
    studio.addSink((path, value) => this.apply(path, value));
    studio.signals.on('state', () => this.build());
    studio.signals.on('selection', () => this.showSelection());
    studio.signals.on('frame', () => this.poll());
    studio.signals.on('frame', (now) => this.pose(now));
    this.bones = new Bones(this);       // after build's 'state' handler: the nodes are there
    this.bind();
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  // -- the scene --------------------------------------------------------------------------

  build() {
    for (const node of this.nodes.values()) {
      node.root.removeFromParent();
      node.helper?.removeFromParent();
      node.rig?.dispose();
    }
    this.nodes.clear();
    this.rigs.keep(this.studio.objects);
    this.studio.objects.forEach((obj, i) => {
      if (obj.kind === 'cue') return;                     // a cue has no place in space (a sound's beats)
      const root = new THREE.Group();
      root.name = obj.name;
      /** @type {Node} */
      const node = { name: obj.name, kind: obj.kind, root, pick: [] };
      if (obj.kind === 'light') {
        const light = new THREE.SpotLight(0xffffff, 1, 0, Math.PI / 5, 0.4, 0);
        light.target.position.set(0, 0, -1);
        root.add(light, light.target);
        const bulb = new THREE.Mesh(new THREE.SphereGeometry(0.16, 24, 12), new THREE.MeshBasicMaterial({ color: 0xffffff }));
        const beam = new THREE.Mesh(new THREE.ConeGeometry(0.22, 0.4, 24, 1, true),
          new THREE.MeshBasicMaterial({ color: 0xffffff, wireframe: true, transparent: true, opacity: 0.5 }));
        beam.rotation.x = Math.PI / 2;
        beam.position.z = -0.25;
        root.add(bulb, beam);
        node.light = light;
        node.pick = [bulb, beam];
      } else if (obj.kind === 'camera') {
        const camera = new THREE.PerspectiveCamera(50, 16 / 9, 0.1, 100);
        root.add(camera);
        const body = new THREE.Mesh(new THREE.BoxGeometry(0.3, 0.22, 0.36), new THREE.MeshStandardMaterial({ color: 0x8a93a6 }));
        const lens = new THREE.Mesh(new THREE.CylinderGeometry(0.08, 0.1, 0.14, 20), new THREE.MeshStandardMaterial({ color: 0x30343c }));
        lens.rotation.x = Math.PI / 2;
        lens.position.z = -0.24;
        root.add(body, lens);
        node.camera = camera;
        const frustum = new THREE.PerspectiveCamera(50, 16 / 9, 0.1, 1.2);   // the helper's: a short frustum
        root.add(frustum);
        node.frustum = frustum;
        node.helper = new THREE.CameraHelper(frustum);
        this.scene.add(node.helper);
        node.pick = [body, lens];
      } else if (obj.kind === 'chain' || obj.kind === 'walker') {
        const rig = obj.kind === 'chain' ? new ChainView(obj.name, this.scene) : new WalkerView(obj.name, this.scene);
        node.rig = rig;
        node.root = rig.root;
      } else {
        const mesh = new THREE.Mesh(geometry('box'), new THREE.MeshStandardMaterial({ color: PALETTE[i % PALETTE.length], roughness: 0.55 }));
        root.add(mesh);
        node.pick = [mesh];
      }
      for (const mesh of node.pick) mesh.userData.object = obj.name;
      this.scene.add(node.root);
      this.nodes.set(obj.name, node);
      for (const a of obj.attributes) this.apply(`${obj.name}.${a.name}`, this.studio.values.get(`${obj.name}.${a.name}`));
    });
    if (!this.aimed) this.aim();
    this.pose(performance.now());
    this.showSelection();
  }

  /** Look at the box (or the scene's first object) from the front, once. */
  aim() {
    const node = this.nodes.get('box') ?? [...this.nodes.values()].find((n) => n.kind === 'object');
    if (!node) return;
    this.aimed = true;
    const target = node.root.position.clone();
    this.orbit.target.copy(target);
    this.camera.position.copy(target).add(new THREE.Vector3(4.5, 4, 8.5));
    this.camera.lookAt(target);
    this.orbit.update();
  }

  /**
   * Draw one value.
   * @param {string} path
   * @param {any} value
   */
  apply(path, value) {
    const dot = path.indexOf('.');
    const node = this.nodes.get(path.slice(0, dot));
    if (!node || value == null) return;
    const attr = path.slice(dot + 1);
    const root = node.root;
    if (attr === 'goal' && node.rig) node.rig.goal.position.set(value[0], value[1], value[2]);
    else if (attr === 'position') root.position.set(value[0], value[1], value[2]);
    else if (attr === 'orientation') root.quaternion.set(value[0], value[1], value[2], value[3]);
    else if (attr === 'scale') root.scale.set(value[0], value[1], value[2]);
    else if (attr === 'visible') root.visible = value;
    else if (attr === 'shape' && node.kind === 'object') {
      const mesh = node.pick[0];
      mesh.geometry.dispose();
      mesh.geometry = geometry(value);
    } else if (node.light && attr === 'color') {
      node.light.color.setRGB(value[0], value[1], value[2]);
      for (const mesh of node.pick) /** @type {THREE.MeshBasicMaterial} */ (mesh.material).color.setRGB(value[0], value[1], value[2]);
    } else if (node.light && attr === 'intensity') node.light.intensity = value[0] * LIGHT_SCALE;
    else if (node.light && attr === 'on') node.light.visible = value;
    else if (node.camera && attr === 'fov') {
      for (const cam of [node.camera, node.frustum]) {
        if (!cam) continue;
        cam.fov = value[0];
        cam.updateProjectionMatrix();
      }
    }
  }

  showSelection() {
    const node = this.studio.selected ? this.nodes.get(this.studio.selected) : null;
    if (node) {
      const target = this.gizmoTarget(node);
      if (target) this.transform.attach(target);
      else this.transform.detach();
      this.selection.setFromObject(node.root);
      this.selection.visible = true;
    } else {
      this.transform.detach();
      this.selection.visible = false;
    }
  }

  /**
   * What the gizmo moves of `node` in its mode: a rig's base or goal in translate mode only.
   * @param {Node} node
   * @returns {THREE.Object3D | null}
   */
  gizmoTarget(node) {
    if (!node.rig) return node.root;
    if (this.transform.mode !== 'translate') return null;
    return node.kind === 'walker' ? node.rig.goal : node.root;
  }

  // -- chains and walkers -----------------------------------------------------------------

  /**
   * Each frame: every rig in the pose rigs.js gives it at the transport's time (live while its
   * goal is performed).
   * @param {number} now performance.now()
   */
  pose(now) {
    const t = this.studio.transport.time;
    for (const node of this.nodes.values()) {
      const rig = node.rig;
      if (!rig) continue;
      const pose = this.rigs.poseAt(node.name, t, now);
      const state = this.rigs.rigs.get(node.name);
      const motion = state?.motion;
      this.tellOnce(`${node.name}#structure`, state?.error ? `${node.name} is drawn without its joints: ${state.error}` : '', node.kind);
      const pixel = this.pixelAt(rig.goal.position);
      if (rig instanceof ChainView) {
        rig.show(motion?.chain ?? null, pose);
        rig.face(this.camera, pixel);
      } else {
        rig.show(motion?.skeleton ?? null, pose);
        rig.fit(pixel);
        this.tellBehind(node.name);
      }
    }
  }

  /**
   * A notice when a walker's marker outruns its fastest run (once per change of what it says):
   * its walk simulated a second past its goal's track, AHEAD ticks a frame (no hitch after a take).
   * @param {string} name
   */
  tellBehind(name) {
    const curve = this.studio.tracks.get(`${name}.goal`);
    const spans = curve?.kind === 'curve' ? this.rigs.behindUntil(name, curve.end + 1, AHEAD) : [];
    if (!spans) return;
    this.tellOnce(name, spans.length ? behindText(name, spans) : '', 'walker');
  }

  /**
   * A warning notice of `text` under `key`, unless it is what was told there last ('': nothing to tell).
   * @param {string} key
   * @param {string} text
   * @param {string} source
   */
  tellOnce(key, text, source) {
    if (text && text !== this.told.get(key)) this.studio.tell('warning', text, source);
    this.told.set(key, text);
  }

  /**
   * What each rig shows now, for tests: its joints in the world, its goal, its pose.
   * @returns {{name: string, kind: string, points: number[][], goal: number[], rotations: number[], root: number[] | null}[]}
   */
  rigReport() {
    const t = this.studio.transport.time;
    return [...this.nodes.values()].flatMap((node) => {
      if (!node.rig) return [];
      const pose = this.rigs.poseAt(node.name, t, performance.now());
      return [{ name: node.name, kind: node.kind, points: node.rig.world(), goal: node.rig.goal.position.toArray(),
        rotations: pose ? Array.from(pose.rotations) : [], root: pose?.root ? Array.from(pose.root) : null }];
    });
  }

  /**
   * The page coordinates of a rig's goal handle (a chain's ball, a walker's marker), for tests and tools.
   * @param {string} name
   * @returns {{x: number, y: number} | null}
   */
  goalScreen(name) {
    const node = this.nodes.get(name);
    return node?.rig ? this.pageOf(node.rig.goal.getWorldPosition(new THREE.Vector3())) : null;
  }

  /**
   * The page coordinates of a rig's joint `i` (world points as rigReport lists them), for tests and tools.
   * @param {string} name
   * @param {number} i
   * @returns {{x: number, y: number} | null}
   */
  jointScreen(name, i) {
    const p = this.nodes.get(name)?.rig?.world()[i];
    return p ? this.pageOf(new THREE.Vector3(p[0], p[1], p[2])) : null;
  }

  // -- the pointer ------------------------------------------------------------------------

  bind() {
    const el = this.renderer.domElement;
    el.addEventListener('pointerdown', (e) => this.press(e), { capture: true });   // before the controls
    el.addEventListener('pointermove', (e) => { this.eventStamp = e.timeStamp; }, { capture: true });  // before the gizmo
    el.addEventListener('pointermove', (e) => this.move(e));
    el.addEventListener('pointerup', (e) => this.lift(e));
    el.addEventListener('pointercancel', (e) => { if (!this.paths.cancel()) this.lift(e); });
    this.transform.addEventListener('dragging-changed', (e) => { this.orbit.enabled = !e.value; });
    this.transform.addEventListener('mouseDown', () => {
      const name = this.studio.selected;
      const node = name ? this.nodes.get(name) : null;
      if (!name || !node) return;
      const mode = this.transform.mode;
      const attr = { translate: PLACED[/** @type {keyof PLACED} */ (node.kind)] ?? 'position', rotate: 'orientation', scale: 'scale' }[mode];
      const path = `${name}.${attr}`;
      this.studio.performer.hold([path], `${mode} ${name}`, null, () => ({ [path]: this.gizmoResolution(name, mode) }));
    });
    this.transform.addEventListener('objectChange', () => {
      const grab = this.studio.performer.grab;
      const node = this.studio.selected ? this.nodes.get(this.studio.selected) : null;
      if (!grab || !node) return;
      const r = this.transform.object ?? node.root;
      for (const path of grab.paths) {
        if (path.endsWith('.position') || path.endsWith('.goal')) this.studio.setLocal(path, r.position.toArray());
        if (path.endsWith('.orientation')) this.studio.setLocal(path, r.quaternion.toArray());
        if (path.endsWith('.scale')) this.studio.setLocal(path, r.scale.toArray());
      }
      this.studio.performer.mark(this.eventStamp);
    });
    this.transform.addEventListener('mouseUp', () => this.studio.performer.release());
  }

  /**
   * The gizmo's mode (W, E, S).
   * @param {'translate' | 'rotate' | 'scale'} mode
   */
  setGizmo(mode) {
    this.transform.setMode(mode);
    this.showSelection();                               // a rig has the translate gizmo alone
  }

  /** Show or hide the scene camera's view in the corner (C). */
  togglePreviewCamera() {
    this.previewCamera = !this.previewCamera;
  }

  /**
   * Scene units one CSS pixel spans at `point`'s depth in the view.
   * @param {THREE.Vector3} point
   */
  pixelAt(point) {
    const view = this.camera.getWorldDirection(new THREE.Vector3());
    const depth = Math.max(point.clone().sub(this.camera.position).dot(view), this.camera.near);
    return pixelWorld(this.camera.fov, Math.max(this.renderer.domElement.clientHeight, 1), depth);
  }

  /**
   * What a pixel of the gizmo's drag does to the object `name`: scene units (translate),
   * degrees (rotate: TransformControls' 20 / distance radians per unit), or scale (the
   * drag's ratio to its start point's distance from the centre).
   * @param {string} name
   * @param {'translate' | 'rotate' | 'scale'} mode
   * @returns {import('./resolution.js').Resolution}
   */
  gizmoResolution(name, mode) {
    const node = /** @type {Node} */ (this.nodes.get(name));
    const root = node.root;
    const centre = (this.gizmoTarget(node) ?? root).getWorldPosition(new THREE.Vector3());
    const pixel = this.pixelAt(centre);
    if (mode === 'rotate') return { step: turnPerPixel(pixel, Math.max(centre.distanceTo(this.camera.position), 1e-6)), input: 'px' };
    if (mode === 'scale') {
      const start = /** @type {{pointStart?: THREE.Vector3}} */ (/** @type {unknown} */ (this.transform)).pointStart;
      const reach = Math.max(start ? start.length() : 0, 20 * pixel);
      return { step: (Math.max(...root.scale.toArray().map(Math.abs)) * pixel) / reach, input: 'px' };
    }
    return { step: pixel, input: 'px' };
  }

  /** @param {PointerEvent} e */
  ray(e) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1, -((e.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    return this.raycaster;
  }

  /** @param {PointerEvent} e */
  press(e) {
    if (e.button !== 0 || this.transform.dragging) return;
    const meshes = [...this.nodes.values()].filter((n) => n.root.visible).flatMap((n) => (n.rig ? n.rig.pick : n.pick));
    const hits = this.ray(e).intersectObjects(meshes, false);
    const hit = hits.find((h) => h.object.userData.handle) ?? hits[0];     // a goal handle is drawn over everything: it is grabbed first
    // a control point's handle takes the press over the gizmo and the objects; in record mode (a take
    // is the object's) only where neither is
    const record = this.studio.transport.record;
    if ((!record || (!hit && this.transform.axis === null)) && this.paths.press(e)) {
      e.stopImmediatePropagation();
      return;
    }
    if (this.transform.axis !== null) return;
    this.downAt = { x: e.clientX, y: e.clientY };
    if (!hit) return;
    const name = hit.object.userData.object;
    const node = /** @type {Node} */ (this.nodes.get(name));
    const path = `${name}.${hit.object.userData.attr ?? 'position'}`;
    const at = new THREE.Vector3(...this.studio.values.get(path));
    // a walker's goal slides on the ground at the marker's height: the grabbed point (on the marker, or the
    // body) moves level, under the pointer, and the marker with it; anything else in the plane facing the view
    const level = node.kind === 'walker' && Math.abs(this.raycaster.ray.direction.y) > LEVEL;
    const plane = level ? new THREE.Plane(new THREE.Vector3(0, 1, 0), -hit.point.y)
      : new THREE.Plane().setFromNormalAndCoplanarPoint(this.camera.getWorldDirection(new THREE.Vector3()), hit.point);
    this.drag = { name, path, plane, offset: at.clone().sub(hit.point), x: e.clientX, y: e.clientY,
      ground: node.kind === 'walker' ? at.y : null };
    this.orbit.enabled = false;
    this.renderer.domElement.setPointerCapture(e.pointerId);
    if (this.studio.selected !== name) this.studio.select(name);
    this.studio.performer.hold([path], `move ${path.endsWith('.goal') ? path : name}`, null, () => ({ [path]: this.dragResolution() }));
    e.stopImmediatePropagation();
  }

  /**
   * A pixel at the grabbed point's depth, in scene units (the drag's plane faces the view).
   * @returns {import('./resolution.js').Resolution}
   */
  dragResolution() {
    const drag = this.drag;
    const value = drag ? this.studio.values.get(drag.path) : null;
    const point = drag && value ? new THREE.Vector3(...value).sub(drag.offset) : this.orbit.target.clone();
    return { step: this.pixelAt(point), input: 'px' };
  }

  /**
   * Every pointer event since the last (the coalesced ones where the browser has them)
   * moves the grabbed object and is marked with its own time.
   * @param {PointerEvent} e
   */
  move(e) {
    if (this.paths.move(e) || !this.drag) return;
    const events = typeof e.getCoalescedEvents === 'function' ? e.getCoalescedEvents() : [];
    for (const ev of events.length ? events : [e]) {
      const point = this.ray(ev).ray.intersectPlane(this.drag.plane, new THREE.Vector3());
      if (!point) continue;
      point.add(this.drag.offset);
      if (this.drag.ground !== null) point.y = this.drag.ground;      // a view too level for the ground plane: still on the ground
      this.studio.setLocal(this.drag.path, point.toArray());
      this.studio.performer.mark(ev.timeStamp);
    }
  }

  /** @param {PointerEvent} e */
  lift(e) {
    if (this.paths.lift()) {
      this.downAt = null;
      return;
    }
    if (this.drag) {
      this.drag = null;
      this.orbit.enabled = true;
      this.studio.performer.release();
    } else if (this.downAt && Math.hypot(e.clientX - this.downAt.x, e.clientY - this.downAt.y) < 4 && !this.transform.dragging && this.transform.axis === null) {
      this.studio.select(null);                         // a click on nothing
    }
    this.downAt = null;
  }

  /**
   * The page coordinates of an object's centre (a chain's base, a walker's marker; for tests and tools).
   * @param {string} name
   * @returns {{x: number, y: number} | null}
   */
  screenOf(name) {
    const node = this.nodes.get(name);
    const at = node?.rig && node.kind === 'walker' ? node.rig.goal : node?.root;      // a walker is where its marker is
    return at ? this.pageOf(at.getWorldPosition(new THREE.Vector3())) : null;
  }

  /**
   * The page coordinates of a point of the scene.
   * @param {THREE.Vector3} point
   * @returns {{x: number, y: number}}
   */
  pageOf(point) {
    const p = point.clone().project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height };
  }

  // -- a gamepad or 3D mouse ----------------------------------------------------------------

  /** Each frame: a device at work moves the selected object (a hold: a take in record mode). */
  poll() {
    const pads = navigator.getGamepads ? [...navigator.getGamepads()].filter(Boolean) : [];
    const pad = /** @type {Gamepad | undefined} */ (pads[0]);
    const name = this.studio.selected;
    const node = name ? this.nodes.get(name) : null;
    if (!pad || !name || !node) return;
    if (this.pad && this.pad.idle >= PAD_REST) {
      this.pad = null;
      this.studio.performer.release();
      return;
    }
    if (this.pad || this.studio.performer.grab || !active(readPad(pad))) return;
    const state = { idle: 0 };
    this.pad = state;
    // a rig's goal moves (a walker's on its ground: its height kept); an object moves and turns
    const moved = node.rig ? `${name}.goal` : `${name}.position`;
    const turned = node.rig ? null : `${name}.orientation`;
    const paths = turned ? [moved, turned] : [moved];
    const stick = padResolution();
    const resolve = () => ({ [moved]: { step: stick.position, input: 'step' },
      ...(turned ? { [turned]: { step: stick.orientation, input: 'step' } } : {}) });
    this.studio.performer.hold(paths, `steer ${name}`, (dt) => {
      const current = /** @type {Gamepad | undefined} */ ([...navigator.getGamepads()].filter(Boolean)[0]);
      const input = current ? readPad(current) : { move: [0, 0, 0], turn: [0, 0, 0] };
      state.idle = active(/** @type {any} */ (input)) ? 0 : state.idle + dt;
      const from = this.studio.values.get(moved);
      const next = applyPad(from, turned ? this.studio.values.get(turned) : [0, 0, 0, 1],
        /** @type {any} */ (input), dt, this.camera.quaternion.toArray());
      if (node.kind === 'walker') next.position[1] = from[1];
      this.studio.setLocal(moved, next.position);
      if (turned) this.studio.setLocal(turned, next.orientation);
    }, resolve);
  }

  // -- drawing ------------------------------------------------------------------------------

  /**
   * Frame and name the camera preview (an element over the canvas).
   * @param {{left: number, top: number, width: number, height: number} | null} box
   * @param {string} name
   */
  showInset(box, name) {
    const key = box ? `${box.left},${box.top},${box.width},${box.height},${name}` : '';
    if (key === this.insetKey) return;
    this.insetKey = key;
    this.insetFrame.hidden = !box;
    if (!box) return;
    Object.assign(this.insetFrame.style, { left: `${box.left}px`, top: `${box.top}px`, width: `${box.width}px`, height: `${box.height}px` });
    this.insetFrame.textContent = `${name} view (C hides)`;
  }

  resize() {
    const w = Math.max(this.container.clientWidth, 1);
    const h = Math.max(this.container.clientHeight, 1);
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  render() {
    const r = this.renderer;
    const size = r.getSize(new THREE.Vector2());
    if (this.selection.visible) {
      const node = this.studio.selected ? this.nodes.get(this.studio.selected) : null;
      if (node) this.selection.setFromObject(node.root);
    }
    for (const node of this.nodes.values()) node.helper?.update();
    r.setScissorTest(false);
    r.setViewport(0, 0, size.x, size.y);
    r.render(this.scene, this.camera);
    const cam = [...this.nodes.values()].find((n) => n.camera);
    if (this.previewCamera && cam?.camera) {
      const w = Math.round(size.x * 0.26);
      const h = Math.round(w / cam.camera.aspect);
      const x = size.x - w - 12;
      const y = 12;
      r.setScissorTest(true);
      r.setScissor(x, y, w, h);
      r.setViewport(x, y, w, h);
      const rigs = [...this.nodes.values()].flatMap((n) => (n.rig instanceof ChainView ? [n.rig.goal, n.rig.line] : n.rig ? [n.rig.goal] : []));
      const hidden = [cam.helper, this.transform.getHelper(), this.selection, cam.root, this.paths.group, this.onion.group, ...rigs];
      const was = hidden.map((o) => o?.visible);
      hidden.forEach((o) => o && (o.visible = false));
      r.render(this.scene, cam.camera);
      hidden.forEach((o, i) => o && (o.visible = /** @type {boolean} */ (was[i])));
      r.setScissorTest(false);
      this.showInset({ left: x, top: size.y - y - h, width: w, height: h }, cam.name);
    } else this.showInset(null, '');
    this.drawn += 1;
  }
}
