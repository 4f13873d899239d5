/**
 * `createViewer`: an OpenSeadragon viewer showing the relightable layer of a Lanterna manifest.
 */
import OpenSeadragon from 'openseadragon';
import { RelightDrawer, type PixelData } from './drawer/relight-drawer';
import { LanternaError } from './iiif/errors';
import { loadRelightManifest, type LoadedLayer } from './iiif/load';
import { lightFromPointer, lightFromProjection, type Light } from './math/light';
import { BundleTileSource } from './tiles/bundle-tile-source';
import { attachInteraction, type DragMode } from './ui/interaction';
import { createLightIndicator, type LightIndicator } from './ui/light-indicator';

/** Options of {@link createViewer}. */
export interface CreateViewerOptions {
  /** Container element (or its id). The viewer fills it. */
  element: HTMLElement | string;
  /** URL of the IIIF Presentation 3 manifest. */
  manifest: string;
  /** Initial light (lu, lv). @default [0, 0] */
  light?: readonly [number, number];
  /** What a plain drag does. @default 'light' */
  mode?: DragMode;
  /** Show the light indicator disc. @default true */
  lightIndicator?: boolean;
  /** Extra OpenSeadragon options (the drawer, navigator and tile sources are set by Lanterna). */
  osd?: Partial<OpenSeadragon.Options>;
  /** `fetch` options for the manifest and info.json requests. */
  fetchInit?: RequestInit;
}

/** A running Lanterna viewer. */
export interface LanternaViewer {
  /** Resolves once the manifest is loaded and the layer is added; rejects with a {@link LanternaError}. */
  readonly ready: Promise<void>;
  /** The OpenSeadragon viewer. */
  readonly viewer: OpenSeadragon.Viewer;
  /** The loaded manifest and plane information (null until ready). */
  readonly layer: LoadedLayer | null;
  /** Set the light projection (clamped to the unit disk) and redraw. */
  setLight(lu: number, lv: number): void;
  /** The current light. */
  getLight(): Light;
  /** Set what a plain drag does. */
  setMode(mode: DragMode): void;
  /** What a plain drag does. */
  getMode(): DragMode;
  /** Fit the rectangle (x, y, w, h) in image pixels into the viewer, immediately. */
  showImageRegion(x: number, y: number, width: number, height: number): void;
  /** Resolves when every tile needed for the current view is loaded and drawn. */
  whenFullyLoaded(): Promise<void>;
  /** Render a frame now and read it back: RGBA, rows top-down, device pixels. */
  readPixels(): PixelData;
  /** Remove the viewer and free its GL resources. */
  destroy(): void;
}

function nextFrame(): Promise<void> {
  return new Promise((resolve) => { requestAnimationFrame(() => { resolve(); }); });
}

/**
 * Create a viewer for a Lanterna manifest.
 *
 * @example
 * ```ts
 * const lanterna = createViewer({ element: 'viewer', manifest: 'https://example.org/datasets/ushabti/manifest.json' });
 * await lanterna.ready;
 * lanterna.setLight(0.5, 0.5);
 * ```
 */
