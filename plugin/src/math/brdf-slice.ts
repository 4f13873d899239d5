/**
 * The BRDF slice φd = 90° of Lambert + isotropic Ward (Rusinkiewicz 1998; the slice as Burley's
 * BRDF Explorer and the MERL images show it), as the measurement mode plots it
 * (docs/rendering.md, "Measurement mode"), and its tone mapping. Mirrors `tiler/render/measure.py`.
 *
 * Pure maths: no DOM, no GL.
 */

/** Samples per axis of a slice. */
export const SLICE_SIZE = 32;

/** The `n` sample angles of each slice axis, `(i + ½)·(π/2)/n` radians, ascending. */
export function sliceAngles(n = SLICE_SIZE): Float64Array {
  return Float64Array.from({ length: n }, (_, i) => ((i + 0.5) * Math.PI) / 2 / n);
}

/**
 * Ward's specular lobe `exp(−tan²θh/α²)/(4α²)` of `nh = n·h`, clamped to `≥ 1e-4` as in the shader.
 */
export function wardLobe(nh: number, alpha: number): number {
  const c = Math.max(nh, 1e-4);
  const tan2 = (1 - c * c) / (c * c);
  const a2 = alpha * alpha;
  return Math.exp(-tan2 / a2) / (4 * a2);
}

/**
 * `π·f(θh, θd)` at φd = 90° (E = π, so a Lambertian kd shows as kd): with `n·l = n·v = cosθd·cosθh`
 * and `n·h = cosθh`, `π·f = kd + ks·exp(−tan²θh/α²)/(4α²·cosθd·cosθh)`.
 *
 * @param kd - linear diffuse reflectance (R, G, B)
 * @param ks - linear specular reflectance (R, G, B)
 * @param alpha - Ward roughness
 * @param n - samples per axis
 * @returns `n·n·3` values, row `j` = θd (first row θd ≈ 0), column `i` = θh
 */
export function brdfSlice(kd: readonly number[], ks: readonly number[], alpha: number, n = SLICE_SIZE): Float32Array {
  const t = sliceAngles(n);
  const out = new Float32Array(n * n * 3);
  for (let j = 0; j < n; j++) {
    const cd = Math.cos(t[j] ?? 0);
    for (let i = 0; i < n; i++) {
      const ch = Math.cos(t[i] ?? 0);
      const lobe = wardLobe(ch, alpha) / (cd * ch);
      for (let c = 0; c < 3; c++) {
        out[(j * n + i) * 3 + c] = (kd[c] ?? 0) + (ks[c] ?? 0) * lobe;
      }
    }
  }
  return out;
}

/** sRGB encoding of a value clamped to 0–1. */
export function linearToSrgb(x: number): number {
  const v = Math.min(1, Math.max(0, x));
  return v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055;
}

/** sRGB decoding: `x/12.92` if `x ≤ 0.04045`, else `((x + 0.055)/1.055)^2.4`. */
export function srgbToLinear(x: number): number {
  return x <= 0.04045 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4;
}

/**
 * The display value of a slice value: Reinhard's `x/(1 + x)` (one fixed curve, so that slices of two
 * pixels compare, a peak of any height stays below white and kd = 1 is mid-grey), then sRGB.
 */
export function toneMapSlice(x: number): number {
  const v = Math.max(0, x);
  return linearToSrgb(v / (1 + v));
}
