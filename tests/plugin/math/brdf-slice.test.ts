import { describe, expect, it } from 'vitest';
import { brdfSlice, sliceAngles, toneMapSlice, wardLobe } from '../../../plugin/src/math/brdf-slice';

const { cos, sin, exp, tan, sqrt, PI } = Math;
const dot = (a: number[], b: number[]): number => a.reduce((s, x, i) => s + x * (b[i] ?? 0), 0);
const norm = (a: number[]): number[] => a.map((x) => x / sqrt(dot(a, a)));

/** Rotate `p` about the unit `axis` by `angle` (Rodrigues). */
function rotate(p: number[], axis: number[], angle: number): number[] {
  const [x, y, z] = axis as [number, number, number];
  const c = cos(angle);
  const s = sin(angle);
  const k = dot(axis, p);
  const cross = [y * (p[2] ?? 0) - z * (p[1] ?? 0), z * (p[0] ?? 0) - x * (p[2] ?? 0), x * (p[1] ?? 0) - y * (p[0] ?? 0)];
  return p.map((pi, i) => pi * c + (cross[i] ?? 0) * s + (axis[i] ?? 0) * k * (1 - c));
}

describe('brdfSlice', () => {
  it('samples θh along a row and θd down the columns, at (i + ½)·(π/2)/n', () => {
    expect(Array.from(sliceAngles(2))).toEqual([PI / 8, (3 * PI) / 8]);
    const kd = [0.5, 0.4, 0.3];
    const ks = [0.2, 0.1, 0.05];
    const alpha = 0.3;
    const s = brdfSlice(kd, ks, alpha, 2);
    expect(s).toHaveLength(2 * 2 * 3);
    // row 1 (θd = 3π/8), column 0 (θh = π/8), green: written out by hand
    const th = PI / 8;
    const td = (3 * PI) / 8;
    const want = 0.4 + (0.1 * exp(-(tan(th) ** 2) / alpha ** 2)) / (4 * alpha ** 2 * cos(td) * cos(th));
    expect(s[(1 * 2 + 0) * 3 + 1]).toBeCloseTo(want, 6);
  });

  it('is kd everywhere without a specular term', () => {
    const s = brdfSlice([0.6, 0.3, 0.1], [0, 0, 0], 0.2, 8);
    for (let p = 0; p < 64; p++) {
      expect([s[p * 3], s[p * 3 + 1], s[p * 3 + 2]].map((x) => Number(x?.toFixed(6)))).toEqual([0.6, 0.3, 0.1]);
    }
  });

  it('falls off along θh from the peak and grows along θd (1/cos θd)', () => {
    const n = 16;
    const s = brdfSlice([0.2, 0.2, 0.2], [0.5, 0.5, 0.5], 0.1, n);
    const at = (i: number, j: number): number => s[(j * n + i) * 3] ?? NaN;
    for (let i = 1; i < n; i++) {
      // strictly while the lobe has not underflowed
      expect(at(i, 3)).toBeLessThanOrEqual(at(i - 1, 3));
      expect(at(i, 3) < at(i - 1, 3) || at(i, 3) === Math.fround(0.2)).toBe(true);
    }
    expect(at(1, 3)).toBeLessThan(at(0, 3));
    for (let j = 1; j < n; j++) {
      expect(at(0, j)).toBeGreaterThan(at(0, j - 1));
    }
  });

  it('times cos θi is the shader\'s Ward radiance for the same geometry seen from (0, 0, 1)', () => {
    const kd = 0.35;
    const ks = 0.4;
    const alpha = 0.25;
    const n = 8;
    const s = brdfSlice([kd, kd, kd], [ks, ks, ks], alpha, n);
    const t = sliceAngles(n);
    for (const [i, j] of [[0, 0], [2, 1], [5, 3], [1, 2]] as const) {
      const th = t[i] ?? 0;
      const td = t[j] ?? 0;
      // the slice's local frame (n = z), φd = 90°
      const l = [cos(td) * sin(th), sin(td), cos(td) * cos(th)];
      const v = [cos(td) * sin(th), -sin(td), cos(td) * cos(th)];
      // rotate it so that the view is (0, 0, 1), as the renderer's camera
      const axis = norm([v[1] ?? 0, -(v[0] ?? 0), 0]);
      const angle = Math.acos(v[2] ?? 1);
      const [lw, nw] = [rotate(l, axis, angle), rotate([0, 0, 1], axis, angle)];
      expect(rotate(v, axis, angle).map((x) => Number(x.toFixed(9)) + 0)).toEqual([0, 0, 1]);
      const hw = norm([(lw[0] ?? 0), (lw[1] ?? 0), (lw[2] ?? 0) + 1]);
      // the svbrdf shader's lt_color, before the clamp
      const cosi = Math.max(0, dot(nw, lw));
      const cosr = Math.max(nw[2] ?? 0, 1e-4);
      const nh = Math.max(dot(nw, hw), 1e-4);
      const tan2 = (1 - nh * nh) / (nh * nh);
      const radiance = kd * cosi + (ks * exp(-tan2 / alpha ** 2) * sqrt(cosi / cosr)) / (4 * alpha ** 2);
      expect((s[(j * n + i) * 3] ?? 0) * cosi).toBeCloseTo(radiance, 6); // the slice is float32
    }
  });
});

describe('wardLobe and toneMapSlice', () => {
  it('peaks at 1/(4α²) and clamps n·h as the shader does', () => {
    expect(wardLobe(1, 0.5)).toBeCloseTo(1, 12);
    expect(wardLobe(0, 0.5)).toBe(wardLobe(1e-4, 0.5));
  });

  it('maps 0 to black, kd = 1 to sRGB(½) and any peak below white, monotonically', () => {
    expect(toneMapSlice(0)).toBe(0);
    expect(toneMapSlice(1)).toBeCloseTo(1.055 * 0.5 ** (1 / 2.4) - 0.055, 12);
    expect(toneMapSlice(1e6)).toBeLessThan(1);
    const xs = [0, 0.1, 0.5, 1, 3, 30, 300];
    xs.slice(1).forEach((x, k) => { expect(toneMapSlice(x)).toBeGreaterThan(toneMapSlice(xs[k] ?? 0)); });
  });
});
