import { describe, expect, it } from 'vitest';
import { F3, F5, modeFilter } from '../../../plugin/src/render/filter-plan';
import { RENDER_MODES } from '../../../plugin/src/render/modes';
import {
  quantityKey, quantityPlan, type QuantityFacts, type QuantityInputs,
} from '../../../plugin/src/render/quantity-key';

const BASE: QuantityInputs = {
  program: 3, layer: 7, filter: F5, width: 1920, height: 1080, sampler: 2,
  tiles: [
    { texture: 11, matrix: [0.5, 0, 0, 0, 0.5, 0, -1, -1, 1], texScale: [1, 1] },
    { texture: 12, matrix: [0.25, 0, 0, 0, 0.25, 0, 0.1, -0.3, 1], texScale: [0.75, 1] },
  ],
};

describe('how the unsharp quantities are drawn and kept', () => {
  const LIT = { lit: true, unsharpTerms: 0 };
  const UNLIT = { lit: false, unsharpTerms: 0 };
  const LRGB = { lit: true, unsharpTerms: 2 };
  const kept = (facts: QuantityFacts): string[] => RENDER_MODES.filter((m) => quantityPlan(m, facts)?.kept);

  it('has a plan for each mode with a screen filter, and only for those', () => {
    for (const mode of RENDER_MODES) {
      expect(quantityPlan(mode, LIT) !== null).toBe(modeFilter(mode) !== null);
    }
  });

  it('keeps the normals always, the image quantity on unlit layers, the relit ones only through terms', () => {
    expect(kept(LIT)).toEqual(['unsharpNormals']);
    expect(kept(UNLIT)).toEqual(['unsharpNormals', 'unsharpImage']);
    expect(kept(LRGB)).toEqual(['unsharpNormals', 'unsharpCoefficients', 'unsharpLuminance']);
  });

  it('filters the terms instead of the relit quantity where the kind has them', () => {
    expect(quantityPlan('unsharpCoefficients', LRGB)).toEqual({ kept: true, filtered: 2, extras: 0, fromView: false });
    expect(quantityPlan('unsharpCoefficients', LIT)).toEqual({ kept: false, filtered: 1, extras: 0, fromView: false });
  });

  it('combines only the normals from the view, with the normal and albedo kept', () => {
    for (const facts of [LIT, UNLIT, LRGB]) {
      expect(RENDER_MODES.filter((m) => quantityPlan(m, facts)?.fromView)).toEqual(['unsharpNormals']);
      expect(quantityPlan('unsharpNormals', facts)).toEqual({ kept: true, filtered: 1, extras: 2, fromView: true });
    }
  });
});

describe('the key of a filtered quantity', () => {
  it('is the same for the same inputs, built afresh', () => {
    const copy: QuantityInputs = { ...BASE, tiles: BASE.tiles.map((t) => ({ ...t, matrix: [...t.matrix] })) };
    expect(quantityKey(copy)).toBe(quantityKey(BASE));
  });

  it('changes with every input it depends on', () => {
    const variants: QuantityInputs[] = [
      { ...BASE, program: 4 },
      { ...BASE, layer: 8 },
      { ...BASE, filter: F3 },
      { ...BASE, width: 1919 },
      { ...BASE, height: 1081 },
      { ...BASE, sampler: 1 },
      { ...BASE, tiles: BASE.tiles.slice(0, 1) }, // a tile less
      { ...BASE, tiles: [...BASE.tiles].reverse() }, // another drawing order
      { ...BASE, tiles: [BASE.tiles[0], { ...BASE.tiles[1], texture: 13 }] }, // a new texture
      { ...BASE, tiles: [BASE.tiles[0], { ...BASE.tiles[1], texScale: [0.75, 0.5] }] },
      // a pan far below a device pixel still changes the key (numbers are written exactly)
      { ...BASE, tiles: [BASE.tiles[0], { ...BASE.tiles[1], matrix: [0.25, 0, 0, 0, 0.25, 0, 0.1 + 1e-15, -0.3, 1] }] },
    ];
    const keys = new Set([quantityKey(BASE), ...variants.map(quantityKey)]);
    expect(keys.size).toBe(variants.length + 1);
  });

  it('does not mistake one tile list for another (no ambiguous concatenation)', () => {
    const a: QuantityInputs = { ...BASE, tiles: [{ texture: 1, matrix: [12, 3], texScale: [1, 1] }] };
    const b: QuantityInputs = { ...BASE, tiles: [{ texture: 1, matrix: [1, 23], texScale: [1, 1] }] };
    expect(quantityKey(a)).not.toBe(quantityKey(b));
  });
});
