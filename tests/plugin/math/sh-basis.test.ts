import { describe, expect, it } from 'vitest';
import { HSH_NORMAL_LIGHTS } from '../../../plugin/src/math/hsh-basis';
import { SH_TERM_COUNTS, shNormalWeights, shWeights } from '../../../plugin/src/math/sh-basis';

const { sqrt, PI } = Math;

/** The real spherical harmonics of bands 0–2 with exact constants, in Relight's order (band 1: y, z, x). */
function textbook(x: number, y: number, z: number): number[] {
  return [0.5 / sqrt(PI), sqrt(3 / (4 * PI)) * y, sqrt(3 / (4 * PI)) * z, sqrt(3 / (4 * PI)) * x,
    0.5 * sqrt(15 / PI) * x * y, 0.5 * sqrt(15 / PI) * y * z, 0.25 * sqrt(5 / PI) * (3 * z * z - 1),
    0.5 * sqrt(15 / PI) * x * z, 0.25 * sqrt(15 / PI) * (x * x - y * y)];
}

describe('shWeights', () => {
  it('is Relight\'s rounding of the textbook real harmonics', () => {
    for (const [lu, lv] of [[0, 0], [0.6, 0.1], [-0.5, 0.4], [0.2, -0.95]] as const) {
      const w = Array.from(shWeights(lu, lv, 9));
      const want = textbook(lu, lv, sqrt(1 - lu * lu - lv * lv));
      expect(w).toHaveLength(9);
      w.forEach((v, k) => { expect(Math.abs(v - (want[k] ?? NaN)), `term ${k}`).toBeLessThan(2e-6); });
    }
  });

  it('has 4 or 9 terms, the first a prefix of the second', () => {
    expect([...SH_TERM_COUNTS]).toEqual([4, 9]);
    expect(Array.from(shWeights(0.3, -0.4, 4))).toEqual(Array.from(shWeights(0.3, -0.4, 9)).slice(0, 4));
  });

  it('puts a light on or past the rim at the horizon (lz = 0)', () => {
    const w = shWeights(0.8, 0.6, 9);
    expect(w[2]).toBe(0);
    expect(w[6]).toBeCloseTo(-0.315392, 12);
  });
});

describe('shNormalWeights', () => {
  it('holds the weights of the three normal lights, 16 slots each, zero past the terms', () => {
    const out = shNormalWeights(4);
    expect(out).toHaveLength(48);
    HSH_NORMAL_LIGHTS.forEach(([lu, lv], i) => {
      expect(Array.from(out.slice(16 * i, 16 * i + 4))).toEqual(Array.from(shWeights(lu, lv, 4)));
      expect(Array.from(out.slice(16 * i + 4, 16 * i + 16)).every((v) => v === 0)).toBe(true);
    });
  });
});
