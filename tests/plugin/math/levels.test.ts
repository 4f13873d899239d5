import { describe, expect, it } from 'vitest';
import { currentLevel, homeLevelOf, maxLevelOf } from '../../../plugin/src/math/levels';

describe('currentLevel (docs/annotations.md: clamp(H − floor(log2(zoom / homeZoom) + 1e-6), 0, H))', () => {
  it.each([
    // zoom / home zoom, expected level (home level 3)
    [1, 3], [1.5, 3], [1.999, 3], [2 - 1e-7, 2], [2, 2], [3.9, 2], [4, 1], [4 * (1 - 1e-7), 1],
    [7.99, 1], [8, 0], [16, 0], [1e6, 0],
  ])('zoom %f × home → level %i', (ratio, level) => {
    expect(currentLevel({ zoom: 0.7 * ratio, homeZoom: 0.7, homeLevel: 3 })).toBe(level);
  });

  it('shows the home level when zoomed out beyond home', () => {
    expect(currentLevel({ zoom: 0.5, homeZoom: 1, homeLevel: 3 })).toBe(3);
    expect(currentLevel({ zoom: 0.01, homeZoom: 1, homeLevel: 2 })).toBe(2);
  });

  it('depends only on the zoom relative to home, not on its unit', () => {
    for (const home of [0.001, 0.25, 1, 37]) {
      expect(currentLevel({ zoom: home * 4, homeZoom: home, homeLevel: 4 })).toBe(2);
    }
  });

  it('is 0 at home when the home level is 0', () => {
    expect(currentLevel({ zoom: 1, homeZoom: 1, homeLevel: 0 })).toBe(0);
  });

  it('falls back to the home level for unusable zooms', () => {
    expect(currentLevel({ zoom: 0, homeZoom: 1, homeLevel: 3 })).toBe(3);
    expect(currentLevel({ zoom: Number.NaN, homeZoom: 1, homeLevel: 3 })).toBe(3);
    expect(currentLevel({ zoom: 1, homeZoom: 0, homeLevel: 3 })).toBe(3);
    expect(currentLevel({ zoom: Infinity, homeZoom: 1, homeLevel: 3 })).toBe(0);
    expect(currentLevel({ zoom: 1, homeZoom: 1, homeLevel: -2 })).toBe(0);
  });
});

describe('homeLevelOf', () => {
  it('is the coarsest annotated level', () => {
    expect(homeLevelOf([0, 1, 2, 3], [1, 2, 4, 8, 16])).toBe(3);
    expect(homeLevelOf([2, 0], [1, 2, 4, 8])).toBe(2);
  });

  it("is the pyramid's coarsest level without an overlay", () => {
    expect(homeLevelOf([], [1, 2, 4, 8])).toBe(3);
    expect(homeLevelOf([], [])).toBe(0);
  });
});

describe('maxLevelOf', () => {
  it('reads the coarsest level from scale factors', () => {
    expect(maxLevelOf([1, 2, 4, 8])).toBe(3);
    expect(maxLevelOf([1])).toBe(0);
    expect(maxLevelOf([])).toBe(0);
  });
});
