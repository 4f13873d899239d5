import { describe, expect, it } from 'vitest';
import { hshWeights } from '../../../plugin/src/math/hsh-basis';
import { relightPtmPixel } from '../../../plugin/src/math/ptm-basis';
import { diskLight, diskPixelOf, hshColor, ptmColor, reflectanceDisk, shColor } from '../../../plugin/src/math/reflectance-disk';

const named = (prefixes: string[], n: number, values: number[]): Record<string, number> => {
  const out: Record<string, number> = {};
  prefixes.forEach((p, c) => { for (let k = 0; k < n; k++) { out[`${p}${k}`] = values[c * n + k] ?? 0; } });
  return out;
};

describe('diskLight', () => {
  it('projects orthographically: centre overhead, right lu = 1, top lv = 1', () => {
    expect(diskLight(2, 2, 5)).toEqual({ lu: 0, lv: 0, inside: true });
    expect(diskLight(4, 2, 5)).toEqual({ lu: 0.8, lv: 0, inside: true });
    expect(diskLight(2, 0, 5)).toEqual({ lu: 0, lv: 0.8, inside: true });
    expect(diskLight(0, 0, 5).inside).toBe(false);
    expect(diskPixelOf(0.8, 0, 5)).toEqual({ x: 4.5, y: 2.5 });
  });
});

describe('reflectanceDisk', () => {
  const lrgb = { L0: -0.3, L1: -0.2, L2: 0.05, L3: 0.2, L4: -0.1, L5: 0.6, R: 0.8, G: 0.5, B: 0.3 };

  it('is the shader\'s PTM colour for each disk pixel\'s light, 0 outside', () => {
    const size = 9;
    const disk = reflectanceDisk(size, (lu, lv) => ptmColor(lrgb, 'lrgb', lu, lv));
    let inside = 0;
    for (let j = 0; j < size; j++) {
      for (let i = 0; i < size; i++) {
        const { lu, lv, inside: isIn } = diskLight(i, j, size);
        const got = Array.from(disk.subarray((j * size + i) * 3, (j * size + i) * 3 + 3));
        if (!isIn) {
          expect(got).toEqual([0, 0, 0]);
          continue;
        }
        inside++;
        const coefficients = [lrgb.L0, lrgb.L1, lrgb.L2, lrgb.L3, lrgb.L4, lrgb.L5, lrgb.R, lrgb.G, lrgb.B];
        relightPtmPixel(coefficients, 'lrgb', lu, lv).forEach((v, c) => { expect(got[c]).toBeCloseTo(v, 6); });
      }
    }
    expect(inside).toBe(69); // the pixel centres within the unit circle of a 9×9 disk
  });

  it('evaluates rgb PTMs per channel and applies the light intensity', () => {
    const values = named(['R', 'G', 'B'], 6, Array.from({ length: 18 }, (_, k) => (k % 7) / 10 - 0.2));
    const [r, g, b] = ptmColor(values, 'rgb', 0.3, -0.4, 2);
    const w = [0.09, 0.16, -0.12, 0.3, -0.4, 1];
    const channel = (c: number): number => w.reduce((s, x, k) => s + x * (values[`${'RGB'[c]}${k}`] ?? 0), 0) * 2;
    expect([r, g, b].map((x) => Number(x.toFixed(12)))).toEqual([0, 1, 2].map((c) => Number(channel(c).toFixed(12))));
  });

  it('is Σ a_k·H_k(light) for HSH', () => {
    const values = named(['R', 'G', 'B'], 9, Array.from({ length: 27 }, (_, k) => Math.sin(k)));
    const w = hshWeights(-0.5, 0.25, 9);
    const want = ['R', 'G', 'B'].map((c) => Array.from(w).reduce((s, x, k) => s + x * (values[`${c}${k}`] ?? 0), 0));
    hshColor(values, 9, -0.5, 0.25).forEach((v, c) => { expect(v).toBeCloseTo(want[c] ?? NaN, 12); });
  });

  it("is Σ a_k·Y_k(light) for SH, Y Relight's real SH (stated here)", () => {
    const values = named(['R', 'G', 'B'], 9, Array.from({ length: 27 }, (_, k) => Math.cos(k)));
    const [x, y] = [0.3, -0.45];
    const z = Math.sqrt(1 - x * x - y * y);
    const basis = [0.282095, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y, 1.092548 * y * z,
      0.315392 * (3 * z * z - 1), 1.092548 * x * z, 0.546274 * (x * x - y * y)];
    const want = ['R', 'G', 'B'].map((c) => basis.reduce((s, b, k) => s + b * (values[`${c}${k}`] ?? 0), 0) * 1.5);
    shColor(values, 9, x, y, 1.5).forEach((v, c) => { expect(v).toBeCloseTo(want[c] ?? NaN, 12); });
    const four = shColor(values, 4, x, y);
    expect(four[0]).toBeCloseTo(basis.slice(0, 4).reduce((s, b, k) => s + b * (values[`R${k}`] ?? 0), 0), 12);
  });
});
