/**
 * PTM (polynomial texture map) light basis, as specified in `docs/dataset-format.md`.
 *
 * Pure maths: no DOM, no GL.
 */

/** Names of the six PTM basis terms, in the order the contract's `basis` array lists them. */
export const PTM_BASIS_TERMS = ['lu2', 'lv2', 'lulv', 'lu', 'lv', '1'] as const;

/** Number of terms of the PTM basis. */
export const PTM_TERM_COUNT = PTM_BASIS_TERMS.length;

/**
 * Basis weights `w = [lu², lv², lu·lv, lu, lv, 1]` for a light projected on the image plane.
 *
 * @param lu - light x component (to the right), in [-1, 1]
 * @param lv - light y component (up), in [-1, 1]
 * @returns the six weights, in basis order
 */
export function ptmWeights(lu: number, lv: number): Float64Array {
  return Float64Array.of(lu * lu, lv * lv, lu * lv, lu, lv, 1);
}

/** A basis: how many terms it has and how to weight them for a light direction. */
export interface LightBasis {
  /** Number of coefficients per colour channel. */
  readonly termCount: number;
  /** Term names, in order, as written in the manifest's `basis` array. */
  readonly terms: readonly string[];
  /** Weights for a light (lu, lv); lz is implied. */
  weights(lu: number, lv: number): Float64Array;
}

/** Basis table, keyed by `layerType`. */
export const BASES: Readonly<Record<string, LightBasis>> = {
  ptm: { termCount: PTM_TERM_COUNT, terms: PTM_BASIS_TERMS, weights: ptmWeights },
};

/**
 * Relight one PTM pixel on the CPU, exactly as the shader does (reference implementation for tests).
 *
 * @param coefficients - dequantised coefficients: for `lrgb`, `[L0..L5, R, G, B]`; for `rgb`,
 *   `[R0..R5, G0..G5, B0..B5]`
 * @param colorspace - `'lrgb'` or `'rgb'`
 * @param lu - light x
 * @param lv - light y
 * @returns RGB in 0–1, clamped
 */
export function relightPtmPixel(
  coefficients: ArrayLike<number>,
  colorspace: 'lrgb' | 'rgb',
  lu: number,
  lv: number,
): [number, number, number] {
  const w = ptmWeights(lu, lv);
  const clamp = (x: number): number => Math.min(1, Math.max(0, x));
  const dot = (offset: number): number => {
    let s = 0;
    for (let k = 0; k < PTM_TERM_COUNT; k++) {
      s += (coefficients[offset + k] ?? 0) * (w[k] ?? 0);
    }
    return s;
  };
  if (colorspace === 'lrgb') {
    const l = dot(0);
    return [
      clamp((coefficients[6] ?? 0) * l),
      clamp((coefficients[7] ?? 0) * l),
      clamp((coefficients[8] ?? 0) * l),
    ];
  }
  return [clamp(dot(0)), clamp(dot(6)), clamp(dot(12))];
}
