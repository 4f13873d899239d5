import { describe, expect, it } from 'vitest';
import { restoreCandidates, STANDARD_DRAWERS } from '../../../plugin/src/embed/host-drawer';

describe('the drawer a page gets back from attachLanterna', () => {
  it('is the standard drawer it had, then the others of WebGL and canvas', () => {
    expect(restoreCandidates('webgl')).toEqual(['webgl', 'canvas']);
    expect(restoreCandidates('canvas')).toEqual(['canvas', 'webgl']);
    expect(restoreCandidates('html')).toEqual(['html', 'webgl', 'canvas']);
  });

  it('is WebGL, else canvas, for a custom drawer or none', () => {
    for (const previous of ['lanterna', 'custom', '', null]) {
      expect(restoreCandidates(previous)).toEqual(['webgl', 'canvas']);
    }
  });

  it('never asks for a drawer that is not one of OpenSeadragon\'s own', () => {
    for (const previous of [...STANDARD_DRAWERS, 'lanterna', null]) {
      for (const type of restoreCandidates(previous)) {
        expect(STANDARD_DRAWERS).toContain(type);
      }
    }
  });
});
