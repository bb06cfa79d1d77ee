// @ts-check
/**
 * The inspector: the selected object's attributes. Numbers for positions, scales and
 * orientations (shown as XYZ Euler angles in degrees); sliders for the other floats
 * (intensity, field of view, any float attribute) and a colour picker for colours: a
 * drag of one is a hold of its attribute, so in record mode it records a take of it.
 * A click on an attribute's name shows it in the curve view. Under each continuous
 * attribute, the tolerance its takes are recorded within: empty for what the input
 * resolves (resolution.js: 2 px for a pointer), or an amount in input steps (px) or in the
 * attribute's units; the project keeps it. A chain's `lengths`, `limits` and `hinges` (8 slots
 * each) show as one table of its joints: a row per joint in use (length, limit in degrees, hinge
 * or ball) and one empty row to add a joint; a length of 0 removes that joint and those after
 * it. In a read-only project the fields are disabled.
 */
import * as THREE from 'three';
import { el } from './dom.js';
import { DEFAULT_STEPS, PICKER_STEP, sliderPerPixel } from './resolution.js';

/** Slider ranges by attribute type. */
const RANGES = { intensity: [0, 5, 0.01], fov: [10, 120, 0.1] };
const LABELS = { position: 'x y z', goal: 'x y z', scale: 'x y z', orientation: 'x° y° z°' };
/** A chain's structure attributes (anim/scene.py KINDS["chain"]), shown as one joints table. */
const JOINTS = ['lengths', 'limits', 'hinges'];
/** The fewest joints a chain has (anim/scene.py CHAIN_SLOTS' leading positive lengths: 2 to 8). */
const MIN_JOINTS = 2;

/**
 * How many joints a chain's `lengths` use: its leading slots of positive length.
 * @param {number[]} lengths
 *
 * @example
 * jointsUsed([0.5, 0.4, 0, 0.3]);   // 2
 */
export function jointsUsed(lengths) {
  let n = 0;
  while (n < lengths.length && lengths[n] > 0) n += 1;
  return n;
}

/**
 * A chain's `lengths` with slot `i` set to `x`: a length of 0 (or less) ends the chain there
 * (the slots after it cleared too), a slot past the end joins the chain's end.
 * @param {number[]} lengths
 * @param {number} i
 * @param {number} x
 * @returns {number[]}
 *
 * @example
 * withLength([0.5, 0.4, 0.3, 0], 1, 0);     // [0.5, 0, 0, 0]
 * withLength([0.5, 0.4, 0, 0], 2, 0.25);    // [0.5, 0.4, 0.25, 0]
 */
export function withLength(lengths, i, x) {
  const next = [...lengths];
  if (x > 0) next[i] = x;
  else for (let j = i; j < next.length; j++) next[j] = 0;
  return next;
}

export class Inspector {
  /**
   * @param {import('./Studio.js').Studio} studio
   * @param {HTMLElement} root
   */
  constructor(studio, root) {
    this.studio = studio;
    this.head = el('div', { class: 'panel-head' }, 'Inspector');
    this.body = el('div', { class: 'inspector', 'data-testid': 'inspector' });
    root.append(this.head, this.body);
    /** @type {Map<string, () => void>} what refreshes each row from the current values */
    this.refreshers = new Map();
    this.lastRefresh = 0;
    const signals = studio.signals;
    for (const signal of /** @type {const} */ (['state', 'selection', 'tracks', 'attribute', 'tolerances', 'lock'])) signals.on(signal, () => this.show());
    signals.on('frame', (now) => {
      if (now - this.lastRefresh > 100) this.refresh(now);
    });
    signals.on('values', () => this.refresh(performance.now()));
  }

  /** @param {number} now */
  refresh(now) {
    this.lastRefresh = now;
    for (const refresh of this.refreshers.values()) refresh();
  }

  show() {
    const s = this.studio;
    this.refreshers.clear();
    const obj = s.selected ? s.objectOf(s.selected) : null;
    this.head.textContent = obj ? `${obj.name} · ${obj.kind}` : 'Inspector';
    if (!obj) {
      this.body.replaceChildren(el('p', { class: 'hint' }, 'Click an object in the view or the list to select it. Drag it to move it; turn REC on first to record the move.'));
      return;
    }
    const chain = obj.kind === 'chain';
    this.body.replaceChildren(...obj.attributes.flatMap((a) => {
      if (chain && JOINTS.includes(a.name)) return a.name === JOINTS[0] ? [this.joints(obj.name)] : [];
      return a.type.continuous
        ? [this.row(obj.name, a.name, a.type), this.toleranceRow(`${obj.name}.${a.name}`, a.type)]
        : [this.row(obj.name, a.name, a.type)];
    }));
    for (const field of this.body.querySelectorAll('input, select')) {
      /** @type {HTMLInputElement | HTMLSelectElement} */ (field).disabled = s.readOnly;
    }
  }

