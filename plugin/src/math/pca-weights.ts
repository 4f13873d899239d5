/**
 * PCA light bases (Relight's `rbf` and `bilinear` types, colour spaces `mrgb` and `mycc`): the
 * TypeScript twin of `tiler/formats/pca_model.py`, which states the semantics (docs/rendering.md).
 * Pure: no DOM, no GL.
 *
 * A pixel holds N coefficients `r_q`; the basis has N + 1 rows (row 0 the mean) sampled at D light
 * directions, 3 channels each. For a light the sample weights `w_d` give
 * `E[p, k] = Σ_d w_d·B[p, d, k]`, folded (mrgb: as is; mycc: per YCC channel, then YCoCg → RGB)
 * into RGB plane weights `W` with `c = W[0] + Σ_q r_q·W[q + 1]` — what the shader uploads.
 */
import { HSH_NORMAL_LIGHTS } from './hsh-basis';

/** Basis types of a PCA layer. */
export type PcaType = 'rbf' | 'bilinear';
/** Colour spaces of a PCA layer. */
export type PcaColorspace = 'mrgb' | 'mycc';

/** Normalised RBF weights at or below this are dropped, the rest renormalised (Relight). */
export const RBF_DROP = 0.001;
/** Most coefficient planes a PCA layer may have (16 plane groups of 3). */
export const MAX_PCA_PLANES = 48;

/** Relight's `Color3::toRgb`: RGB = M · (Y, Co, Cg), rows R, G, B. */
export const YCC_TO_RGB: readonly (readonly [number, number, number])[] = [
  [1, 0.5, -0.5],
  [1, 0, 0.5],
  [1, -0.5, -0.5],
];

/** A layer's PCA basis, decoded once when the layer is read. */
export interface PcaBasis {
  readonly layerType: PcaType;
  readonly colorspace: PcaColorspace;
  /** N, the coefficient planes. */
  readonly nplanes: number;
  /** D, the light samples of the basis. */
  readonly ndimensions: number;
  /** The decoded basis, `(N + 1)·D·3` values at `(p·D + d)·3 + k`. */
  readonly values: Float64Array;
  /** rbf: the D acquisition lights, `d·3 + axis` (unit, x right, y up). */
  readonly lights: Float64Array | null;
  /** rbf: the Gaussian's σ. */
  readonly sigma: number;
  /** bilinear: the grid's side R (D = R²). */
  readonly resolution: number;
  /** mycc: `[ny, nc, nc]`. */
  readonly yccplanes: readonly [number, number, number] | null;
}

/** The unit light `(lu, lv, lz)`; a projection outside the unit disk is moved onto it. */
export function lightDirection(lu: number, lv: number): [number, number, number] {
  const r = Math.hypot(lu, lv);
  const [x, y] = r > 1 ? [lu / r, lv / r] : [lu, lv];
  return [x, y, Math.sqrt(Math.max(0, 1 - x * x - y * y))];
}

/**
 * Relight's RBF sample weights (D) for the light projected at `(lu, lv)`: `g_d = exp(−‖l − l_d‖²/σ²)`,
 * `w = g/Σg`; weights ≤ {@link RBF_DROP} become 0 and the rest are renormalised. (The exponent is
 * shifted by its minimum, which leaves the normalised weights unchanged and keeps them finite.)
 */
export function rbfWeights(lights: ArrayLike<number>, sigma: number, lu: number, lv: number): Float64Array {
  const l = lightDirection(lu, lv);
  const n = Math.floor(lights.length / 3);
  const d2 = new Float64Array(n);
  for (let d = 0; d < n; d++) {
    let s = 0;
    for (let a = 0; a < 3; a++) {
      s += ((lights[d * 3 + a] ?? 0) - (l[a] ?? 0)) ** 2;
    }
    d2[d] = s;
  }
  const min = Math.min(...d2);
  const w = d2.map((v) => Math.exp(-(v - min) / (sigma * sigma)));
  const total = w.reduce((a, b) => a + b, 0);
  const max = Math.max(...w);
  const keep = w.map((v) => (v / total > RBF_DROP ? 1 : 0));
  if (!keep.some((k) => k === 1)) {
    w.forEach((v, d) => { keep[d] = v === max ? 1 : 0; });
  }
  const kept = w.map((v, d) => v * (keep[d] ?? 0));
  const sum = kept.reduce((a, b) => a + b, 0);
  return kept.map((v) => v / sum);
}

