import { describe, expect, it } from 'vitest';
import { currentLevel, homeLevelOf, maxLevelOf, screenLevelOf } from '../../../plugin/src/math/levels';

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
  it('is the coarsest annotated level when that is coarser than the screen-sized level', () => {
    expect(homeLevelOf([0, 1, 2, 3], [1, 2, 4, 8, 16], 1536, 1152)).toBe(3);
    expect(homeLevelOf([2, 0], [1, 2, 4, 8], 800, 600)).toBe(2);
  });

  it('is the screen-sized level for a layer without an overlay, or with fine levels only', () => {
    expect(homeLevelOf([], [1, 2, 4, 8], 1536, 1152)).toBe(0); // 1536 px: level 0 is screen-sized
    expect(homeLevelOf([], [1, 2, 4, 8, 16, 32, 64, 128, 256], 60000, 40000)).toBe(5); // 1875 px
    expect(homeLevelOf([1], [1, 2, 4, 8, 16, 32, 64, 128, 256], 60000, 40000)).toBe(5);
    expect(homeLevelOf([], [], 100, 100)).toBe(0);
  });

  it('never moves when a patch is added at the level shown at some zoom', () => {
    const factors = [1, 2, 4, 8, 16, 32, 64, 128];
    for (const overlays of [[], [0], [2, 4], [6]]) {
      const home = homeLevelOf(overlays, factors, 30000, 20000);
      for (let finer = 0; finer <= home + 1; finer += 1) {
        const drawn = currentLevel({ zoom: 2 ** finer, homeZoom: 1, homeLevel: home });
        expect(homeLevelOf([...overlays, drawn], factors, 30000, 20000)).toBe(home);
      }
    }
  });

  it('stays within the pyramid', () => {
    expect(homeLevelOf([], [1, 2], 60000, 40000)).toBe(1);
    expect(homeLevelOf([5], [1, 2, 4], 800, 600)).toBe(2);
  });
});

describe('screenLevelOf', () => {
  it('is the coarsest level at least 1024 px on its longer side', () => {
    expect(screenLevelOf(1023, 10, 5)).toBe(0);
    expect(screenLevelOf(2047, 10, 5)).toBe(0);
    expect(screenLevelOf(2048, 10, 5)).toBe(1);
    expect(screenLevelOf(10, 4096, 5)).toBe(2);
    expect(screenLevelOf(60000, 40000, 8)).toBe(5);
    expect(screenLevelOf(60000, 40000, 3)).toBe(3);
  });
});

describe('maxLevelOf', () => {
  it('reads the coarsest level from scale factors', () => {
    expect(maxLevelOf([1, 2, 4, 8])).toBe(3);
    expect(maxLevelOf([1])).toBe(0);
    expect(maxLevelOf([])).toBe(0);
  });
});