  /**
   * The tolerance takes of `path` are recorded within: an amount (empty: the input's
   * resolution, DEFAULT_STEPS steps) in input steps or the attribute's units.
   * @param {string} path
   * @param {import('./messages.js').AttrType} type
   */
  toleranceRow(path, type) {
    const s = this.studio;
    const row = el('div', { class: 'row tol', 'data-path': path, title: `The tolerance takes of ${path} are recorded within; empty: ${DEFAULT_STEPS} px (steps) of what the input resolves` });
    const label = el('span', { class: 'attr' }, 'tol');
    const amount = el('input', { type: 'number', min: '0', step: 'any', placeholder: String(DEFAULT_STEPS), 'data-testid': `tol-${path}` });
    const unit = el('select', { 'data-testid': `tol-unit-${path}` });
    unit.append(el('option', { value: 'px' }, type.name === 'color' ? 'steps' : 'px'), el('option', { value: 'units' }, type.unit || 'units'));
    const setting = s.tolerances.get(path);
    amount.value = setting ? String(setting.amount) : '';
    unit.value = setting ? setting.unit : 'px';
    const send = () => {
      const x = Number(amount.value);
      if (amount.value.trim() === '') s.setTolerance(path, null);
      else if (x > 0 && Number.isFinite(x)) s.setTolerance(path, { amount: x, unit: /** @type {'px' | 'units'} */ (unit.value) });
      else amount.setCustomValidity('a tolerance is a number > 0');
    };
    amount.addEventListener('input', () => amount.setCustomValidity(''));
    amount.addEventListener('change', send);
    unit.addEventListener('change', () => { if (amount.value.trim() !== '') send(); });
    const wrap = el('div', { class: 'numbers' });
    wrap.append(amount, unit);
    row.append(label, wrap);
    return row;
  }

  /**
   * @param {string} name
   * @param {string} attr
   * @param {import('./messages.js').AttrType} type
   */
  row(name, attr, type) {
    const s = this.studio;
    const path = `${name}.${attr}`;
    const row = el('div', { class: 'row', 'data-path': path });
    const animated = s.tracks.has(path);
    const label = el('button', { class: `attr${attr === s.attribute ? ' shown' : ''}`, title: type.continuous ? `Show ${path} in the curve view` : path },
      `${animated ? '● ' : ''}${attr}`);
    label.classList.toggle('animated', animated);
    if (type.continuous) {
      label.addEventListener('click', () => s.showAttribute(attr));
    }
    row.append(label);
    const editor = this.editor(path, attr, type);
    row.append(editor);
    return row;
  }

