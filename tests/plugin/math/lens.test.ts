import { describe, expect, it } from 'vitest';
import {
  boundingBox, clampRadius, LENS_BORDER_PX, lensBounds, lensHit, lensInDevicePixels, MIN_LENS_RADIUS, moveLens,
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
