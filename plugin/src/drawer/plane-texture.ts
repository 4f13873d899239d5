/**
 * Upload a {@link PlaneBundle} into one `TEXTURE_2D_ARRAY` (one layer per plane group), bytes
 * unchanged: no premultiplication, no colour-space conversion, no flip; and the tile textures the
 * drawer keeps, made again from the bundle after a context loss.
 */
import type { PlaneBundle } from '../tiles/bundle';

/** A tile's texture, as the drawer's internal cache keeps it. */
export interface TileTexture {
  /** The texture array (null while the context is lost, or when the bundle cannot be uploaded). */
  texture: WebGLTexture | null;
  /** Fraction of the texture holding valid data, from the tile's `sourceBounds`. */
  readonly texScale: readonly [number, number];
  /** Context generation the texture belongs to (-1: none yet). */
  generation: number;
  /** The decoded planes, held by OpenSeadragon's tile cache: uploaded again after a restoration. */
  readonly bundle: PlaneBundle;
}

/**
 * The tile's texture in context generation `generation`, uploaded (again) from its bundle when it
 * has none of that generation. Null while the context is lost or when the upload fails (the tile is
 * then skipped, so the coarser level shows through).
 */
export function currentTexture(gl: WebGL2RenderingContext, tile: TileTexture, generation: number): WebGLTexture | null {
  if (gl.isContextLost()) {
    return null;
  }
  if (tile.generation !== generation) {
    tile.generation = generation;
    tile.texture = null;
    // A closed bitmap (its cache record destroyed) has no size; texSubImage3D would throw on it.
    if (tile.bundle.bitmaps.every((b) => b.width > 0)) {
      try {
        tile.texture = uploadPlaneBundle(gl, tile.bundle);
      } catch {
        tile.texture = null;
      }
    }
  }
  return tile.texture;
}

/** The tile's texture if it was uploaded (or failed) in context generation `generation`; never uploads. */
export function uploadedTexture(gl: WebGL2RenderingContext, tile: TileTexture, generation: number): WebGLTexture | null {
  return tile.generation === generation && !gl.isContextLost() ? tile.texture : null;
}

/** True while the tile waits for its upload in context generation `generation`. */
export function uploadPending(tile: TileTexture, generation: number): boolean {
  return tile.generation !== generation;
}

/** Bytes of the tile's texture (RGBA8, every plane). */
export function textureBytes(tile: TileTexture): number {
  return tile.bundle.width * tile.bundle.height * 4 * tile.bundle.bitmaps.length;
}

/** Delete the tile's texture if it belongs to the current, live context. */
export function freeTileTexture(gl: WebGL2RenderingContext, tile: TileTexture, generation: number): void {
  if (tile.texture && tile.generation === generation && !gl.isContextLost()) {
    gl.deleteTexture(tile.texture);
  }
  tile.texture = null;
}

/**
 * Create an immutable RGBA8 texture array holding the bundle's bitmaps.
 *
 * @returns the texture, or null if the context is lost
 * @throws the browser's error if a bitmap cannot be uploaded (e.g. it was closed)
 */
export function uploadPlaneBundle(gl: WebGL2RenderingContext, bundle: PlaneBundle): WebGLTexture | null {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, texture);
  gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.RGBA8, bundle.width, bundle.height, bundle.bitmaps.length);
  gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
  gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
  gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  try {
    bundle.bitmaps.forEach((bitmap, layer) => {
      gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, 0, layer, bundle.width, bundle.height, 1,
        gl.RGBA, gl.UNSIGNED_BYTE, bitmap);
    });
  } catch (error) {
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, null);
    gl.deleteTexture(texture);
    throw error;
  }
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
