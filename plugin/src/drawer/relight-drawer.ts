/**
 * `RelightDrawer`: an OpenSeadragon drawer that relights plane bundles with WebGL2, straight into
 * its own on-screen canvas. This is the only module that touches OpenSeadragon drawer internals.
 */
import OpenSeadragon from 'openseadragon';
import * as twgl from 'twgl.js';
import { LanternaError } from '../iiif/errors';
import type { RelightLayer } from '../iiif/relight-service';
import { layerUniforms } from '../layers/layer-uniforms';
import { createPrograms, programKind, type ProgramKind } from '../layers/programs';
import { lightFromProjection, OVERHEAD_LIGHT, type Light } from '../math/light';
import { modelMatrix, multiply, viewMatrix, type Mat3 } from '../math/matrix';
import { BUNDLE_DATA_TYPE, type PlaneBundle } from '../tiles/bundle';
import { U_MATRIX, U_PLANES, U_TEX_SCALE } from '../gl/uniforms';
import { createSamplers, uploadPlaneBundle } from './plane-texture';

/** The drawer's type name (`getType()`). */
export const RELIGHT_DRAWER_TYPE = 'lanterna';

/** WebGL2 is not available. */
export class WebGLUnavailableError extends LanternaError {}

/** What `internalCacheCreate` stores per tile. */
interface TileTexture {
  texture: WebGLTexture | null;
  /** Fraction of the texture holding valid data, from the tile's `sourceBounds`. */
  texScale: [number, number];
  /** Context generation the texture belongs to. */
  generation: number;
}

/** RGBA pixels, rows top-down. */
export interface PixelData {
  readonly width: number;
  readonly height: number;
  readonly data: Uint8Array;
}

/** Minimal view of the OSD objects the drawer reads (typed locally: the shipped types omit them). */
interface TileLike {
  positionedBounds: OpenSeadragon.Rect;
  sourceBounds?: OpenSeadragon.Rect;
  flipped?: boolean;
}
interface TiledImageLike {
  getTilesToDraw(): { tile: TileLike }[];
  getOpacity(): number;
  getRotation(current?: boolean): number;
  getBoundsNoRotate(current?: boolean): OpenSeadragon.Rect;
}

const CONTEXT_ATTRIBUTES: WebGLContextAttributes = {
  alpha: true,
  premultipliedAlpha: true,
  antialias: false,
  depth: false,
  stencil: false,
  preserveDrawingBuffer: false,
};

/**
 * OpenSeadragon drawer for Lanterna layers. Pass the class as the viewer's `drawer` option, then
 * register each relightable TiledImage with {@link RelightDrawer.setLayer}.
 */
export class RelightDrawer extends OpenSeadragon.DrawerBase {
  declare private gl: WebGL2RenderingContext;
  declare private programs: Record<ProgramKind, twgl.ProgramInfo> | null;
  declare private samplers: { linear: WebGLSampler; nearest: WebGLSampler } | null;
  declare private layers: WeakMap<object, RelightLayer>;
  declare private light: Light;
  declare private smoothing: boolean;
  declare private generation: number;
  declare private lastFrame: { item: TiledImageLike; tiles: TileLike[] }[];
  declare private destroyed: boolean;
  declare private onLost: (e: Event) => void;
  declare private onRestored: () => void;

  constructor(options: ConstructorParameters<typeof OpenSeadragon.DrawerBase>[0]) {
    super(options);
    this.layers = new WeakMap();
    this.light = OVERHEAD_LIGHT;
    this.smoothing = true;
    this.generation = 0;
    this.lastFrame = [];
    this.destroyed = false;
    this.programs = null;
    this.samplers = null;
    const gl = this.canvas.getContext('webgl2', CONTEXT_ATTRIBUTES);
    if (!gl) {
      throw new WebGLUnavailableError('WebGL2 is not available');
    }
    this.gl = gl;
    this.setupGl();
    this.onLost = (e: Event) => { e.preventDefault(); };
    this.onRestored = () => {
      this.generation++;
      this.setupGl();
      this.setInternalCacheNeedsRefresh();
      this.viewer.forceRedraw();
    };
    this.canvas.addEventListener('webglcontextlost', this.onLost);
    this.canvas.addEventListener('webglcontextrestored', this.onRestored);
  }

  override get defaultOptions(): OpenSeadragon.BaseDrawerOptions {
    return { usePrivateCache: true, preloadCache: false };
  }

  /** WebGL2 must be available. */
  static override isSupported(): boolean {
    try {
      return document.createElement('canvas').getContext('webgl2') !== null;
    } catch {
      return false;
    }
  }

  override getType(): string {
    return RELIGHT_DRAWER_TYPE;
  }

  override getSupportedDataFormats(): string[] {
    return [BUNDLE_DATA_TYPE];
  }

  override canRotate(): boolean {
    return true;
  }

  /** Declare how a TiledImage is drawn. Items without a layer are not drawn. */
  setLayer(tiledImage: object, layer: RelightLayer): void {
    this.layers.set(tiledImage, layer);
  }

  /** Set the light (clamped to the unit disk). Call `viewer.forceRedraw()` afterwards. */
  setLight(lu: number, lv: number): void {
    this.light = lightFromProjection(lu, lv);
  }

  /** The current light. */
  getLight(): Light {
    return this.light;
  }

  override setImageSmoothingEnabled(enabled: boolean): void {
    this.smoothing = enabled;
    this.viewer.forceRedraw();
  }

