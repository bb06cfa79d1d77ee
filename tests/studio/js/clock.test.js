// @ts-check
import test from 'node:test';
import assert from 'node:assert/strict';
import { Clock } from '../../../src/sketchanim/studio/web/js/clock.js';

test('a running clock maps the browser clock to transport time at its speed', () => {
  const c = new Clock();
  c.seek(2, 1000);
  assert.equal(c.tick(1500).time, 2);           // paused
  c.play(1500);
  c.setSpeed(0.5, 1500);
  assert.equal(c.tick(2500).time, 2.5);
  c.pause(3500);
  assert.equal(c.tick(9000).time, 3);
});

test('the loop range wraps and re-anchors, stopping at the end otherwise', () => {
  const c = new Clock();
  c.loop = [1, 3];
  c.seek(2.5, 0);
  c.play(0);
  const r = c.tick(1000);
  assert.ok(r.wrapped);
  assert.ok(Math.abs(r.time - 1.5) < 1e-12);
  assert.ok(Math.abs(c.tick(1250).time - 1.75) < 1e-12);
  c.loop = null;
  const s = c.tick(5000, [0, 3]);
  assert.ok(s.stopped && s.time === 3 && !c.playing);
});

test('backwards playback wraps into the loop and stops at the start', () => {
  const c = new Clock();
  c.setSpeed(-1, 0);
  c.seek(1.2, 0);
  c.play(0);
  c.loop = [1, 2];
  assert.ok(Math.abs(c.tick(500).time - 1.7) < 1e-12);
  c.loop = null;
  assert.equal(c.tick(5000, [0, 2]).time, 0);
});