  /**
   * A chain's joints, a row each (length, limit, hinge), and an empty row to add one: an edit
   * is one undoable step of the attribute it changes (a length of 0 on the first two joints is refused: a chain has two at least).
   * @param {string} name
   */
  joints(name) {
    const s = this.studio;
    const [lengths, limits, hinges] = JOINTS.map((a) => `${name}.${a}`);
    const table = el('div', { class: 'joints', 'data-testid': `joints-${name}`,
      title: 'The chain from its base: each joint\'s segment length, how far it turns from rest (degrees), hinge (turns about its x axis) or ball' });
    const used = jointsUsed(s.values.get(lengths));
    const slots = Math.min(used + 1, s.values.get(lengths).length);
    table.append(el('span', { class: 'attr' }, 'joint'), el('span', { class: 'attr' }, 'length'),
      el('span', { class: 'attr' }, 'limit°'), el('span', { class: 'attr' }, 'hinge'));
    /** @type {(() => void)[]} */
    const refresh = [];
    for (let i = 0; i < slots; i++) {
      const spare = i >= used;
      const length = /** @type {HTMLInputElement} */ (el('input', { type: 'number', min: '0', step: '0.05', 'data-testid': `edit-${lengths}-${i}`,
        placeholder: spare ? 'add' : '' }));
      const limit = /** @type {HTMLInputElement} */ (el('input', { type: 'number', min: '0.1', max: '180', step: '5', 'data-testid': `edit-${limits}-${i}` }));
      const hinge = /** @type {HTMLInputElement} */ (el('input', { type: 'checkbox', 'data-testid': `edit-${hinges}-${i}`,
        title: 'hinge (turns about its x axis); unticked: a ball joint' }));
      limit.disabled = spare;
      hinge.disabled = spare;
      length.addEventListener('change', () => {
        const x = Number(length.value);
        if (length.value.trim() === '' && spare) return;
        if (!Number.isFinite(x)) return;
        if (x <= 0 && i < MIN_JOINTS) {                 // ik.js chainFromSlots: 2 joints at least
          length.setCustomValidity(`a chain has ${MIN_JOINTS} joints at least`);
          length.reportValidity();
          return;
        }
        length.setCustomValidity('');
        s.set(lengths, withLength(s.values.get(lengths), i, x), `set ${lengths}`);
      });
      limit.addEventListener('change', () => {
        const x = Number(limit.value);
        if (!(x > 0 && x <= 180)) { limit.setCustomValidity('a limit is more than 0 and at most 180 degrees'); limit.reportValidity(); return; }
        limit.setCustomValidity('');
        s.set(limits, s.values.get(limits).map((/** @type {number} */ v, /** @type {number} */ j) => (j === i ? x : v)), `set ${limits}`);
      });
      hinge.addEventListener('change', () => {
        s.set(hinges, s.values.get(hinges).map((/** @type {number} */ v, /** @type {number} */ j) => (j === i ? (hinge.checked ? 1 : 0) : v)), `set ${hinges}`);
      });
      refresh.push(() => {
        if (document.activeElement !== length) length.value = spare ? '' : Number(s.values.get(lengths)[i]).toFixed(2);
        if (document.activeElement !== limit) limit.value = spare ? '' : String(Number(s.values.get(limits)[i]));
        hinge.checked = !spare && s.values.get(hinges)[i] > 0.5;
      });
      table.append(el('span', { class: 'joint-index' }, spare ? '+' : String(i + 1)), length, limit, hinge);
    }
    this.refreshers.set(lengths, () => {
      if (jointsUsed(s.values.get(lengths)) !== used) queueMicrotask(() => this.show());     // a joint came or went
      else for (const r of refresh) r();
    });
    this.refreshers.get(lengths)?.();
    return table;
  }

  /**
   * A bool toggled or an enum value picked: while the transport plays, or once the attribute
   * has a track, it is keyed at the transport's time of the input event (performed); else set.
   * @param {string} path
   * @param {boolean | string} value
   * @param {number} stamp the input event's timeStamp
   */
  change(path, value, stamp) {
    const s = this.studio;
    if (s.transport.clock.playing || s.tracks.has(path)) s.key(path, value, stamp);
    else s.set(path, value, `set ${path}`);
  }

  /**
   * @param {string} path
   * @param {string} attr
   * @param {import('./messages.js').AttrType} type
   * @returns {HTMLElement}
   */
  editor(path, attr, type) {
    const s = this.studio;
    const value = () => s.values.get(path);
    if (type.name === 'bool') {
      const box = /** @type {HTMLInputElement} */ (el('input', { type: 'checkbox', 'data-testid': `edit-${path}` }));
      box.addEventListener('change', (e) => this.change(path, box.checked, e.timeStamp));
      this.refreshers.set(path, () => { box.checked = !!value(); });
      return box;
    }
    if (type.name === 'enum') {
      const select = /** @type {HTMLSelectElement} */ (el('select', { 'data-testid': `edit-${path}` }));
      for (const c of type.choices) select.append(el('option', { value: c }, c));
      select.addEventListener('change', (e) => this.change(path, select.value, e.timeStamp));
      this.refreshers.set(path, () => { if (document.activeElement !== select) select.value = value(); });
      return select;
    }
    if (type.name === 'event') {
      const hint = el('span', { class: 'hint', title: 'Cues fire as playback passes them; M marks one on the selected object at the transport time' });
      this.refreshers.set(path, () => {
        const n = /** @type {import('./evaluate.js').Steps | undefined} */ (s.tracks.get(path))?.times.length ?? 0;
        hint.textContent = `${n ? `${n} cue${n === 1 ? '' : 's'} · ` : ''}M marks one`;
      });
      this.refreshers.get(path)?.();
      return hint;
    }
    if (!type.continuous) return el('span', { class: 'hint' }, type.name);
    if (type.name === 'color') return this.colour(path);
    if (type.dim === 1) return this.slider(path, type);
    return this.numbers(path, attr, type);
  }

