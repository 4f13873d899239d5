/**
 * The `sh` layer kinds (contract `layerType: "sh"`, 4 or 9 terms): Relight's plain spherical
 * harmonics, drawn by HSH's program body with the SH basis, so HSH's modes and normal estimate.
 * Pure: no DOM, no GL.
 */
import { U_HSH_NORMAL_INV, U_HSH_NORMAL_WEIGHTS } from '../../gl/uniforms';
import { hshNormalInverse } from '../../math/hsh-basis';
import { shNormalWeights, shWeights } from '../../math/sh-basis';
import { HSH_MODES, type LayerKind } from '../kind-types';
import { SH_FRAGMENT_BODY } from './sh.frag';

/** The row of an sh kind with `terms` terms. */
export function shKind(name: 'sh4' | 'sh9', terms: 4 | 9): LayerKind {
  return {
    name,
    shading: 'sh',
    modes: HSH_MODES,
    lit: true,
    previewPlane: 0,
    glsl: { name, body: SH_FRAGMENT_BODY, defines: { TERMS: terms } },
    weights: (light) => shWeights(light.lu, light.lv, terms),
    uniforms: () => ({
      [U_HSH_NORMAL_WEIGHTS]: Float32Array.from(shNormalWeights(terms)),
      [U_HSH_NORMAL_INV]: Float32Array.from(hshNormalInverse()),
    }),
  };
}

/** The rows of `sh` layers in `LAYER_KINDS`. */
export const SH4_KIND = shKind('sh4', 4);
export const SH9_KIND = shKind('sh9', 9);
