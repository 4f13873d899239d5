/**
 * `RelightDrawer`: an OpenSeadragon drawer that relights plane bundles with WebGL2, straight into
 * its own on-screen canvas. This is the only module that touches OpenSeadragon drawer internals.
 *
 * A frame is drawn in three steps: the base layers (opaque), the lens layer (into a target, then
 * composited inside the lens circle with its opacity), then the annotation overlays (premultiplied
 * source-over, everywhere or only inside or outside the lens).
 */
import OpenSeadragon from 'openseadragon';
import * as twgl from 'twgl.js';
import { LanternaError } from '../iiif/errors';
import type { RelightLayer } from '../iiif/relight-service';
import type { Compositor, DrawerLens } from '../compositor';
import type { Stage } from '../gl/glsl/modes.glsl';
import type { AnnotationDisplay } from '../lens/lens-state';
import { lensInDevicePixels } from '../math/lens';
import { layerUniforms, type LayerUniforms } from '../layers/layer-uniforms';
import { ProgramCache, programSpec, type ProgramSpec } from '../layers/programs';
import { lightFromProjection, OVERHEAD_LIGHT, type Light } from '../math/light';
import { modelMatrix, multiply, viewMatrix, type Mat3 } from '../math/matrix';
import { modeFilter } from '../render/filter-plan';
import { applicableModes, DEFAULT_RENDER_MODE, type RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, type RenderParams } from '../render/params';
import { BUNDLE_DATA_TYPE, type PlaneBundle } from '../tiles/bundle';
import { U_FILTERED, U_MATRIX, U_PLANES, U_TEX_SCALE } from '../gl/uniforms';
import { LensTarget, scissorBox, type DeviceCircle } from './lens-target';
import { OverlayPass, type OverlayQuad } from './overlay-pass';
import { createSamplers, uploadPlaneBundle } from './plane-texture';
import { ScreenFilter } from './screen-filter';

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
 * register each relightable TiledImage with {@link RelightDrawer.setLayer} (base layers),
 * {@link RelightDrawer.setLensItem} (the lens) or {@link RelightDrawer.setOverlayItem} (overlays).
 */