export function createViewer(options: CreateViewerOptions): LanternaViewer {
  const element = typeof options.element === 'string' ? document.getElementById(options.element) : options.element;
  if (!element) {
    throw new LanternaError(`viewer element #${options.element as string} not found`);
  }
  let mode: DragMode = options.mode ?? 'light';
  let light = lightFromProjection(options.light?.[0] ?? 0, options.light?.[1] ?? 0);
  let layer: LoadedLayer | null = null;
  let destroyed = false;

  const viewer = OpenSeadragon({
    element,
    drawer: RelightDrawer,
    crossOriginPolicy: 'Anonymous',
    showNavigator: false,
    showNavigationControl: false,
    blendTime: 0,
    immediateRender: false,
    // Levels finer than needed (render ratio < 0.75) are skipped, so at 1 screen px = 2 image px the
    // next coarser level is drawn, never a half-faded finer one.
    minPixelRatio: 0.75,
    maxZoomPixelRatio: 16,
    minZoomImageRatio: 0.05,
    visibilityRatio: 0.1,
    maxImageCacheCount: 150,
    gestureSettingsMouse: { clickToZoom: false, dblClickToZoom: true },
    gestureSettingsTouch: { flickEnabled: false },
    silenceMultiImageWarnings: true,
    ...options.osd,
  });

  const drawer = (): RelightDrawer => {
    const d = viewer.drawer as unknown;
    if (!(d instanceof RelightDrawer)) {
      throw new LanternaError('the viewer is not using the Lanterna drawer (is WebGL2 available?)');
    }
    return d;
  };

  const indicator: LightIndicator | null = options.lightIndicator === false
    ? null : createLightIndicator(viewer.element);

  const applyLight = (): void => {
    drawer().setLight(light.lu, light.lv);
    indicator?.update(light);
    viewer.forceRedraw();
  };

  const detach = attachInteraction(viewer, {
    getMode: () => mode,
    moveLight: (x, y, w, h) => {
      light = lightFromPointer(x, y, w, h);
      applyLight();
    },
  });

  const ready = (async () => {
    layer = await loadRelightManifest(options.manifest, options.fetchInit);
    const loaded = layer;
    const previewIndex = loaded.layer.layerType === 'ptm' && loaded.layer.colorspace === 'lrgb' ? 2 : 0;
    const source = new BundleTileSource({
      infos: loaded.infos,
      geometry: loaded.geometry,
      formats: loaded.layer.planes.map((p) => p.format),
      previewIndex,
    });
    await new Promise<void>((resolve, reject) => {
      viewer.addTiledImage({
        tileSource: source as unknown as OpenSeadragon.TileSource,
        x: 0,
        y: 0,
        width: 1,
        success: (event: { item: OpenSeadragon.TiledImage }) => {
          drawer().setLayer(event.item, loaded.layer);
          resolve();
        },
        error: (event: { message?: string }) => {
          reject(new LanternaError(`cannot open the layer: ${event.message ?? 'unknown error'}`));
        },
      } as unknown as Parameters<OpenSeadragon.Viewer['addTiledImage']>[0]);
    });
    applyLight();
  })();
  // Avoid an unhandled rejection if the caller never awaits `ready`.
  ready.catch(() => undefined);

  const item = (): OpenSeadragon.TiledImage => {
    const ti = viewer.world.getItemAt(0) as OpenSeadragon.TiledImage | undefined;
    if (!ti) {
      throw new LanternaError('the layer is not open yet (await ready)');
    }
    return ti;
  };

  return {
    ready,
    viewer,
    get layer() { return layer; },
    setLight(lu: number, lv: number) {
      light = lightFromProjection(lu, lv);
      applyLight();
    },
    getLight: () => light,
    setMode(m: DragMode) { mode = m; },
    getMode: () => mode,
    showImageRegion(x: number, y: number, width: number, height: number) {
      const rect = item().imageToViewportRectangle(x, y, width, height);
      // No viewport.update() here: OSD's own update must see the change to recompute the levels.
      viewer.viewport.fitBounds(rect, true);
      viewer.forceRedraw();
    },
    async whenFullyLoaded() {
      // Let OSD run at least one update for the current view, then wait for a frame that was drawn
      // with every item fully loaded and nothing animating.
      let stable = 0;
      for (let frame = 0; stable < 3; frame++) {
        await nextFrame();
        if (destroyed) {
          throw new LanternaError('viewer destroyed');
        }
        const count = viewer.world.getItemCount();
        let loaded = count > 0;
        for (let i = 0; i < count; i++) {
          loaded &&= viewer.world.getItemAt(i).getFullyLoaded();
        }
        stable = loaded && !(viewer as unknown as { isAnimating(): boolean }).isAnimating() && frame >= 2 ? stable + 1 : 0;
        if (stable === 1) {
          viewer.forceRedraw();
        }
      }
    },
    readPixels: () => drawer().readPixels(),
    destroy() {
      if (destroyed) {
        return;
      }
      destroyed = true;
      detach();
      indicator?.destroy();
      viewer.destroy();
    },
  };
}