  // Required by DrawerBase (called from its constructor, before this class's fields exist).
  _createDrawingElement(): HTMLCanvasElement {
    const canvas = document.createElement('canvas');
    const size = this.viewport.getContainerSize();
    canvas.width = Math.round(size.x * OpenSeadragon.pixelDensityRatio);
    canvas.height = Math.round(size.y * OpenSeadragon.pixelDensityRatio);
    return canvas;
  }

  override internalCacheCreate(cache: OpenSeadragon.CacheRecord, tile: OpenSeadragon.Tile): TileTexture {
    const bundle = cache.data as PlaneBundle;
    const source = (tile as unknown as TileLike).sourceBounds;
    const texScale: [number, number] = source
      ? [Math.min(source.width, bundle.width) / bundle.width, Math.min(source.height, bundle.height) / bundle.height]
      : [1, 1];
    const texture = this.gl.isContextLost() ? null : uploadPlaneBundle(this.gl, bundle);
    return { texture, texScale, generation: this.generation };
  }

  override internalCacheFree(data: TileTexture): void {
    if (data.texture && data.generation === this.generation && !this.gl.isContextLost()) {
      this.gl.deleteTexture(data.texture);
    }
    data.texture = null;
  }

  /** Draw one frame (called by OpenSeadragon). Calls `getTilesToDraw()` once per item. */
  draw(tiledImages: object[]): void {
    this.lastFrame = (tiledImages as TiledImageLike[]).map((item) => ({
      item,
      tiles: item.getTilesToDraw().map((info) => info.tile),
    }));
    this.render();
  }

  /**
   * Re-render the last frame synchronously and read it back.
   *
   * @returns RGBA bytes, rows top-down, at the canvas's device-pixel size
   */
  readPixels(): PixelData {
    this.render();
    const gl = this.gl;
    const width = gl.drawingBufferWidth;
    const height = gl.drawingBufferHeight;
    const bottomUp = new Uint8Array(width * height * 4);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, bottomUp);
    const data = new Uint8Array(bottomUp.length);
    const row = width * 4;
    for (let y = 0; y < height; y++) {
      data.set(bottomUp.subarray((height - 1 - y) * row, (height - y) * row), y * row);
    }
    return { width, height, data };
  }

  override destroy(): void {
    if (this.destroyed) {
      return;
    }
    this.destroyed = true;
    this.destroyInternalCache();
    super.destroy();
    this.canvas.removeEventListener('webglcontextlost', this.onLost);
    this.canvas.removeEventListener('webglcontextrestored', this.onRestored);
    const lose = this.gl.getExtension('WEBGL_lose_context');
    lose?.loseContext();
    this.canvas.width = 0;
    this.canvas.height = 0;
    this.canvas.remove();
  }

  private setupGl(): void {
    this.programs = createPrograms(this.gl);
    this.samplers = createSamplers(this.gl);
  }

  private resizeIfNeeded(): void {
    const size = this.viewport.getContainerSize();
    const w = Math.round(size.x * OpenSeadragon.pixelDensityRatio);
    const h = Math.round(size.y * OpenSeadragon.pixelDensityRatio);
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
  }

  private currentViewMatrix(): Mat3 {
    const bounds = this.viewport.getBoundsNoRotateWithMargins(true);
    const rotation = (this.viewport.getRotation(true) * Math.PI) / 180;
    return viewMatrix(bounds, rotation, this.viewport.getFlip());
  }

  private render(): void {
    const gl = this.gl;
    if (this.destroyed || gl.isContextLost() || !this.programs || !this.samplers) {
      return;
    }
    this.resizeIfNeeded();
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
    gl.disable(gl.BLEND);
    gl.disable(gl.DEPTH_TEST);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    const view = this.currentViewMatrix();
    const sampler = this.smoothing ? this.samplers.linear : this.samplers.nearest;
    for (const { item, tiles } of this.lastFrame) {
      const layer = this.layers.get(item);
      if (!layer || item.getOpacity() === 0 || tiles.length === 0) {
        continue;
      }
      const programInfo = this.programs[programKind(layer)];
      gl.useProgram(programInfo.program);
      twgl.setUniforms(programInfo, layerUniforms(layer, this.light.lu, this.light.lv));
      const itemMatrix = multiply(view, this.itemRotation(item));
      // Tiles come coarse level first; finer tiles are drawn over them (painter's algorithm), opaque.
      for (const tile of tiles) {
        const data = this.getDataToDraw(tile as unknown as OpenSeadragon.Tile) as TileTexture | undefined;
        if (!data?.texture) {
          continue;
        }
        const matrix = multiply(itemMatrix, modelMatrix(tile.positionedBounds, tile.flipped === true));
        gl.activeTexture(gl.TEXTURE0);
        gl.bindTexture(gl.TEXTURE_2D_ARRAY, data.texture);
        gl.bindSampler(0, sampler);
        twgl.setUniforms(programInfo, {
          [U_PLANES]: data.texture,
          [U_MATRIX]: new Float32Array(matrix),
          [U_TEX_SCALE]: data.texScale,
        });
        gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
      }
    }
    gl.bindSampler(0, null);
  }

  private itemRotation(item: TiledImageLike): Mat3 {
    const degrees = item.getRotation(true);
    if (degrees % 360 === 0) {
      return [1, 0, 0, 0, 1, 0, 0, 0, 1];
    }
    const a = (-degrees * Math.PI) / 180;
    const c = item.getBoundsNoRotate(true).getCenter();
    const cos = Math.cos(a);
    const sin = Math.sin(a);
    const rot: Mat3 = [cos, sin, 0, -sin, cos, 0, 0, 0, 1];
    return multiply(multiply([1, 0, 0, 0, 1, 0, c.x, c.y, 1], rot), [1, 0, 0, 0, 1, 0, -c.x, -c.y, 1]);
  }
}
