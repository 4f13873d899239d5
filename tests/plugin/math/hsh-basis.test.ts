import { describe, expect, it } from 'vitest';
import { HSH_MAX_THETA, HSH_NORMAL_LIGHTS, hshNormalInverse, hshNormalWeights, hshWeights } from '../../../plugin/src/math/hsh-basis';

const { sqrt, PI } = Math;

describe('hshWeights', () => {
  it('matches the contract at the overhead light (x = cos 0 = 1, s = 0)', () => {
    const w = hshWeights(0, 0, 16);
    expect(w).toHaveLength(16);
    expect(w[0]).toBeCloseTo(1 / sqrt(2 * PI), 12);
    expect(w[2]).toBeCloseTo(sqrt(3 / (2 * PI)), 12);
    expect(w[6]).toBeCloseTo(sqrt(5 / (2 * PI)), 12);
    expect(w[12]).toBeCloseTo(sqrt(7 / (2 * PI)), 12);
    for (const k of [1, 3, 4, 5, 7, 8, 9, 10, 11, 13, 14, 15]) {
      expect(Math.abs(w[k] ?? NaN)).toBeLessThan(1e-12);
    }
  });

  it('returns 4, 9 or 16 terms, prefixes of each other', () => {
    const w16 = Array.from(hshWeights(0.3, -0.4, 16));
    expect(Array.from(hshWeights(0.3, -0.4, 4))).toEqual(w16.slice(0, 4));
    expect(Array.from(hshWeights(0.3, -0.4, 9))).toEqual(w16.slice(0, 9));
  });

  it('follows the formulas at a generic light', () => {
    const lu = 0.3;
    const lv = 0.4;
    const x = sqrt(1 - 0.25);
    const s = sqrt(x - x * x);
    const cp = 0.6;
    const sp = 0.8;
    const w = hshWeights(lu, lv, 16);
    expect(w[1]).toBeCloseTo(sqrt(6 / PI) * cp * s, 12);
    expect(w[3]).toBeCloseTo(sqrt(6 / PI) * sp * s, 12);
    expect(w[4]).toBeCloseTo(sqrt(30 / PI) * (cp * cp - sp * sp) * (x * x - x), 12);
    expect(w[9]).toBeCloseTo(2 * sqrt(35 / PI) * (4 * cp ** 3 - 3 * cp) * s ** 3, 12);
    expect(w[15]).toBeCloseTo(2 * sqrt(35 / PI) * (3 * sp - 4 * sp ** 3) * s ** 3, 12);
    expect(w[12]).toBeCloseTo(sqrt(7 / (2 * PI)) * (20 * x ** 3 - 30 * x * x + 12 * x - 1), 12);
  });

  it('is symmetric: mirroring lv flips the sin terms only; mirroring lu flips the odd cos terms', () => {
    const a = hshWeights(0.3, 0.5, 16);
    const b = hshWeights(0.3, -0.5, 16);
    const sinTerms = [3, 7, 8, 13, 14, 15];
    a.forEach((v, k) => { expect(b[k]).toBeCloseTo(sinTerms.includes(k) ? -v : v, 12); });
    const c = hshWeights(-0.3, 0.5, 16);
    const flipped = [1, 5, 8, 9, 11, 14]; // cos φ, cos 3φ and sin 2φ change sign
    a.forEach((v, k) => { expect(c[k]).toBeCloseTo(flipped.includes(k) ? -v : v, 12); });
  });

  it('clamps the elevation near the horizon', () => {
    const edge = hshWeights(1, 0, 16);
    const x = Math.cos(HSH_MAX_THETA);
    expect(edge[2]).toBeCloseTo(sqrt(3 / (2 * PI)) * (2 * x - 1), 12);
    expect(Array.from(hshWeights(2, 0, 16))).toEqual(Array.from(edge));
  });

  it('uses (cos φ, sin φ) = (1, 0) at the pole', () => {
    const w = hshWeights(1e-8, -1e-8, 4);
    expect(w[3]).toBe(0);
    expect(w[1]).toBeGreaterThanOrEqual(0);
  });
});

describe('HSH normal estimate', () => {
  it('has three lights at 45° elevation', () => {
    for (const [u, v, z] of HSH_NORMAL_LIGHTS) {
      expect(Math.hypot(u, v, z)).toBeCloseTo(1, 12);
      expect(z).toBeCloseTo(Math.SQRT1_2, 12);
    }
  });

  it('inverts the light matrix (column-major)', () => {
    const inv = hshNormalInverse();
    for (let i = 0; i < 3; i++) {
      for (let j = 0; j < 3; j++) {
        let s = 0;
        for (let k = 0; k < 3; k++) {
          s += (HSH_NORMAL_LIGHTS[i]?.[k] ?? 0) * (inv[j * 3 + k] ?? 0);
        }
        expect(s).toBeCloseTo(i === j ? 1 : 0, 12);
      }
    }
  });

  it('recovers a Lambertian normal from I_i = n·l_i', () => {
    const n = [0.2, -0.3, Math.sqrt(1 - 0.13)];
    const intensities = HSH_NORMAL_LIGHTS.map((l) => l[0] * (n[0] ?? 0) + l[1] * (n[1] ?? 0) + l[2] * (n[2] ?? 0));
    const inv = hshNormalInverse();
    const g = [0, 1, 2].map((r) => [0, 1, 2].reduce((s, c) => s + (inv[c * 3 + r] ?? 0) * (intensities[c] ?? 0), 0));
    g.forEach((v, i) => { expect(v).toBeCloseTo(n[i] ?? NaN, 12); });
  });

  it('packs 16 weights per light', () => {
    const w = hshNormalWeights(9);
    expect(w).toHaveLength(48);
    expect(w[9]).toBe(0);
    expect(w[16]).toBeCloseTo(1 / sqrt(2 * PI), 12);
  });
});
