import { describe, expect, it } from 'vitest';
import { parseRelightService, type RelightLayer } from '../../../plugin/src/iiif/relight-service';
import { pcaWeights, reconstruct } from '../../../plugin/src/math/pca-weights';
import { diskLight } from '../../../plugin/src/math/reflectance-disk';
import { measurementCaption } from '../../../plugin/src/measure/caption';
import { materialOf, plotOf, swatchOf, type Measurement } from '../../../plugin/src/measure/plot-of';
import { placeBeside } from '../../../plugin/src/measure/placement';
import { dequantise, groupValues } from '../../../plugin/src/measure/dequantise';
import { plotRgba } from '../../../plugin/src/measure/plot-rgba';
import { pcaBlock } from '../fixtures';

const group = (channels: string[]) => ({ serviceId: 'x', format: 'png', channels, scale: channels.map(() => 1),
  bias: channels.map(() => 0), embedded: null });
const svbrdf = (maps: string[][], inputColorSpace: RelightLayer['inputColorSpace'] = 'linear'): RelightLayer => ({
  id: 'sv', layerType: 'svbrdf', colorspace: 'rgb', width: 4, height: 4, planes: maps.map(group), terms: 0,
  glossLimits: [0.02, 0.42], inputColorSpace,
});
const N = ['NX', 'NY', 'NZ'];
const KD = ['KD_R', 'KD_G', 'KD_B'];
const KS = ['KS_R', 'KS_G', 'KS_B'];

describe('dequantisation', () => {
  it('is (byte/255 − bias)·scale in float32, a single band read from its first channel', () => {
    expect(dequantise(255, 2, 0.5)).toBe(1);
    expect(dequantise(51, 1, 0)).toBe(Math.fround(0.2));
    expect(dequantise(128, 3, 0.25)).toBe(Math.fround(Math.fround(Math.fround(128 / 255) - 0.25) * 3));
    const rgba = [10, 20, 30, 255, 40, 50, 60, 255];
    expect(groupValues({ channels: ['A', 'B', 'C'], scale: [1, 2, 3], bias: [0, 0, 0] }, rgba, 4))
      .toEqual({ A: dequantise(40, 1, 0), B: dequantise(50, 2, 0), C: dequantise(60, 3, 0) });
    expect(groupValues({ channels: ['GLOSS'], scale: [1], bias: [0] }, rgba, 4)).toEqual({ GLOSS: dequantise(40, 1, 0) });
  });
});

describe('materialOf', () => {
  const values = { NX: 0, NY: 0.6, NZ: 0.8 * 2, KD_R: 0.5, KD_G: 0.04, KD_B: 1, KS_R: 0.2, KS_G: 0.2, KS_B: 0.2,
    GLOSS: 0.5 };

  it('normalises the normal, reads α from the gloss map and decodes sRGB maps', () => {
    const m = materialOf(svbrdf([N, KD, KS, ['GLOSS']], 'srgb'), values);
    expect(m?.normal.map((x) => Number(x.toFixed(6)))).toEqual([0, Number((0.6 / Math.hypot(0.6, 1.6)).toFixed(6)),
      Number((1.6 / Math.hypot(0.6, 1.6)).toFixed(6))]);
    expect(m?.alpha).toBeCloseTo(0.22, 12);
    expect(m?.kd[1]).toBeCloseTo(0.04 / 12.92, 12);
    expect(m?.kd[0]).toBeCloseTo(((0.5 + 0.055) / 1.055) ** 2.4, 12);
  });

  it('takes the contract\'s defaults for missing maps, and is null without a normal map', () => {
    expect(materialOf(svbrdf([N]), values)).toMatchObject({ kd: [0.7, 0.7, 0.7], ks: [0.15, 0.15, 0.15], alpha: 0.25 });
    expect(materialOf(svbrdf([N, KD]), values)).toMatchObject({ ks: [0, 0, 0], alpha: 0.22 });
    expect(materialOf(svbrdf([KD]), values)).toBeNull();
    expect(plotOf(svbrdf([KD], 'srgb'), values, 1).kind).toBe('swatch');
    expect(swatchOf(svbrdf([KD], 'srgb'), values)).toEqual([0.5, 0.04, 1]);
  });
});