export class RelightDrawer extends OpenSeadragon.DrawerBase implements Compositor {
  declare private gl: WebGL2RenderingContext;
  declare private programs: ProgramCache | null;
  declare private screenFilter: ScreenFilter | null;
  declare private mode: RenderMode;
  declare private params: RenderParams;
  declare private samplers: { linear: WebGLSampler; nearest: WebGLSampler } | null;
  declare private layers: WeakMap<object, RelightLayer>;
  declare private roles: WeakMap<object, 'lens' | 'overlay'>;
  declare private lens: DrawerLens | null;
  declare private overlayDisplay: AnnotationDisplay;
  declare private lensTarget: LensTarget | null;
  declare private overlayPass: OverlayPass | null;
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
    this.roles = new WeakMap();
    this.lens = null;
    this.overlayDisplay = 'everywhere';
    this.lensTarget = null;
    this.overlayPass = null;
    this.light = OVERHEAD_LIGHT;
    this.smoothing = true;
    this.generation = 0;
    this.lastFrame = [];
    this.destroyed = false;
    this.programs = null;
    this.screenFilter = null;
    this.samplers = null;
    this.mode = DEFAULT_RENDER_MODE;
    this.params = DEFAULT_RENDER_PARAMS;
    const gl = this.canvas.getContext('webgl2', CONTEXT_ATTRIBUTES);
    if (!gl) {
      throw new WebGLUnavailableError('WebGL2 is not available');
    }
    this.gl = gl;
    this.setupGl();
    this.onLost = (e: Event) => { e.preventDefault(); };
    this.onRestored = () => {
      this.generation++;
      this.programs?.clear();
      this.screenFilter = null;
      this.lensTarget = null;
      this.overlayPass = null;
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

  /** Draw `tiledImage` as the lens layer: inside the lens only (see {@link RelightDrawer.setLens}). */
  setLensItem(tiledImage: object, layer: RelightLayer): void {
    this.layers.set(tiledImage, layer);
    this.roles.set(tiledImage, 'lens');
  }

  /** Draw `tiledImage` (a one-plane bundle of RGBA with straight alpha) as an annotation overlay. */
  setOverlayItem(tiledImage: object): void {
    this.roles.set(tiledImage, 'overlay');
  }

  /**
   * The lens (circle in CSS px of the viewer element, opacity, the lens layer's mode and
   * parameters), or null when it is off. Call `viewer.forceRedraw()` afterwards.
   */
  setLens(lens: DrawerLens | null): void {
    this.lens = lens;
  }

  /** Where overlays show relative to the lens (ignored while the lens is off). */
  setOverlayDisplay(display: AnnotationDisplay): void {
    this.overlayDisplay = display;
  }

  /** Set the light (clamped to the unit disk). Call `viewer.forceRedraw()` afterwards. */
  setLight(lu: number, lv: number): void {
    this.light = lightFromProjection(lu, lv);
  }

  /** The current light. */
  getLight(): Light {
    return this.light;
  }

  /**
   * Set the render mode (layers it does not apply to are drawn in `color`). Call
   * `viewer.forceRedraw()` afterwards.
   */
  setRenderMode(mode: RenderMode): void {
    this.mode = mode;
  }

  /** The render mode. */
  getRenderMode(): RenderMode {
    return this.mode;
  }

  /** Set the render parameters (already clamped). Call `viewer.forceRedraw()` afterwards. */
  setRenderParams(params: RenderParams): void {
    this.params = params;
  }

  /**
   * Compile the programs a layer needs in a mode now, so that errors surface here rather than
   * during a frame.
   *
   * @throws {@link ShaderError} or {@link FloatTargetsUnavailableError}
   */
  prepare(layer: RelightLayer, mode: RenderMode, params: RenderParams = this.params): void {
    if (!this.programs) {
      return;
    }
    const kind = programSpec(layer);
    const gammaOne = params.gamma === 1;
    if (modeFilter(mode)) {
      this.screenFilter ??= new ScreenFilter(this.gl);
      this.programs.get(kind, mode, 'quantity', gammaOne);
      this.programs.get(kind, mode, 'combine', gammaOne);
    } else {
      this.programs.get(kind, mode, 'direct', gammaOne);
    }
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
    this.programs?.clear();
    this.screenFilter?.destroy();
    this.lensTarget?.destroy();
    this.overlayPass?.destroy();
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
    this.programs = new ProgramCache(this.gl);
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
    let lensEntry: { item: TiledImageLike; tiles: TileLike[]; layer: RelightLayer } | null = null;
    const overlays: { item: TiledImageLike; tiles: TileLike[] }[] = [];
    for (const { item, tiles } of this.lastFrame) {
      if (item.getOpacity() === 0 || tiles.length === 0) {
        continue;
      }
      const role = this.roles.get(item);
      const layer = this.layers.get(item);
      if (role === 'overlay') {
        overlays.push({ item, tiles });
      } else if (layer && role === 'lens') {
        lensEntry = { item, tiles, layer };
      } else if (layer) {
        this.drawLayer(item, tiles, layer, this.mode, this.params, view, null);
      }
    }
    const circle = this.lens ? this.deviceCircle(this.lens) : null;
    if (this.lens && circle && lensEntry && this.lens.opacity > 0) {
      const box = scissorBox(circle, gl.drawingBufferWidth, gl.drawingBufferHeight);
      this.lensTarget ??= new LensTarget(gl);
      this.lensTarget.begin(gl.drawingBufferWidth, gl.drawingBufferHeight, box);
      this.drawLayer(lensEntry.item, lensEntry.tiles, lensEntry.layer, this.lens.mode, this.lens.params, view,
        this.lensTarget.framebuffer, box);
      this.lensTarget.composite(circle, this.lens.opacity, box);
    }
    if (overlays.length > 0) {
      this.drawOverlays(overlays, view, circle);
    }
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, null);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindSampler(0, null);
  }

  /** The lens in device pixels, y up. */
  private deviceCircle(lens: DrawerLens): DeviceCircle {
    return lensInDevicePixels(lens, OpenSeadragon.pixelDensityRatio, this.gl.drawingBufferHeight);
  }

