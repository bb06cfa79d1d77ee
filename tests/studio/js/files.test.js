// @ts-check
// The project dialog's offered name for a copy.
import test from 'node:test';
import assert from 'node:assert/strict';
import { copyName } from '../../../src/sketchanim/studio/web/js/filesdialog.js';

test('a copy is offered the project\'s stem and -copy', () => {
  assert.equal(copyName('show.sketchanim'), 'show-copy.sketchanim');
  assert.equal(copyName('Show.SKETCHANIM'), 'Show-copy.sketchanim');
  assert.equal(copyName(''), 'project-copy.sketchanim');
});