describe('plotRgba and the caption', () => {
  const layer: RelightLayer = { ...svbrdf([['R0', 'G0', 'B0']]), layerType: 'hsh', terms: 4,
    planes: [0, 1, 2, 3].map((k) => group([`R${k}`, `G${k}`, `B${k}`])) };
  const values = { R0: 2, G0: 1, B0: 0.5 };

  it('shows the disk transparent outside the circle and clamped inside', () => {
    const { kind, plot } = plotOf(layer, values, 1);
    expect(kind).toBe('reflectance-disk');
    const rgba = plotRgba(kind, plot);
    expect(rgba[3]).toBe(0); // the top-left corner is outside
    const centre = ((plot.height / 2) * plot.width + plot.width / 2) * 4;
    // H0 = 1/√(2π): R0·H0 ≈ 0.80, G0·H0 ≈ 0.40
    expect(Array.from(rgba.subarray(centre, centre + 4))).toEqual([
      Math.round((2 / Math.sqrt(2 * Math.PI)) * 255), Math.round((1 / Math.sqrt(2 * Math.PI)) * 255),
      Math.round((0.5 / Math.sqrt(2 * Math.PI)) * 255), 255]);
  });

  it('plots an sh pixel as a disk too: its centre is Σ a_k·Y_k(overhead)', () => {
    const sh: RelightLayer = { ...layer, layerType: 'sh' };
    const { kind, plot } = plotOf(sh, values, 1);
    expect(kind).toBe('reflectance-disk');
    const centre = ((plot.height / 2) * plot.width + plot.width / 2) * 3;
    const { lu, lv } = diskLight(plot.width / 2, plot.height / 2, plot.width);
    const lz = Math.sqrt(1 - lu * lu - lv * lv); // Y0 = 0.282095, Y2 = 0.488603·lz; R1, R3 are 0
    expect(plot.data[centre]).toBeCloseTo(2 * 0.282095, 5);
    expect(plot.data[centre]).not.toBeCloseTo(plotOf(layer, values, 1).plot.data[centre] ?? NaN, 3);
    expect(lz).toBeGreaterThan(0.99);
  });

  it('names the material, the light or the values', () => {
    const m = { imageX: 3, imageY: 1, layer: 'sv', kind: 'brdf-slice', values: {}, light: { lu: 0.5, lv: 0, lz: 0.87 },
      material: { kd: [0.62, 0.41, 0.3], ks: [0.2, 0.2, 0.2], alpha: 0.15, normal: [0, 0, 1] },
      plot: { width: 1, height: 1, data: new Float32Array(3) } } satisfies Measurement;
    expect(measurementCaption(m)).toBe('kd 0.62 0.41 0.30 · ks 0.20 · α 0.15 (3, 1)');
    expect(measurementCaption({ ...m, kind: 'reflectance-disk', material: null })).toBe('light 0.50 0.00 (3, 1)');
    expect(measurementCaption({ ...m, kind: 'swatch', material: null, values: { Y: 0.25 } })).toBe('Y 0.25 (3, 1)');
  });
});

describe('placeBeside', () => {
  it('goes below right of the pointer, flips near the edges and stays inside', () => {
    expect(placeBeside(10, 10, { w: 100, h: 50 }, { w: 400, h: 300 })).toEqual({ left: 26, top: 26 });
    expect(placeBeside(390, 290, { w: 100, h: 50 }, { w: 400, h: 300 })).toEqual({ left: 274, top: 224 });
    expect(placeBeside(50, 20, { w: 100, h: 50 }, { w: 120, h: 60 })).toEqual({ left: 0, top: 0 });
  });
});

describe('the reflectance disk of a PCA pixel', () => {
  const layer = parseRelightService(pcaBlock('bilinear', 4));
  const values = { P0: 0.4, P1: -0.2, P2: 0.1, P3: 0.3 };

  it('relights the pixel\'s coefficients at each light of the disk, as the colour mode does', () => {
    const { kind, plot } = plotOf(layer, values, 1.5);
    expect(kind).toBe('reflectance-disk');
    const basis = layer.pca;
    expect(basis).toBeDefined();
    const at = (i: number, j: number): number[] => Array.from(plot.data.subarray((j * plot.width + i) * 3, (j * plot.width + i) * 3 + 3));
    for (const [i, j] of [[24, 24], [10, 30], [35, 12]] as const) {
      const { lu, lv } = diskLight(i, j, plot.width);
      const c = basis ? reconstruct([0.4, -0.2, 0.1, 0.3], pcaWeights(basis, lu, lv)) : [NaN, NaN, NaN];
      at(i, j).forEach((v, k) => { expect(v).toBeCloseTo((c[k] ?? NaN) * 1.5, 5); });
    }
    expect(at(10, 30)).not.toEqual(at(35, 12));
  });
});
