import { describe, expect, it } from 'vitest';
import {
  boundingBox, clampLensInto, clampRadius, lensAfterResize, LENS_BORDER_PX, lensBounds, lensHit, lensInDevicePixels, MIN_LENS_RADIUS, moveLens,
  resizeLensTo, scaleLens, twoFingerLens, wheelFactor,
} from '../../../plugin/src/math/lens';

const lens = { x: 100, y: 80, radius: 50 };

describe('lensHit', () => {
  it.each([
    // [x, y, expected]: distance from the centre along +x
    [100, 80, 'inside'], [141, 80, 'inside'], [141.9, 80, 'inside'],
    [142, 80, 'border'], [150, 80, 'border'], [158, 80, 'border'],
    [158.1, 80, 'outside'], [300, 80, 'outside'],
    [100, 80 - 50, 'border'], [100 + 20, 80 + 20, 'inside'], [100 + 40, 80 + 40, 'border'], [100 + 42, 80 + 42, 'outside'],
  ] as const)('(%f, %f) → %s', (x, y, hit) => {
    expect(lensHit(lens, x, y)).toBe(hit);
  });

  it('uses ±8 CSS px by default and takes another band', () => {
    expect(LENS_BORDER_PX).toBe(8);
    expect(lensHit(lens, 100 + 50 + 3, 80, 2)).toBe('outside');
    expect(lensHit(lens, 100 + 50 - 3, 80, 2)).toBe('inside');
  });
});

describe('lens moves and sizes', () => {
  it('moves by a delta', () => {
    expect(moveLens(lens, 5, -7)).toEqual({ x: 105, y: 73, radius: 50 });
  });

  it('resizes so the border follows the pointer, within limits', () => {
    expect(resizeLensTo(lens, 100, 80 + 70).radius).toBe(70);
    expect(resizeLensTo(lens, 101, 80).radius).toBe(MIN_LENS_RADIUS);
    expect(clampRadius(Number.NaN)).toBe(MIN_LENS_RADIUS);
  });

  it('scales by a factor, and wheel steps are ±10 %', () => {
    expect(scaleLens(lens, 2).radius).toBe(100);
    expect(scaleLens(lens, -1).radius).toBe(50);
    expect(wheelFactor(1)).toBeCloseTo(1.1);
    expect(wheelFactor(-3)).toBeCloseTo(1 / 1.1);
    expect(wheelFactor(0)).toBe(1);
  });

  it('follows two fingers: midpoint moves the centre, distance scales the radius', () => {
    const moved = twoFingerLens(lens, { x: 90, y: 80, distance: 40 }, { x: 120, y: 60, distance: 60 });
    expect(moved.x).toBe(130);
    expect(moved.y).toBe(60);
    expect(moved.radius).toBeCloseTo(75);
  });

  it('gives the bounding box and the device-pixel circle (y up)', () => {
    expect(lensBounds(lens)).toEqual([50, 30, 100, 100]);
    expect(boundingBox([[1, 5], [4, 2], [3, 3]], 1)).toEqual([0, 1, 5, 5]);
    expect(lensInDevicePixels(lens, 2, 600)).toEqual({ x: 200, y: 600 - 160, radius: 100 });
  });
});

describe('the lens on a resize', () => {
  const inside = (c: { x: number; y: number; radius: number }, w: number, h: number): boolean =>
    c.x - c.radius >= 0 && c.y - c.radius >= 0 && c.x + c.radius <= w && c.y + c.radius <= h;

  it('leaves a lens that fits alone', () => {
    expect(clampLensInto(lens, 640, 480)).toEqual(lens);
  });

  it('moves a lens partly outside back in, the least', () => {
    expect(clampLensInto({ x: 630, y: 20, radius: 50 }, 640, 480)).toEqual({ x: 590, y: 50, radius: 50 });
    expect(clampLensInto({ x: -500, y: 900, radius: 50 }, 640, 480)).toEqual({ x: 50, y: 430, radius: 50 });
  });

  it('shrinks a lens larger than the viewer, and keeps its other fields', () => {
    const big = { x: 10, y: 10, radius: 400, opacity: 0.5 };
    expect(clampLensInto(big, 640, 480)).toEqual({ x: 240, y: 240, radius: 240, opacity: 0.5 });
    const tiny = clampLensInto(big, 20, 20); // smaller than the smallest lens: centred
    expect(tiny).toEqual({ x: 10, y: 10, radius: MIN_LENS_RADIUS, opacity: 0.5 });
  });

  it('keeps the offset from the centre when a phone turns to landscape', () => {
    // 390×844 portrait, the lens at its initial place (the centre, a fifth of the short side)
    const portrait = { x: 195, y: 422, radius: 78 };
    const landscape = lensAfterResize(portrait, { width: 390, height: 844 }, { width: 844, height: 390 });
    expect(landscape).toEqual({ x: 422, y: 195, radius: 78 });
    expect(inside(landscape, 844, 390)).toBe(true);
    const low = lensAfterResize({ x: 100, y: 800, radius: 60 }, { width: 390, height: 844 },
      { width: 844, height: 390 });
    expect(inside(low, 844, 390)).toBe(true);
    expect(low.x).toBe(100 + 227); // the offset from the centre is kept where it fits
  });
});
