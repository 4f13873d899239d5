import { describe, expect, it } from 'vitest';
import { BASES, PTM_BASIS_TERMS, ptmWeights, relightPtmPixel } from '../../../plugin/src/math/ptm-basis';

describe('ptmWeights', () => {
  it('is [lu², lv², lu·lv, lu, lv, 1]', () => {
    expect(Array.from(ptmWeights(0.5, -0.25))).toEqual([0.25, 0.0625, -0.125, 0.5, -0.25, 1]);
  });
  it('keeps only the constant term for the overhead light', () => {
    expect(Array.from(ptmWeights(0, 0))).toEqual([0, 0, 0, 0, 0, 1]);
  });
  it('distinguishes lu from lv', () => {
    const a = ptmWeights(0.3, 0.7);
    expect(a[0]).toBeCloseTo(0.09, 12);
    expect(a[1]).toBeCloseTo(0.49, 12);
    expect(a[3]).toBe(0.3);
    expect(a[4]).toBe(0.7);
  });
  it('matches the contract basis names', () => {
    expect(PTM_BASIS_TERMS).toEqual(['lu2', 'lv2', 'lulv', 'lu', 'lv', '1']);
    expect(BASES.ptm?.termCount).toBe(6);
  });
});

describe('relightPtmPixel', () => {
  it('lrgb multiplies the colour by the luminance polynomial and clamps', () => {
    // L = 0.1·lu² + 0.2·lv² + 0.3·lu·lv + 0.4·lu + 0.5·lv + 0.6
    const c = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 1, 0.5, 0.25];
    const lu = 0.5;
    const lv = 0.5;
    const l = 0.1 * 0.25 + 0.2 * 0.25 + 0.3 * 0.25 + 0.4 * 0.5 + 0.5 * 0.5 + 0.6;
    const [r, g, b] = relightPtmPixel(c, 'lrgb', lu, lv);
    expect(r).toBe(1); // 1.2 clamped
    expect(g).toBeCloseTo(0.5 * l, 12);
    expect(b).toBeCloseTo(0.25 * l, 12);
  });
  it('rgb evaluates one polynomial per channel', () => {
    const c = [0, 0, 0, 0.5, 0, 0.2, /* G */ 0, 0, 0, 0, 0.5, 0.2, /* B */ 0, 0, 0, 0, 0, -0.5];
    expect(relightPtmPixel(c, 'rgb', 1, 0)).toEqual([0.7, 0.2, 0]);
    const [, g] = relightPtmPixel(c, 'rgb', 0, 1);
    expect(g).toBeCloseTo(0.7, 12);
  });
});
