import { describe, expect, it } from 'vitest';
import { freeArea, homeRegion } from '../../../plugin/src/demo/home-fit';

describe('freeArea', () => {
  it('is below the toolbar and left of a side panel', () => {
    const free = freeArea(1280, 800, { left: 8, top: 8, right: 700, bottom: 44 },
      { left: 1014, top: 8, right: 1272, bottom: 792 });
    expect(free).toEqual({ left: 0, top: 44, right: 1014, bottom: 800 });
  });

  it('is above a bottom sheet', () => {
    const free = freeArea(390, 844, { left: 8, top: 8, right: 382, bottom: 140 },
      { left: 0, top: 380, right: 390, bottom: 844 });
    expect(free).toEqual({ left: 0, top: 140, right: 390, bottom: 380 });
  });

  it('ignores a toolbar or panel that would leave too little room', () => {
    expect(freeArea(300, 100, { left: 0, top: 0, right: 300, bottom: 60 }, null))
      .toEqual({ left: 0, top: 0, right: 300, bottom: 100 });
  });
});

describe('homeRegion', () => {
  it('maps the image onto the free area, centred, for the whole viewer', () => {
    const free = { left: 0, top: 100, right: 400, bottom: 500 };
    const [x, y, w, h] = homeRegion(400, 800, free, 200, 100);
    const s = 400 / w; // CSS px per image px
    expect(h * s).toBeCloseTo(800);
    // image corners in CSS px of the viewer
    const left = (0 - x) * s;
    const right = (200 - x) * s;
    const top = (0 - y) * s;
    const bottom = (100 - y) * s;
    expect(left).toBeCloseTo(0);
    expect(right).toBeCloseTo(400);
    expect((top + bottom) / 2).toBeCloseTo(300);
    expect(bottom - top).toBeCloseTo(200);
  });
});