/**
 * Relight's bilinear sample weights (R², sample `x + y·R`) for `(lu, lv)`: the light on the
 * octahedral square rotated by 45° (`s = |lx| + |ly| + |lz|`, `x = ((lx + ly)/s + 1)/2·(R − 1)`,
 * `y = ((ly − lx)/s + 1)/2·(R − 1)`), the cell corner clamped to `[0, R − 2]`, and the four corners'
 * bilinear weights.
 */
export function bilinearWeights(resolution: number, lu: number, lv: number): Float64Array {
  const res = Math.trunc(resolution);
  const [lx, ly, lz] = lightDirection(lu, lv);
  const s = Math.abs(lx) + Math.abs(ly) + Math.abs(lz);
  const x = (((lx + ly) / s + 1) / 2) * (res - 1);
  const y = (((ly - lx) / s + 1) / 2) * (res - 1);
  const sx = Math.min(res - 2, Math.max(0, Math.floor(x)));
  const sy = Math.min(res - 2, Math.max(0, Math.floor(y)));
  const dx = x - sx;
  const dy = y - sy;
  const w = new Float64Array(res * res);
  const corners: [number, number, number][] = [
    [0, 0, (1 - dx) * (1 - dy)], [1, 0, dx * (1 - dy)], [0, 1, (1 - dx) * dy], [1, 1, dx * dy],
  ];
  for (const [ox, oy, v] of corners) {
    w[sx + ox + (sy + oy) * res] += v;
  }
  return w;
}

/** Relight's basis bytes (flat, `(p·D + d)·3 + k`) as values: `b/255` for p = 0, `(b − 127)/range[p − 1]`. */
export function decodeBasis(bytes: ArrayLike<number>, ranges: readonly number[], ndimensions: number): Float64Array {
  const row = ndimensions * 3;
  const out = new Float64Array((ranges.length + 1) * row);
  for (let i = 0; i < out.length; i++) {
    const p = Math.floor(i / row);
    const b = bytes[i] ?? 0;
    out[i] = p === 0 ? b / 255 : (b - 127) / (ranges[p - 1] ?? 1);
  }
  return out;
}

/** The YCC channel of each plane (mycc: plane q < 3·nc → q % 3, later planes 0), or -1 (mrgb: all three). */
export function planeChannels(colorspace: PcaColorspace, nplanes: number,
  yccplanes: readonly number[] | null): number[] {
  const nc = colorspace === 'mycc' ? (yccplanes?.[1] ?? 0) : 0;
  return Array.from({ length: nplanes }, (_, q) => (colorspace === 'mrgb' ? -1 : q < 3 * nc ? q % 3 : 0));
}

/** Fold `E` ((N + 1)·3) into RGB plane weights `W` with `c = W[0] + Σ_q r_q·W[q + 1]`. */
export function rgbPlaneWeights(e: Float64Array, colorspace: PcaColorspace,
  yccplanes: readonly number[] | null): Float64Array {
  if (colorspace === 'mrgb') {
    return e.slice();
  }
  const out = new Float64Array(e.length);
  YCC_TO_RGB.forEach((m, r) => { out[r] = m[0] * (e[0] ?? 0) + m[1] * (e[1] ?? 0) + m[2] * (e[2] ?? 0); });
  planeChannels(colorspace, e.length / 3 - 1, yccplanes).forEach((k, q) => {
    const v = e[(q + 1) * 3 + k] ?? 0;
    YCC_TO_RGB.forEach((m, r) => { out[(q + 1) * 3 + r] = (m[k] ?? 0) * v; });
  });
  return out;
}

