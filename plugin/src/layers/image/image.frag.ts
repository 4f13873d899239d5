/**
 * Plain image layer functions (contract `layerType: "image"`): one plane group drawn as is; a
 * single-band (`Y`) group decodes as grey, so its three channels already hold Y.
 */

/** Layer functions of an image program. */
export const IMAGE_FRAGMENT_BODY = /* glsl */ `
vec3 lt_color() { return lanterna_plane(0); }
vec3 lt_albedo() { return lt_color(); }
vec3 lt_achromatic() { return vec3(luma(lt_color())); }
`;
