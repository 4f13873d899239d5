/**
 * Uniform values of a relight layer (pure: no GL), checked against the uniform names with `satisfies`.
 */
import type { RelightLayer } from '../iiif/relight-service';
import { ptmWeights } from '../math/ptm-basis';
import { MAX_PLANES, U_BIAS, U_SCALE, U_WEIGHTS } from '../gl/uniforms';

/** Uniforms that depend on the layer and the light (not on the tile). */
export interface LayerUniforms {
  [U_SCALE]: Float32Array;
  [U_BIAS]: Float32Array;
  [U_WEIGHTS]: Float32Array;
}

/**
 * Per-layer uniform values: scale and bias padded to {@link MAX_PLANES} vec3s, and the basis weights.
 *
 * @param layer - the validated relight layer
 * @param lu - light x (right)
 * @param lv - light y (up)
 */
export function layerUniforms(layer: RelightLayer, lu: number, lv: number): LayerUniforms {
  const scale = new Float32Array(MAX_PLANES * 3);
  const bias = new Float32Array(MAX_PLANES * 3);
  layer.planes.forEach((p, i) => {
    scale.set(p.scale, i * 3);
    bias.set(p.bias, i * 3);
  });
  const weights = new Float32Array(6);
  if (layer.layerType === 'ptm') {
    weights.set(ptmWeights(lu, lv));
  }
  return { [U_SCALE]: scale, [U_BIAS]: bias, [U_WEIGHTS]: weights } satisfies LayerUniforms;
}
