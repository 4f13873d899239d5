/**
 * `RelightDrawer`: an OpenSeadragon drawer that relights plane bundles with WebGL2, straight into
 * its own on-screen canvas. This is the only module that touches OpenSeadragon drawer internals.
 *
 * It keeps the tile textures and the viewer's settings, and describes each frame (which items are
 * base layers, the lens layer or overlays, and where) to the {@link FrameRenderer}, which draws it.
 *
 * A lost WebGL context is kept restorable; on restoration the programs and float targets are made
 * again on first use and each tile's texture is uploaded again from its cached bundle (OpenSeadragon
 * keeps the decoded planes in its tile cache, so nothing is fetched again). While the context is
 * lost, frames draw nothing and nothing throws.
 */
import OpenSeadragon from 'openseadragon';
import { LanternaError } from '../errors';
import type { RelightLayer } from '../iiif/relight-service';
import { resolveLayer, type ResolvedLayer } from '../layers/resolved-layer';
import type { AnnotationDisplay } from '../lens/lens-state';
import { lensInDevicePixels } from '../math/lens';
import { OVERHEAD_LIGHT, type Light } from '../math/light';
import { modelMatrix, multiply, viewMatrix, type Mat3 } from '../math/matrix';
import { DEFAULT_RENDER_MODE, type RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, type RenderParams } from '../render/params';
import { BUNDLE_DATA_TYPE, type PlaneBundle } from '../tiles/bundle';
import type { Compositor, DrawerLens } from './compositor';
import { FrameRenderer } from './frame-renderer';
import type { TileQuad } from './layer-pass';
import { freeTileTexture, uploadedTexture, type TileTexture } from './plane-texture';
import { ContextWatch } from './context-watch';
import { FrameScheduler } from './frame-scheduler';
import { sceneKey, sortItems, type ItemLike } from './frame-items';
import { prepareFrameTiles, type FrameEntry } from './frame-tiles';
import { readCanvasPixels, type PixelData } from './read-pixels';

export type { PixelData } from './read-pixels';

/** The drawer's type name (`getType()`). */
export const RELIGHT_DRAWER_TYPE = 'lanterna';

/** WebGL2 is not available. */
export class WebGLUnavailableError extends LanternaError {}

/** What the drawer reports to the viewer (see {@link RelightDrawer.setEvents}). */
export interface DrawerEvents {
  /** The WebGL context was lost (`true`), or restored and a frame redrawn (`false`). */
  context(lost: boolean): void;
  /** A frame could not be drawn (each distinct message once); the drawer carries on. */
  error(error: unknown): void;
}

/** Minimal view of the OSD objects the drawer reads (typed locally: the shipped types omit them). */
interface TileLike {
  positionedBounds: OpenSeadragon.Rect;
  sourceBounds?: OpenSeadragon.Rect;
  flipped?: boolean;
  /** Squared distance of the tile's centre from the view's centre (set by OSD each update). */
  squaredDistance?: number | null;
}
interface TiledImageLike extends ItemLike {
  getTilesToDraw(): { tile: TileLike }[];
  getFullyLoaded(): boolean;
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
  declare private frames: FrameRenderer | null;
  declare private mode: RenderMode;
  declare private params: RenderParams;
  declare private layers: WeakMap<object, ResolvedLayer>;
  declare private resolved: WeakMap<RelightLayer, ResolvedLayer>;
  declare private roles: WeakMap<object, 'lens' | 'overlay'>;
  declare private overlayOrder: WeakMap<object, number>;
  declare private lens: DrawerLens | null;
  declare private overlayDisplay: AnnotationDisplay;
  declare private light: Light;
  declare private smoothing: boolean;
  declare private lastFrame: FrameEntry<TiledImageLike, TileLike>[];
  declare private scheduler: FrameScheduler;
  /** Bumped by every setting that changes the picture (light, mode, lens...): part of the frame key. */
  declare private settings: number;
  declare private destroyed: boolean;
  declare private context: ContextWatch;
  declare private events: DrawerEvents | null;
  declare private reported: Set<string>;

