import { describe, expect, it } from 'vitest';
import { currentLevel, imagePxPerDevicePx, maxLevelOf } from '../../../plugin/src/math/levels';

describe('currentLevel (docs/annotations.md: clamp(floor(log2(s) + 1e-6), 0, maxLevel))', () => {
  it.each([
    // s = image px per device px, expected level (maxLevel 4)
    [0.25, 0], [0.5, 0], [0.999, 0], [1, 0], [1.5, 0], [1.999, 0],
    [2, 1], [2 - 1e-7, 1], [3, 1], [3.999, 1], [4, 2], [4 * (1 - 1e-7), 2], [7.9, 2], [8, 3], [16, 4], [64, 4],
  ])('s = %f → level %i', (s, level) => {
    expect(currentLevel(s, 4)).toBe(level);
  });

  it('clamps to the pyramid', () => {
    expect(currentLevel(1024, 0)).toBe(0);
    expect(currentLevel(1024, 3)).toBe(3);
    expect(currentLevel(Infinity, 3)).toBe(3);
    expect(currentLevel(0, 3)).toBe(0);
    expect(currentLevel(Number.NaN, 3)).toBe(0);
  });

  it('takes s from the image zoom and the device pixel ratio', () => {
    // zoom 1/2 (one CSS px per two image px) on a DPR-2 screen: one device px per image px
    expect(imagePxPerDevicePx(0.5, 2)).toBe(1);
    expect(currentLevel(imagePxPerDevicePx(0.25, 1), 5)).toBe(2);
    expect(currentLevel(imagePxPerDevicePx(1 / 3, 1), 5)).toBe(1);
  });

  it('reads the coarsest level from scale factors', () => {
    expect(maxLevelOf([1, 2, 4, 8])).toBe(3);
    expect(maxLevelOf([1])).toBe(0);
    expect(maxLevelOf([])).toBe(0);
  });
});