  /**
   * A slider and its number: a drag is a hold (a take in record mode).
   * @param {string} path
   * @param {import('./messages.js').AttrType} type
   */
  slider(path, type) {
    const s = this.studio;
    const v = s.values.get(path)[0];
    const [lo, hi, step] = RANGES[/** @type {keyof RANGES} */ (type.name)]
      ?? [Math.min(0, Math.floor(v - 1)), Math.max(1, Math.ceil(v + 1)), 0.001];
    const wrap = el('div', { class: 'slider' });
    const range = /** @type {HTMLInputElement} */ (el('input', { type: 'range', min: String(lo), max: String(hi), step: String(step), 'data-testid': `slider-${path}` }));
    const readout = el('span', { class: 'num' });
    const resolve = () => ({ [path]: { step: sliderPerPixel(Number(range.min), Number(range.max), Math.max(range.clientWidth, 1)), input: 'px' } });
    range.addEventListener('pointerdown', () => s.performer.hold([path], `slide ${path}`, null, resolve));
    range.addEventListener('input', (e) => {
      if (!s.performer.grab) s.performer.hold([path], `slide ${path}`, null, resolve);        // the keyboard
      s.setLocal(path, [Number(range.value)]);
      s.performer.mark(e.timeStamp);
    });
    const done = () => { if (s.performer.grab?.paths[0] === path) s.performer.release(); };
    range.addEventListener('pointerup', done);
    range.addEventListener('change', done);
    range.addEventListener('lostpointercapture', done);
    this.refreshers.set(path, () => {
      const x = s.values.get(path)[0];
      if (s.performer.grab?.paths[0] !== path) range.value = String(x);
      readout.textContent = `${x.toFixed(type.name === 'fov' ? 1 : 2)}${type.unit === 'degrees' ? '°' : ''}`;
    });
    this.refreshers.get(path)?.();
    wrap.append(range, readout);
    return wrap;
  }

  /**
   * A colour picker (linear RGB in the model, sRGB in the picker).
   * @param {string} path
   */
  colour(path) {
    const s = this.studio;
    const picker = /** @type {HTMLInputElement} */ (el('input', { type: 'color', 'data-testid': `color-${path}` }));
    const c = new THREE.Color();
    const resolve = () => ({ [path]: { step: PICKER_STEP, input: 'step' } });
    picker.addEventListener('input', (e) => {
      if (!s.performer.grab) s.performer.hold([path], `colour ${path}`, null, resolve);
      c.set(picker.value);
      s.setLocal(path, [c.r, c.g, c.b]);
      s.performer.mark(e.timeStamp);
    });
    picker.addEventListener('change', () => { if (s.performer.grab?.paths[0] === path) s.performer.release(); });
    this.refreshers.set(path, () => {
      const v = s.values.get(path);
      if (s.performer.grab?.paths[0] !== path) picker.value = `#${c.setRGB(v[0], v[1], v[2]).getHexString()}`;
    });
    this.refreshers.get(path)?.();
    return picker;
  }

  /**
   * Number fields (orientations as XYZ Euler degrees); an edit is one undoable step.
   * @param {string} path
   * @param {string} attr
   * @param {import('./messages.js').AttrType} type
   */
  numbers(path, attr, type) {
    const s = this.studio;
    const wrap = el('div', { class: 'numbers', title: LABELS[/** @type {keyof LABELS} */ (attr)] ?? '' });
    const n = type.name === 'orientation' ? 3 : type.dim;
    const fields = Array.from({ length: n }, (_, i) => {
      const f = /** @type {HTMLInputElement} */ (el('input', { type: 'number', step: type.name === 'orientation' ? '1' : '0.01', 'data-testid': `edit-${path}-${i}` }));
      f.addEventListener('change', () => {
        const xs = fields.map((g) => Number(g.value));
        if (!xs.every(Number.isFinite)) return;
        const value = type.name === 'orientation'
          ? new THREE.Quaternion().setFromEuler(new THREE.Euler(...xs.map(THREE.MathUtils.degToRad))).toArray()
          : xs;
        s.set(path, value, `set ${path}`);
      });
      return f;
    });
    const e = new THREE.Euler();
    this.refreshers.set(path, () => {
      const v = s.values.get(path);
      const xs = type.name === 'orientation'
        ? e.setFromQuaternion(new THREE.Quaternion(v[0], v[1], v[2], v[3])).toArray().slice(0, 3).map((r) => THREE.MathUtils.radToDeg(/** @type {number} */ (r)))
        : v;
      fields.forEach((f, i) => { if (document.activeElement !== f) f.value = Number(xs[i]).toFixed(type.name === 'orientation' ? 1 : 2); });
    });
    this.refreshers.get(path)?.();
    wrap.append(...fields);
    return wrap;
  }
}
