/**
 * Hemispherical harmonics (HSH) light basis, as specified in `docs/rendering.md` (Gautron 2004,
 * RTIViewer's `getHSH`), and the fixed lights of the HSH normal estimate. Pure maths: no DOM, no GL.
 */

/** Largest elevation angle used: lights closer to the horizon are clamped (RTIViewer's π/2 − 0.04). */
export const HSH_MAX_THETA = Math.PI / 2 - 0.04;

/**
 * The first `terms` (4, 9 or 16) HSH weights for the light projected at (lu, lv).
 *
 * @param lu - light x (right); (lu, lv) is clamped to the unit disk
 * @param lv - light y (up)
 * @param terms - number of terms (at most 16)
 */
export function hshWeights(lu: number, lv: number, terms: number): Float64Array {
  const r = Math.hypot(lu, lv);
  const lz = Math.sqrt(Math.max(0, 1 - Math.min(r, 1) ** 2));
  const theta = Math.min(Math.acos(Math.min(Math.max(lz, 0), 1)), HSH_MAX_THETA);
  const x = Math.cos(theta);
  const s = Math.sqrt(Math.max(x - x * x, 0));
  const [cp, sp] = r >= 1e-6 ? [lu / r, lv / r] : [1, 0];
  const c2 = cp * cp - sp * sp;
  const s2 = 2 * sp * cp;
  const c3 = 4 * cp ** 3 - 3 * cp;
  const s3 = 3 * sp - 4 * sp ** 3;
  const pi = Math.PI;
  const w = [
    1 / Math.sqrt(2 * pi),
    Math.sqrt(6 / pi) * cp * s,
    Math.sqrt(3 / (2 * pi)) * (2 * x - 1),
    Math.sqrt(6 / pi) * sp * s,
    Math.sqrt(30 / pi) * c2 * (x * x - x),
    Math.sqrt(30 / pi) * cp * (2 * x - 1) * s,
    Math.sqrt(5 / (2 * pi)) * (6 * x * x - 6 * x + 1),
    Math.sqrt(30 / pi) * sp * (2 * x - 1) * s,
    Math.sqrt(30 / pi) * s2 * (x * x - x),
    2 * Math.sqrt(35 / pi) * c3 * s ** 3,
    Math.sqrt(210 / pi) * c2 * (2 * x - 1) * (x * x - x),
    2 * Math.sqrt(21 / pi) * cp * s * (1 - 5 * x + 5 * x * x),
    Math.sqrt(7 / (2 * pi)) * (20 * x ** 3 - 30 * x * x + 12 * x - 1),
    2 * Math.sqrt(21 / pi) * sp * s * (1 - 5 * x + 5 * x * x),
    Math.sqrt(210 / pi) * s2 * (2 * x - 1) * (x * x - x),
    2 * Math.sqrt(35 / pi) * s3 * s ** 3,
  ];
  return Float64Array.from(w.slice(0, terms));
}

/** The three lights of the HSH normal estimate: θ = 45°, φ = 30°, 150°, 270°, as (lu, lv, lz). */
export const HSH_NORMAL_LIGHTS: readonly (readonly [number, number, number])[] = [30, 150, 270].map((deg) => {
  const phi = (deg * Math.PI) / 180;
  const t = Math.PI / 4;
  return [Math.sin(t) * Math.cos(phi), Math.sin(t) * Math.sin(phi), Math.cos(t)] as const;
});

/**
 * Inverse of the matrix M whose rows are {@link HSH_NORMAL_LIGHTS}, column-major (as a GLSL mat3),
 * so that `g = M⁻¹·I`.
 */
export function hshNormalInverse(): Float64Array {
  const m = (r: number, c: number): number => HSH_NORMAL_LIGHTS[r]?.[c] ?? 0;
  // cofactor C[r][c] via cyclic indices; inverse[r][c] = C[c][r] / det
  const cof = (r: number, c: number): number => {
    const r1 = (r + 1) % 3;
    const r2 = (r + 2) % 3;
    const c1 = (c + 1) % 3;
    const c2 = (c + 2) % 3;
    return m(r1, c1) * m(r2, c2) - m(r1, c2) * m(r2, c1);
  };
  const det = m(0, 0) * cof(0, 0) + m(0, 1) * cof(0, 1) + m(0, 2) * cof(0, 2);
  const out = new Float64Array(9);
  for (let col = 0; col < 3; col++) {
    for (let row = 0; row < 3; row++) {
      out[col * 3 + row] = cof(col, row) / det;
    }
  }
  return out;
}

/**
 * HSH weights of the three normal-estimate lights, 16 per light (padded with zeros past `terms`).
 */
export function hshNormalWeights(terms: number): Float64Array {
  const out = new Float64Array(48);
  HSH_NORMAL_LIGHTS.forEach(([lu, lv], i) => { out.set(hshWeights(lu, lv, terms), i * 16); });
  return out;
}