/** The sample weights `w_d(l)` of each basis type. */
export const SAMPLE_WEIGHTS: Readonly<Record<PcaType, (basis: PcaBasis, lu: number, lv: number) => Float64Array>> = {
  rbf: (basis, lu, lv) => rbfWeights(basis.lights ?? [], basis.sigma, lu, lv),
  bilinear: (basis, lu, lv) => bilinearWeights(basis.resolution, lu, lv),
};

/** `w_d(l)` of a basis: its RBF or bilinear sample weights. */
export function sampleWeights(basis: PcaBasis, lu: number, lv: number): Float64Array {
  return SAMPLE_WEIGHTS[basis.layerType](basis, lu, lv);
}

/** The RGB plane weights `W` ((N + 1)·3, plane p at 3p) of a basis for the light at `(lu, lv)`. */
export function pcaWeights(basis: PcaBasis, lu: number, lv: number): Float64Array {
  const w = sampleWeights(basis, lu, lv);
  const dims = basis.ndimensions;
  const e = new Float64Array((basis.nplanes + 1) * 3);
  for (let p = 0; p <= basis.nplanes; p++) {
    for (let d = 0; d < dims; d++) {
      const wd = w[d] ?? 0;
      if (wd !== 0) {
        const at = (p * dims + d) * 3;
        for (let k = 0; k < 3; k++) {
          e[p * 3 + k] += wd * (basis.values[at + k] ?? 0);
        }
      }
    }
  }
  return rgbPlaneWeights(e, basis.colorspace, basis.yccplanes);
}

/** {@link pcaWeights} as the shader's uniform: `slots` vec3s (≥ N + 1), zero-padded. */
export function pcaPlaneWeights(basis: PcaBasis, lu: number, lv: number, slots = basis.nplanes + 1): Float32Array {
  const out = new Float32Array(slots * 3);
  out.set(pcaWeights(basis, lu, lv));
  return out;
}

/**
 * The weights of the normal estimate (contract: relit under HSH's three normal lights, intensity 1,
 * `I_i = r + g + b`): per plane p the vec3 `(Σ_k W₁[p, k], Σ_k W₂[p, k], Σ_k W₃[p, k])`, so that
 * `I = N[0] + Σ_q r_q·N[q + 1]`; `slots` vec3s, zero-padded.
 */
export function pcaNormalWeights(basis: PcaBasis, slots = basis.nplanes + 1): Float32Array {
  const out = new Float32Array(slots * 3);
  HSH_NORMAL_LIGHTS.forEach(([lu, lv], i) => {
    const w = pcaWeights(basis, lu, lv);
    for (let p = 0; p <= basis.nplanes; p++) {
      out[p * 3 + i] = (w[p * 3] ?? 0) + (w[p * 3 + 1] ?? 0) + (w[p * 3 + 2] ?? 0);
    }
  });
  return out;
}

/**
 * The weights of the albedo's numerator `c(l₁) + c(l₂) + c(l₃)` (the three normal lights): per
 * plane the sum of the lights' RGB weights; `slots` vec3s, zero-padded.
 */
export function pcaAlbedoWeights(basis: PcaBasis, slots = basis.nplanes + 1): Float32Array {
  const out = new Float32Array(slots * 3);
  const sum = new Float64Array((basis.nplanes + 1) * 3);
  for (const [lu, lv] of HSH_NORMAL_LIGHTS) {
    pcaWeights(basis, lu, lv).forEach((v, i) => { sum[i] += v; });
  }
  out.set(sum);
  return out;
}

/** The colour `(3)` of coefficients `r` (N) under RGB plane weights `W` ((N + 1)·3). */
export function reconstruct(r: ArrayLike<number>, w: ArrayLike<number>): [number, number, number] {
  const c: [number, number, number] = [w[0] ?? 0, w[1] ?? 0, w[2] ?? 0];
  for (let q = 0; q < r.length; q++) {
    for (let k = 0; k < 3; k++) {
      c[k] += (r[q] ?? 0) * (w[(q + 1) * 3 + k] ?? 0);
    }
  }
  return c;
}
