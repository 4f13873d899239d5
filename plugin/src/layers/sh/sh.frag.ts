/**
 * sh layer functions (contract `layerType: "sh"`, docs/rendering.md): Relight's plain real
 * spherical harmonics in HSH's layout — plane k holds term k's R, G, B coefficients, `TERMS` (4 or
 * 9) a compile-time define — so the body is HSH's ({@link basisFragmentBody}) with this basis.
 */
import { basisFragmentBody } from '../hsh/hsh.frag';

/** Per-pixel SH basis (same formulas and constants as `shWeights`), as the body's `lt_basis`. */
const SH_BASIS = /* glsl */ `
void lt_basis(vec2 l, out float w[16]) {
  float lz = sqrt(max(0.0, 1.0 - dot(l, l)));
  for (int k = 9; k < 16; k++) {
    w[k] = 0.0;
  }
  w[0] = 0.282095;
  w[1] = 0.488603 * l.y;
  w[2] = 0.488603 * lz;
  w[3] = 0.488603 * l.x;
  w[4] = 1.092548 * l.x * l.y;
  w[5] = 1.092548 * l.y * lz;
  w[6] = 0.315392 * (3.0 * lz * lz - 1.0);
  w[7] = 1.092548 * l.x * lz;
  w[8] = 0.546274 * (l.x * l.x - l.y * l.y);
}
`;

/** Layer functions of an sh program. */
export const SH_FRAGMENT_BODY = basisFragmentBody(SH_BASIS);