  /**
   * Relight one item into `target` (null = the canvas) in `mode` with `params`; `box` is a scissor
   * box applied to the final stage (the unsharp modes filter the whole view first).
   */
  private drawLayer(item: TiledImageLike, tiles: TileLike[], layer: RelightLayer, requested: RenderMode,
    params: RenderParams, view: Mat3, target: WebGLFramebuffer | null,
    box: readonly [number, number, number, number] | null = null): void {
    const gl = this.gl;
    const mode = applicableModes(layer).includes(requested) ? requested : DEFAULT_RENDER_MODE;
    const kind = programSpec(layer);
    const uniforms = layerUniforms(layer, this.light.lu, this.light.lv, params);
    const itemMatrix = multiply(view, this.itemRotation(item));
    const gammaOne = params.gamma === 1;
    const filter = modeFilter(mode);
    const bindTarget = (): void => {
      gl.bindFramebuffer(gl.FRAMEBUFFER, target);
      gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
      if (box) {
        gl.enable(gl.SCISSOR_TEST);
        gl.scissor(box[0], box[1], box[2], box[3]);
      }
    };
    if (!filter) {
      bindTarget();
      this.drawTiles(kind, mode, 'direct', uniforms, itemMatrix, tiles, null, gammaOne);
      gl.disable(gl.SCISSOR_TEST);
      return;
    }
    // Screen-space unsharp masking: quantity for the whole view, box passes, then combine.
    gl.disable(gl.SCISSOR_TEST);
    this.screenFilter ??= new ScreenFilter(gl);
    this.screenFilter.beginQuantity(gl.drawingBufferWidth, gl.drawingBufferHeight);
    this.drawTiles(kind, mode, 'quantity', uniforms, itemMatrix, tiles, null, gammaOne);
    const filtered = this.screenFilter.filter(filter);
    bindTarget();
    this.drawTiles(kind, mode, 'combine', uniforms, itemMatrix, tiles, filtered, gammaOne);
    gl.disable(gl.SCISSOR_TEST);
  }

  /** Draw overlay tiles over the frame, masked by the lens. */
  private drawOverlays(entries: { item: TiledImageLike; tiles: TileLike[] }[], view: Mat3,
    circle: DeviceCircle | null): void {
    if (!this.samplers) {
      return;
    }
    const quads: OverlayQuad[] = [];
    for (const { item, tiles } of entries) {
      const itemMatrix = multiply(view, this.itemRotation(item));
      for (const tile of tiles) {
        const data = this.getDataToDraw(tile as unknown as OpenSeadragon.Tile) as TileTexture | undefined;
        if (data?.texture) {
          quads.push({
            texture: data.texture,
            matrix: multiply(itemMatrix, modelMatrix(tile.positionedBounds, tile.flipped === true)),
            texScale: data.texScale,
          });
        }
      }
    }
    this.overlayPass ??= new OverlayPass(this.gl);
    this.overlayPass.draw(quads, circle, this.overlayDisplay, this.smoothing ? this.samplers.linear : this.samplers.nearest);
  }

  /** Draw an item's tiles (coarse level first, finer over them: painter's algorithm, opaque). */
  private drawTiles(kind: ProgramSpec, mode: RenderMode, stage: Stage, uniforms: LayerUniforms,
    itemMatrix: Mat3, tiles: TileLike[], filtered: WebGLTexture | null, gammaOne: boolean): void {
    const gl = this.gl;
    if (!this.programs || !this.samplers) {
      return;
    }
    const programInfo = this.programs.get(kind, mode, stage, gammaOne);
    gl.useProgram(programInfo.program);
    twgl.setUniforms(programInfo, uniforms);
    gl.uniform1i(gl.getUniformLocation(programInfo.program, U_PLANES), 0);
    if (filtered) {
      gl.activeTexture(gl.TEXTURE1);
      gl.bindTexture(gl.TEXTURE_2D, filtered);
      gl.bindSampler(1, null);
      gl.uniform1i(gl.getUniformLocation(programInfo.program, U_FILTERED), 1);
    }
    gl.activeTexture(gl.TEXTURE0);
    gl.bindSampler(0, this.smoothing ? this.samplers.linear : this.samplers.nearest);
    for (const tile of tiles) {
      const data = this.getDataToDraw(tile as unknown as OpenSeadragon.Tile) as TileTexture | undefined;
      if (!data?.texture) {
        continue;
      }
      const matrix = multiply(itemMatrix, modelMatrix(tile.positionedBounds, tile.flipped === true));
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, data.texture);
      twgl.setUniforms(programInfo, {
        [U_MATRIX]: new Float32Array(matrix),
        [U_TEX_SCALE]: data.texScale,
      });
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    }
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