  constructor(options: ConstructorParameters<typeof OpenSeadragon.DrawerBase>[0]) {
    super(options);
    this.layers = new WeakMap();
    this.resolved = new WeakMap();
    this.roles = new WeakMap();
    this.overlayOrder = new WeakMap();
    this.lens = null;
    this.overlayDisplay = 'everywhere';
    this.light = OVERHEAD_LIGHT;
    this.smoothing = true;
    this.lastFrame = [];
    this.destroyed = false;
    this.frames = null;
    this.mode = DEFAULT_RENDER_MODE;
    this.params = DEFAULT_RENDER_PARAMS;
    const gl = this.canvas.getContext('webgl2', CONTEXT_ATTRIBUTES);
    if (!gl) {
      throw new WebGLUnavailableError('WebGL2 is not available');
    }
    this.gl = gl;
    this.frames = new FrameRenderer(gl);
    this.settings = 0;
    this.scheduler = new FrameScheduler(gl, () => { this.viewer.forceRedraw(); });
    this.events = null;
    this.reported = new Set();
    this.context = new ContextWatch(this.canvas, gl, {
      lost: () => { this.events?.context(true); },
      restored: () => {
        // The old programs, targets and textures went with the old context: forget them, and let
        // the next frame make them again (tile textures from their bundles, see currentTexture).
        this.frames?.forget();
        this.frames = new FrameRenderer(this.gl);
        this.scheduler.reset();
        this.reported.clear();
        this.viewer.forceRedraw();
        this.events?.context(false);
      },
    });
  }

  /** Tell `events` about context losses and restorations and about frames that failed. */
  setEvents(events: DrawerEvents | null): void {
    this.events = events;
  }

  /** True while the WebGL context is lost. */
  isContextLost(): boolean {
    return this.context.lost;
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
    this.layers.set(tiledImage, this.resolve(layer));
    this.settings++;
  }

  /** Draw `tiledImage` as the lens layer: inside the lens only (see {@link RelightDrawer.setLens}). */
  setLensItem(tiledImage: object, layer: RelightLayer): void {
    this.layers.set(tiledImage, this.resolve(layer));
    this.roles.set(tiledImage, 'lens');
    this.settings++;
  }

  /** Draw `tiledImage` (one plane of straight-alpha RGBA) as an overlay, in increasing `order`. */
  setOverlayItem(tiledImage: object, order = 0): void {
    this.roles.set(tiledImage, 'overlay');
    this.overlayOrder.set(tiledImage, order);
    this.settings++;
  }

  /**
   * The lens (circle in CSS px of the viewer element, opacity, the lens layer's mode and
   * parameters), or null when it is off. Call `viewer.forceRedraw()` afterwards.
   */
  setLens(lens: DrawerLens | null): void {
    this.lens = lens;
    this.settings++;
  }

  /** Where overlays show relative to the lens (ignored while the lens is off). */
  setOverlayDisplay(display: AnnotationDisplay): void {
    this.overlayDisplay = display;
    this.settings++;
  }

  /**
   * Set the light (from `lightFromProjection`, `lightFromPointer` or `nudgeLight`, which clamp it;
   * it is used as given). Call `viewer.forceRedraw()` afterwards.
   */
  setLight(light: Light): void {
    this.light = light;
    this.settings++;
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
    this.settings++;
  }

  /** The render mode. */
  getRenderMode(): RenderMode {
    return this.mode;
  }

  /** Set the render parameters (already clamped). Call `viewer.forceRedraw()` afterwards. */
  setRenderParams(params: RenderParams): void {
    this.params = params;
    this.settings++;
  }

  /**
   * Compile the programs a layer needs in a mode now, so that errors surface here rather than
   * during a frame.
   *
   * @throws {@link ShaderError} or {@link FloatTargetsUnavailableError}
   */
  prepare(layer: RelightLayer, mode: RenderMode, params: RenderParams = this.params): void {
    if (this.context.lost) {
      return; // compiled on first use once the context is back
    }
    this.frames?.prepare(this.resolve(layer), mode, params);
  }

  override setImageSmoothingEnabled(enabled: boolean): void {
    this.smoothing = enabled;
    this.settings++;
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
    // Uploaded by the frames that draw the tile, within their budget (see frame-tiles.ts).
    return { texture: null, texScale, generation: -1, bundle };
  }

  override internalCacheFree(data: TileTexture): void {
    freeTileTexture(this.gl, data, this.context.generation);
  }

  /**
   * Called by OpenSeadragon at most once per animation frame (its update loop); calls
   * `getTilesToDraw()` once per item. Uploads the frame's new tile textures (within a budget
   * unless the scene changed) and renders the relit frame only if it is due: never again for an
   * unchanged frame, and while tiles load not more often than the GPU can afford (frame-schedule.ts).
   * Items that are not Lanterna's (not given to setLayer, setLensItem or setOverlayItem: a page's own
   * images, `attachLanterna`) are left out: their tiles have no plane bundles to draw.
   */
  draw(tiledImages: object[]): void {
    this.lastFrame = (tiledImages as TiledImageLike[]).map((item) => ({
      item,
      tiles: item.getTilesToDraw().map((info) => info.tile),
    })).filter(({ item }) => this.layers.has(item) || this.roles.has(item));
    if (this.destroyed || this.gl.isContextLost() || !this.frames) {
      return;
    }
    this.resizeIfNeeded();
    const scene = sceneKey(this.canvas, this.settings, this.currentViewMatrix(), this.lastFrame.map((e) => e.item));
    const tiles = this.prepareTiles(this.scheduler.sceneChanged(scene));
    this.scheduler.frame({ key: { scene, tiles: tiles.key }, uploadsPending: tiles.pending, loading: tiles.loading },
      () => { this.render(); });
  }

