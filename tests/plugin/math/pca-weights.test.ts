import { describe, expect, it } from 'vitest';
import { HSH_NORMAL_LIGHTS } from '../../../plugin/src/math/hsh-basis';
import {
  bilinearWeights, decodeBasis, lightDirection, pcaAlbedoWeights, pcaNormalWeights, pcaPlaneWeights, pcaWeights,
  planeChannels, rbfWeights, reconstruct, rgbPlaneWeights, YCC_TO_RGB, type PcaBasis,
} from '../../../plugin/src/math/pca-weights';

const sum = (a: ArrayLike<number>): number => Array.from(a).reduce((x, y) => x + y, 0);
const LIGHTS = [0, 0, 1, 0.6, 0, 0.8, -0.6, 0, 0.8, 0, 0.6, 0.8];

/** A basis of N planes over D light samples with the given decoded values ((N + 1)·D·3). */
function basis(extra: Partial<PcaBasis> & Pick<PcaBasis, 'values' | 'nplanes' | 'ndimensions'>): PcaBasis {
  return { layerType: 'rbf', colorspace: 'mrgb', lights: null, sigma: 0.5, resolution: 0, yccplanes: null, ...extra };
}

describe('rbfWeights (Relight: exp(−‖l − lᵢ‖²/σ²), normalised, ≤ 0.001 dropped, renormalised)', () => {
  it('weighs two lights by hand-computed Gaussians', () => {
    // l = (0, 0, 1): ‖l − l₁‖² = 0, ‖l − l₂‖² = 0.36 + 0.04 = 0.4; σ = 0.5: g₂ = e^−1.6
    const w = rbfWeights([0, 0, 1, 0.6, 0, 0.8], 0.5, 0, 0);
    const g2 = Math.exp(-1.6);
    expect(w[0]).toBeCloseTo(1 / (1 + g2), 12);
    expect(w[1]).toBeCloseTo(g2 / (1 + g2), 12);
  });

  it('sums to 1, and agrees with tiler/formats/pca_model.py at a generic light', () => {
    const w = rbfWeights(LIGHTS, 0.5, 0.2, 0.1);
    expect(sum(w)).toBeCloseTo(1, 12);
    // rbf_weights(LIGHTS, 0.5, 0.2, 0.1) of the Python model
    [0.50777819, 0.27881755, 0.04087659, 0.17252767].forEach((v, i) => { expect(w[i]).toBeCloseTo(v, 7); });
  });

  it('drops the weights at or below 0.001 and renormalises the rest', () => {
    // σ = 0.15 at (0.5, 0): the second light takes all but ~1e-4 of the Gaussian mass
    const w = Array.from(rbfWeights(LIGHTS, 0.15, 0.5, 0));
    expect(w).toEqual([0, 1, 0, 0]);
    const wide = Array.from(rbfWeights(LIGHTS, 0.3, 0.5, 0));
    expect(wide.filter((v) => v > 0).length).toBeGreaterThan(1);
    expect(wide.every((v) => v === 0 || v > 0.001)).toBe(true);
    expect(sum(wide)).toBeCloseTo(1, 12);
  });

  it('stays finite far from every light, and moves a light outside the disk onto it', () => {
    const w = rbfWeights(LIGHTS, 0.01, -0.9, -0.4);
    expect(w.every(Number.isFinite)).toBe(true);
    expect(sum(w)).toBeCloseTo(1, 12);
    expect(Array.from(rbfWeights(LIGHTS, 0.5, 2, 0))).toEqual(Array.from(rbfWeights(LIGHTS, 0.5, 1, 0)));
    expect(lightDirection(0, 3)).toEqual([0, 1, 0]);
  });
});

describe('bilinearWeights (the octahedral grid rotated by 45°)', () => {
  it('puts the overhead light on the centre sample and a side light on a corner', () => {
    // R = 3: (0, 0, 1) → x = y = 1, the centre sample 1 + 1·3
    expect(Array.from(bilinearWeights(3, 0, 0))).toEqual([0, 0, 0, 0, 1, 0, 0, 0, 0]);
    // (1, 0, 0) → x = 2, y = 0: sample 2 (the cell clamped to [0, R − 2], dx = 1)
    expect(Array.from(bilinearWeights(3, 1, 0))).toEqual([0, 0, 1, 0, 0, 0, 0, 0, 0]);
    // (0, 1, 0) → x = 2, y = 2: sample 8; (−1, 0, 0) → x = 0, y = 2: sample 6
    expect(bilinearWeights(3, 0, 1)[8]).toBeCloseTo(1, 12);
    expect(bilinearWeights(3, -1, 0)[6]).toBeCloseTo(1, 12);
  });

  it('interpolates the four corners of the cell, as pca_model.py does', () => {
    const w = bilinearWeights(9, 0.3, 0.1);
    expect(sum(w)).toBeCloseTo(1, 12);
    // x = ((0.4/s) + 1)/2·8 = 5.186, y = ((−0.2/s) + 1)/2·8 = 3.407 (s = 0.4 + √0.9): samples 32, 33, 41, 42
    const got = [32, 33, 41, 42].map((i) => w[i] ?? NaN);
    [0.48263828, 0.11053285, 0.33101945, 0.07580941].forEach((v, i) => { expect(got[i]).toBeCloseTo(v, 7); });
    expect(Array.from(w).filter((v) => v !== 0)).toHaveLength(4);
  });
});

