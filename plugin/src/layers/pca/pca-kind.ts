/**
 * The row shared by the PCA layer kinds (`rbf`, `bilinear`): HSH's modes (their own columns), one program
 * per plane-group count, the light's RGB plane weights per frame and the normal-estimate weights
 * fixed per layer. Pure: no DOM, no GL.
 */
import { U_HSH_NORMAL_INV, U_PCA_ALBEDO_WEIGHTS, U_PCA_NORMAL_WEIGHTS, U_PCA_WEIGHTS } from '../../gl/uniforms';
import { LanternaError } from '../../errors';
import type { RelightLayer } from '../../iiif/relight-service';
import { hshNormalInverse } from '../../math/hsh-basis';
import { pcaAlbedoWeights, pcaNormalWeights, pcaPlaneWeights, type PcaBasis } from '../../math/pca-weights';
import { HSH_MODES, type KindGlsl, type LayerKind } from '../kind-types';
import { PCA_FRAGMENT_BODY } from './pca.frag';

/** The basis of a (validated) PCA layer. */
function basisOf(layer: RelightLayer): PcaBasis {
  if (!layer.pca) {
    throw new LanternaError(`layer ${layer.id} (${layer.layerType}) has no PCA basis`);
  }
  return layer.pca;
}

/** vec3 slots of the weight arrays: one per plane of the groups, plus the mean. */
export const pcaSlots = (layer: RelightLayer): number => 3 * layer.planes.length + 1;

/** The PCA program: its loops and arrays are sized by the layer's plane groups. */
export const PCA_GLSL: KindGlsl = {
  name: 'pca',
  body: PCA_FRAGMENT_BODY,
  defines: {},
  layerDefines: (layer) => ({ PCA_GROUPS: layer.planes.length, PCA_SLOTS: pcaSlots(layer) }),
};

/** The row of a PCA kind. */
export function pcaKind(name: 'rbf' | 'bilinear'): LayerKind {
  return {
    name,
    shading: name,
    modes: HSH_MODES,
    lit: true,
    previewPlane: 0,
    glsl: PCA_GLSL,
    weights: null,
    lightUniforms: (layer, light) => ({
      [U_PCA_WEIGHTS]: pcaPlaneWeights(basisOf(layer), light.lu, light.lv, pcaSlots(layer)),
    }),
    uniforms: (layer) => ({
      [U_PCA_NORMAL_WEIGHTS]: pcaNormalWeights(basisOf(layer), pcaSlots(layer)),
      [U_PCA_ALBEDO_WEIGHTS]: pcaAlbedoWeights(basisOf(layer), pcaSlots(layer)),
      [U_HSH_NORMAL_INV]: Float32Array.from(hshNormalInverse()),
    }),
  };
}
