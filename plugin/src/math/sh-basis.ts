/**
 * Relight's plain real spherical harmonics (`layerType: "sh"`), as specified in `docs/rendering.md`
 * (`sh`; Relight's `Rti::lightWeightsSh`, with its rounded constants), and the weights of the fixed
 * normal-estimate lights. Pure maths: no DOM, no GL.
 */
import { HSH_NORMAL_LIGHTS } from './hsh-basis';

/** Term counts of an sh layer: order 1 (4 terms) and order 2 (9 terms). */
export const SH_TERM_COUNTS = [4, 9] as const;

/** Relight's constants: `Y0`; band 1; `lu·lv`, `lv·lz`, `lu·lz`; `3lz² − 1`; `lu² − lv²`. */
export const SH_CONSTANTS = [0.282095, 0.488603, 1.092548, 0.315392, 0.546274] as const;

/**
 * The first `terms` (4 or 9) SH weights for the light projected at (lu, lv), with
 * `lz = √(max(0, 1 − lu² − lv²))`: `Y0 = c0`, `Y1 = c1·lv`, `Y2 = c1·lz`, `Y3 = c1·lu`,
 * `Y4 = c2·lu·lv`, `Y5 = c2·lv·lz`, `Y6 = c3·(3lz² − 1)`, `Y7 = c2·lu·lz`, `Y8 = c4·(lu² − lv²)`.
 *
 * @param lu - light x (right)
 * @param lv - light y (up)
 * @param terms - number of terms (at most 9)
 */
export function shWeights(lu: number, lv: number, terms: number): Float64Array {
  const [c0, c1, c2, c3, c4] = SH_CONSTANTS;
  const lz = Math.sqrt(Math.max(0, 1 - lu * lu - lv * lv));
  const w = [c0, c1 * lv, c1 * lz, c1 * lu, c2 * lu * lv, c2 * lv * lz, c3 * (3 * lz * lz - 1), c2 * lu * lz,
    c4 * (lu * lu - lv * lv)];
  return Float64Array.from(w.slice(0, terms));
}

/**
 * SH weights of the three normal-estimate lights ({@link HSH_NORMAL_LIGHTS}), 16 per light (padded
 * with zeros past `terms`), laid out as the HSH program's `u_hshNormalWeights`.
 */
export function shNormalWeights(terms: number): Float64Array {
  const out = new Float64Array(48);
  HSH_NORMAL_LIGHTS.forEach(([lu, lv], i) => { out.set(shWeights(lu, lv, terms), i * 16); });
  return out;
}
