/**
 * Upload a {@link PlaneBundle} into one `TEXTURE_2D_ARRAY` (one layer per plane group), bytes
 * unchanged: no premultiplication, no colour-space conversion, no flip.
 */
import type { PlaneBundle } from '../tiles/bundle';

/**
 * Create an immutable RGBA8 texture array holding the bundle's bitmaps.
 *
 * @returns the texture, or null if the context is lost
 */
export function uploadPlaneBundle(gl: WebGL2RenderingContext, bundle: PlaneBundle): WebGLTexture | null {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, texture);
  gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.RGBA8, bundle.width, bundle.height, bundle.bitmaps.length);
  gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
  gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
  gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  bundle.bitmaps.forEach((bitmap, layer) => {
    gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, 0, layer, bundle.width, bundle.height, 1,
      gl.RGBA, gl.UNSIGNED_BYTE, bitmap);
  });
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, null);
  return texture;
}

/**
 * Two sampler objects overriding the textures' filters: LINEAR (smoothing on) and NEAREST.
 */
export function createSamplers(gl: WebGL2RenderingContext): { linear: WebGLSampler; nearest: WebGLSampler } {
  const make = (filter: number): WebGLSampler => {
    const s = gl.createSampler();
    gl.samplerParameteri(s, gl.TEXTURE_MIN_FILTER, filter);
    gl.samplerParameteri(s, gl.TEXTURE_MAG_FILTER, filter);
    gl.samplerParameteri(s, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.samplerParameteri(s, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    return s;
  };
  return { linear: make(gl.LINEAR), nearest: make(gl.NEAREST) };
}
