/**
 * Plain image layer (contract `layerType: "image"`): one plane group drawn as is.
 */
import { planesPrelude } from '../../gl/glsl/planes.glsl';
import { OUT_COLOR } from '../../gl/uniforms';

/** Output the dequantised RGB of plane 0, clamped, opaque. */
export const IMAGE_FRAGMENT_SHADER = `${planesPrelude('lanterna-image')}
void main() {
  ${OUT_COLOR} = vec4(clamp(lanterna_plane(0), 0.0, 1.0), 1.0);
}
`;