  /** Set how many tile bundles OpenSeadragon's tile cache keeps (its `maxImageCacheCount`). */
  setTileCacheCount(count: number): void {
    (this.viewer.tileCache as unknown as { _maxCacheItemCount: number })._maxCacheItemCount = count;
  }

  /** Relit frames rendered for the screen so far (read-backs not counted): for tests and benchmarks. */
  getFrameCount(): number {
    return this.scheduler.frames;
  }

  /** True when the screen shows the current state: no frame put off, no texture waiting for upload. */
  isSettled(): boolean {
    return this.scheduler.settled;
  }

  /**
   * Re-render the last frame synchronously (every texture uploaded first) and read it back.
   *
   * @returns RGBA bytes, rows top-down, at the canvas's device-pixel size
   */
  readPixels(): PixelData {
    if (!this.destroyed && !this.gl.isContextLost()) {
      this.prepareTiles(true);
    }
    this.render();
    return readCanvasPixels(this.gl);
  }

  override destroy(): void {
    if (this.destroyed) {
      return;
    }
    this.destroyed = true;
    this.destroyInternalCache();
    this.scheduler.destroy();
    this.frames?.destroy();
    super.destroy();
    this.context.destroy();
    this.events = null;
    const lose = this.gl.getExtension('WEBGL_lose_context');
    lose?.loseContext();
    this.canvas.width = 0;
    this.canvas.height = 0;
    this.canvas.remove();
  }

  /** A layer resolved (kind, program, fixed uniforms), once per layer object. */
  private resolve(layer: RelightLayer): ResolvedLayer {
    let resolved = this.resolved.get(layer);
    if (!resolved) {
      resolved = resolveLayer(layer);
      this.resolved.set(layer, resolved);
    }
    return resolved;
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

  /** The last frame's tile textures, uploaded (all of them, or within the frame's budget). */
  private prepareTiles(all: boolean): { key: unknown[]; pending: boolean; loading: boolean } {
    return prepareFrameTiles(this.lastFrame, {
      gl: this.gl,
      generation: this.context.generation,
      all,
      textureOf: (tile) => this.getDataToDraw(tile as unknown as OpenSeadragon.Tile) as TileTexture | undefined,
    });
  }

  /** Describe the last frame's items to the frame renderer and draw it. */
  private render(): void {
    const gl = this.gl;
    if (this.destroyed || gl.isContextLost() || !this.frames) {
      return;
    }
    this.resizeIfNeeded();
    const view = this.currentViewMatrix();
    const { layers, lensLayer, overlays } = sortItems(this.lastFrame, view, (item) => this.roles.get(item),
      (item) => this.layers.get(item), (item) => this.overlayOrder.get(item) ?? 0);
    const lens = this.lens;
    try {
      this.frames.render({
        layers, lensLayer, overlays,
        quadOf: (tile, itemMatrix) => this.quadOf(tile, itemMatrix),
        mode: this.mode,
        params: this.params,
        light: this.light,
        lens,
        circle: lens ? lensInDevicePixels(lens, OpenSeadragon.pixelDensityRatio, gl.drawingBufferHeight) : null,
        overlayDisplay: this.overlayDisplay,
        smoothing: this.smoothing,
      });
    } catch (error) {
      // Never throw into OpenSeadragon's animation loop: report the error (once) and go on.
      this.report(error);
    }
  }

  /** Report a frame error once per distinct message (none while the context is lost: expected). */
  private report(error: unknown): void {
    if (this.context.lost) {
      return;
    }
    const key = error instanceof Error ? `${error.name}: ${error.message}` : String(error);
    if (this.reported.has(key)) {
      return;
    }
    this.reported.add(key);
    if (this.events) {
      this.events.error(error);
    } else {
      console.error('[lanterna] a frame could not be drawn:', error);
    }
  }

  /** A tile's texture and placement (null while it has no texture). */
  private quadOf(tile: TileLike, itemMatrix: Mat3): TileQuad | null {
    const data = this.getDataToDraw(tile as unknown as OpenSeadragon.Tile) as TileTexture | undefined;
    const texture = data ? uploadedTexture(this.gl, data, this.context.generation) : null;
    if (!data || !texture) {
      return null;
    }
    return {
      texture,
      matrix: multiply(itemMatrix, modelMatrix(tile.positionedBounds, tile.flipped === true)),
      texScale: data.texScale,
    };
  }
}
