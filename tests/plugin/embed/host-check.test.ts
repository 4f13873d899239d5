import { describe, expect, it } from 'vitest';
import { hostProblem } from '../../../plugin/src/embed/host-check';

const viewer = (destroyed: boolean): object => ({ requestDrawer: () => false, isDestroyed: () => destroyed });

describe('which viewers attachLanterna takes', () => {
  it('takes a running OpenSeadragon 6 viewer', () => {
    expect(hostProblem(viewer(false), false)).toBeNull();
  });

  it('refuses what has no requestDrawer (not OpenSeadragon 6), in one line', () => {
    for (const v of [null, undefined, 'osd', {}, { requestDrawer: true }]) {
      expect(hostProblem(v, false)).toMatch(/^attachLanterna needs an OpenSeadragon 6 viewer \(.*requestDrawer\)$/);
    }
  });

  it('refuses a destroyed viewer and one that has Lanterna already', () => {
    expect(hostProblem(viewer(true), false)).toMatch(/has been destroyed/);
    expect(hostProblem(viewer(false), true)).toMatch(/already has Lanterna attached: destroy\(\) that one first/);
  });
});