describe('decodeBasis', () => {
  it('reads the mean as b/255 and the planes as (b − 127)/range', () => {
    // N = 2, D = 1: rows [mean], [plane 0], [plane 1]
    const v = decodeBasis([255, 0, 51, 127, 137, 117, 227, 27, 127], [10, 50], 1);
    expect(Array.from(v)).toEqual([1, 0, 0.2, 0, 1, -1, 2, -2, 0]);
  });
});

describe('the colour-space fold', () => {
  const values = decodeBasis([200, 100, 50, 10, 20, 30, 180, 60, 90, 40, 250, 5, 127, 130, 120, 0, 255, 100,
    140, 110, 127, 30, 60, 90, 77, 88, 99, 11, 22, 33], [2, 4, 8, 16], 2);
  const mycc = basis({ colorspace: 'mycc', nplanes: 4, ndimensions: 2, values, lights: Float64Array.from(LIGHTS.slice(0, 6)),
    yccplanes: [2, 1, 1] });

  it('assigns mycc planes to Y, Co, Cg, then Y', () => {
    expect(planeChannels('mycc', 7, [3, 2, 2])).toEqual([0, 1, 2, 0, 1, 2, 0]);
    expect(planeChannels('mycc', 4, [2, 1, 1])).toEqual([0, 1, 2, 0]);
    expect(planeChannels('mrgb', 3, null)).toEqual([-1, -1, -1]);
  });

  it('is YCC then RGB: c = M·y for any coefficients', () => {
    const e = Float64Array.from([0.5, 0.2, -0.1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]);
    const w = rgbPlaneWeights(e, 'mycc', [2, 1, 1]);
    const r = [0.3, -0.7, 1.1, 0.25];
    // y: Y = 0.5 + 0.3·1 + 0.25·10, Co = 0.2 + (−0.7)·5, Cg = −0.1 + 1.1·9
    const y = [0.5 + 0.3 * 1 + 0.25 * 10, 0.2 - 0.7 * 5, -0.1 + 1.1 * 9];
    const c = reconstruct(r, w);
    YCC_TO_RGB.forEach((m, k) => { expect(c[k]).toBeCloseTo(m[0] * (y[0] ?? 0) + m[1] * (y[1] ?? 0) + m[2] * (y[2] ?? 0), 12); });
    expect(Array.from(rgbPlaneWeights(e, 'mrgb', null))).toEqual(Array.from(e));
  });

  it('matches tiler/formats/pca_model.py PcaBasis.weights for a mycc basis', () => {
    // PcaBasis('rbf', 'mycc', <the bytes above>, (2, 4, 8, 16), LIGHTS[:6], 0.5, None, (2, 1, 1)).weights(0.2, 0.1)
    const expected = [0.576543410361551, 0.604344276799271, 0.29559001336733287, 1.6877267043349349, 1.6877267043349349,
      1.6877267043349349, 5.913453860639524, 0.0, -5.913453860639524, 0.8196911713746495, -0.8196911713746495,
      0.8196911713746495, -4.5871518192088345, -4.5871518192088345, -4.5871518192088345];
    const w = pcaWeights(mycc, 0.2, 0.1);
    expected.forEach((v, i) => { expect(w[i]).toBeCloseTo(v, 10); });
  });
});

describe('pcaPlaneWeights and the fixed normal/albedo sets', () => {
  // N = 3, D = 4: plane p, sample d, channel k holds p + d/10 + k/100 (the mean row p = 0)
  const values = Float64Array.from({ length: 4 * 4 * 3 }, (_, i) => Math.floor(i / 12) + (Math.floor(i / 3) % 4) / 10
    + (i % 3) / 100);
  const b = basis({ nplanes: 3, ndimensions: 4, values, lights: Float64Array.from(LIGHTS) });

  it('is E = Σ_d w_d·B[p, d, k] (mrgb), padded to the slots asked for', () => {
    const w = rbfWeights(LIGHTS, 0.5, 0.2, 0.1);
    const dbar = sum(Array.from(w).map((v, d) => v * d / 10));
    const got = pcaPlaneWeights(b, 0.2, 0.1, 7);
    expect(got).toHaveLength(21);
    for (let p = 0; p <= 3; p++) {
      for (let k = 0; k < 3; k++) {
        expect(got[p * 3 + k]).toBeCloseTo(p + dbar + k / 100, 6);
      }
    }
    expect(Array.from(got.slice(12))).toEqual(new Array(9).fill(0));
  });

  it('gives the normal lights\' r + g + b per plane, and their colours\' sum', () => {
    const n = pcaNormalWeights(b, 4);
    const a = pcaAlbedoWeights(b, 4);
    const at = HSH_NORMAL_LIGHTS.map(([lu, lv]) => pcaWeights(b, lu, lv));
    for (let p = 0; p <= 3; p++) {
      at.forEach((w, i) => {
        expect(n[p * 3 + i]).toBeCloseTo((w[p * 3] ?? 0) + (w[p * 3 + 1] ?? 0) + (w[p * 3 + 2] ?? 0), 6);
      });
      for (let k = 0; k < 3; k++) {
        expect(a[p * 3 + k]).toBeCloseTo(sum(at.map((w) => w[p * 3 + k] ?? 0)), 6);
      }
    }
  });

  it('relights a bilinear basis from the grid samples nearest the light', () => {
    // R = 2: four samples; D = 4 with sample d's mean colour d/10 (+ k/100)
    const bi = basis({ layerType: 'bilinear', resolution: 2, nplanes: 3, ndimensions: 4, values });
    const w = bilinearWeights(2, -0.3, 0.4);
    const c = reconstruct([0, 0, 0], pcaWeights(bi, -0.3, 0.4));
    expect(c[0]).toBeCloseTo(sum(Array.from(w).map((v, d) => v * d / 10)), 12);
  });
});
