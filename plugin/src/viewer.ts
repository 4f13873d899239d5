/**
 * `createViewer`: an OpenSeadragon viewer showing the relightable layers of a Lanterna manifest,
 * one TiledImage per layer (inactive layers at opacity 0, so they load nothing).
 */
import OpenSeadragon from 'openseadragon';
import { RelightDrawer, type PixelData } from './drawer/relight-drawer';
import { LanternaError } from './iiif/errors';
import { fetchJson, loadLayer, type InfoCache, type LoadedLayer } from './iiif/load';
import { parseManifest, type ManifestInfo, type ManifestLayer } from './iiif/manifest';
import type { LayerType } from './iiif/relight-service';
import { lightFromPointer, lightFromProjection, type Light } from './math/light';
import { applicableModes, DEFAULT_RENDER_MODE, isRenderMode, shadingClass, type RenderMode } from './render/modes';
import { DEFAULT_RENDER_PARAMS, mergeParams, type RenderParams } from './render/params';
import { BundleTileSource } from './tiles/bundle-tile-source';
import { attachInteraction, type DragMode } from './ui/interaction';
import { createLightWidget, type LightWidget } from './ui/light-widget';

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
  /** Id of the layer shown first. @default the manifest's first layer */
  layer?: string;
  /** Show the light widget (a draggable, keyboard-controlled disc). @default true */
  lightIndicator?: boolean;
  /** Extra OpenSeadragon options (the drawer, navigator and tile sources are set by Lanterna). */
  osd?: Partial<OpenSeadragon.Options>;
  /** `fetch` options for the manifest and info.json requests. */
  fetchInit?: RequestInit;
}

/** A layer as listed by {@link LanternaViewer.getLayers}. */
export interface LayerInfo {
  readonly id: string;
  readonly label: string;
  readonly layerType: LayerType;
  /** The render modes that apply to it, in menu order. */
  readonly modes: RenderMode[];
}

/** A render mode that is unknown or does not apply to the active layer. */
export class RenderModeError extends LanternaError {}
/** No layer has this id. */
export class UnknownLayerError extends LanternaError {}

/** A running Lanterna viewer. */
export interface LanternaViewer {
  /** Resolves once the manifest is loaded and the default layer is added; rejects with a {@link LanternaError}. */
  readonly ready: Promise<void>;
  /** The OpenSeadragon viewer. */
  readonly viewer: OpenSeadragon.Viewer;
  /** The parsed manifest (null until ready). */
  readonly manifest: ManifestInfo | null;
  /** The active layer with its plane information (null until ready). */
  readonly layer: LoadedLayer | null;
  /** Set the light projection (clamped to the unit disk) and redraw. */
  setLight(lu: number, lv: number): void;
  /** The current light. */
  getLight(): Light;
  /** Set what a plain drag does. */
  setMode(mode: DragMode): void;
  /** What a plain drag does. */
  getMode(): DragMode;
  /** The layers, in manifest order (empty until ready). */
  getLayers(): LayerInfo[];
  /** Show another layer (loads its plane information on first use); rejects with {@link UnknownLayerError}. */
  setActiveLayer(id: string): Promise<void>;
  /** The active layer's id ('' until ready). */
  getActiveLayer(): string;
  /** Set the render mode; throws {@link RenderModeError} if it does not apply to the active layer. */
  setRenderMode(mode: RenderMode): void;
  /** The render mode. */
  getRenderMode(): RenderMode;
  /** Change some render parameters (clamped to their ranges; unknown keys ignored). */
  setRenderParams(params: Partial<RenderParams>): void;
  /** The render parameters. */
  getRenderParams(): RenderParams;
  /** Set every render parameter back to its default. */
  resetRenderParams(): void;
  /** Call `listener` after any change of light, layer, mode or parameters; returns an unsubscribe function. */
  onChange(listener: () => void): () => void;
  /** Fit the rectangle (x, y, w, h) in image pixels into the viewer, immediately. */
  showImageRegion(x: number, y: number, width: number, height: number): void;
  /** Resolves when every tile needed for the current view is loaded and drawn. */
  whenFullyLoaded(): Promise<void>;
  /** Render a frame now and read it back: RGBA, rows top-down, device pixels. */
  readPixels(): PixelData;
  /** Remove the viewer and free its GL resources. */
  destroy(): void;
}

interface LayerSlot {
  readonly info: ManifestLayer;
  loaded?: LoadedLayer;
  item?: Promise<OpenSeadragon.TiledImage>;
  tiledImage?: OpenSeadragon.TiledImage;
}

function nextFrame(): Promise<void> {
  return new Promise((resolve) => { requestAnimationFrame(() => { resolve(); }); });
}

function previewIndex(layer: LoadedLayer['layer']): number {
  return layer.layerType === 'ptm' && layer.colorspace === 'lrgb' ? 2 : 0;
}

/**
 * Create a viewer for a Lanterna manifest.
 *
 * @example
 * ```ts
 * const lanterna = createViewer({ element: 'viewer', manifest: 'https://example.org/datasets/ushabti/manifest.json' });
 * await lanterna.ready;
 * lanterna.setLight(0.5, 0.5);
 * lanterna.setRenderMode('specular');
 * ```
 */
export function createViewer(options: CreateViewerOptions): LanternaViewer {
  const element = typeof options.element === 'string' ? document.getElementById(options.element) : options.element;
  if (!element) {
    throw new LanternaError(`viewer element #${options.element as string} not found`);
  }
  let dragMode: DragMode = options.mode ?? 'light';
  let light = lightFromProjection(options.light?.[0] ?? 0, options.light?.[1] ?? 0);
  let renderMode: RenderMode = DEFAULT_RENDER_MODE;
  let params: RenderParams = DEFAULT_RENDER_PARAMS;
  let manifest: ManifestInfo | null = null;
  let active: LayerSlot | null = null;
  const slots = new Map<string, LayerSlot>();
  const infoCache: InfoCache = new Map();
  const listeners = new Set<() => void>();
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

  const changed = (): void => {
    viewer.forceRedraw();
    for (const l of listeners) {
      l();
    }
  };

  const widget: LightWidget | null = options.lightIndicator === false ? null : createLightWidget(viewer.element, {
    getLight: () => light,
    setLight: (l) => { api.setLight(l.lu, l.lv); },
  });

  const applyLight = (): void => {
    drawer().setLight(light.lu, light.lv);
    widget?.update(light);
    changed();
  };

  const detach = attachInteraction(viewer, {
    getMode: () => dragMode,
    moveLight: (x, y, w, h) => {
      light = lightFromPointer(x, y, w, h);
      applyLight();
    },
  });

  const addItem = (loaded: LoadedLayer, opacity: number): Promise<OpenSeadragon.TiledImage> => {
    const source = new BundleTileSource({
      infos: loaded.infos,
      geometry: loaded.geometry,
      formats: loaded.layer.planes.map((p) => p.format),
      previewIndex: previewIndex(loaded.layer),
    });
    return new Promise((resolve, reject) => {
      viewer.addTiledImage({
        tileSource: source as unknown as OpenSeadragon.TileSource,
        x: 0,
        y: 0,
        width: 1,
        opacity,
        success: (event: { item: OpenSeadragon.TiledImage }) => {
          drawer().setLayer(event.item, loaded.layer);
          resolve(event.item);
        },
        error: (event: { message?: string }) => {
          reject(new LanternaError(`cannot open layer ${loaded.id}: ${event.message ?? 'unknown error'}`));
        },
      } as unknown as Parameters<OpenSeadragon.Viewer['addTiledImage']>[0]);
    });
  };

  /** Load a layer's plane information and add its (invisible) TiledImage, once. */
  const itemOf = (slot: LayerSlot): Promise<OpenSeadragon.TiledImage> => {
    slot.item ??= (async () => {
      slot.loaded ??= await loadLayer(slot.info, options.fetchInit, infoCache);
      slot.tiledImage = await addItem(slot.loaded, 0);
      return slot.tiledImage;
    })();
    slot.item.catch(() => { slot.item = undefined; });
    return slot.item;
  };

  const activate = async (slot: LayerSlot): Promise<void> => {
    const item = await itemOf(slot);
    if (destroyed) {
      return;
    }
    for (const other of slots.values()) {
      if (other !== slot) {
        other.tiledImage?.setOpacity(0);
      }
    }
    item.setOpacity(1);
    active = slot;
    if (!applicableModes(slot.info.layer).includes(renderMode)) {
      renderMode = DEFAULT_RENDER_MODE;
      drawer().setRenderMode(renderMode);
    }
    drawer().prepare(slot.info.layer, renderMode);
    widget?.setLit(shadingClass(slot.info.layer) !== 'flat');
    changed();
  };

  const ready = (async () => {
    const parsed = parseManifest(await fetchJson(options.manifest, options.fetchInit));
    manifest = parsed;
    for (const info of parsed.layers) {
      slots.set(info.id, { info });
    }
    const initialId = options.layer ?? parsed.layers[0]?.id ?? '';
    const initial = slots.get(initialId);
    if (!initial) {
      throw new UnknownLayerError(`no layer ${JSON.stringify(initialId)} (layers: ${[...slots.keys()].join(', ')})`);
    }
    await activate(initial);
    applyLight();
  })();
  // Avoid an unhandled rejection if the caller never awaits `ready`.
  ready.catch(() => undefined);

  const activeItem = (): OpenSeadragon.TiledImage => {
    const count = viewer.world.getItemCount();
    for (let i = 0; i < count; i++) {
      const ti = viewer.world.getItemAt(i);
      if (ti.getOpacity() > 0) {
        return ti;
      }
    }
    throw new LanternaError('the layer is not open yet (await ready)');
  };

  const api: LanternaViewer = {
    ready,
    viewer,
    get manifest() { return manifest; },
    get layer() { return active?.loaded ?? null; },
    setLight(lu: number, lv: number) {
      light = lightFromProjection(lu, lv);
      applyLight();
    },
    getLight: () => light,
    setMode(m: DragMode) { dragMode = m; },
    getMode: () => dragMode,
    getLayers: () => [...slots.values()].map(({ info }) => ({
      id: info.id, label: info.label, layerType: info.layer.layerType, modes: applicableModes(info.layer),
    })),
    async setActiveLayer(id: string) {
      const slot = slots.get(id);
      if (!slot) {
        throw new UnknownLayerError(`no layer ${JSON.stringify(id)} (layers: ${[...slots.keys()].join(', ')})`);
      }
      await activate(slot);
    },
    getActiveLayer: () => active?.info.id ?? '',
    setRenderMode(mode: RenderMode) {
      if (!isRenderMode(mode)) {
        throw new RenderModeError(`unknown render mode ${JSON.stringify(mode)}`);
      }
      if (!active) {
        throw new RenderModeError('no layer is open yet (await ready)');
      }
      const modes = applicableModes(active.info.layer);
      if (!modes.includes(mode)) {
        throw new RenderModeError(`mode ${mode} does not apply to layer ${active.info.id} `
          + `(${active.info.layer.layerType}); it supports ${modes.join(', ')}`);
      }
      drawer().prepare(active.info.layer, mode);
      renderMode = mode;
      drawer().setRenderMode(mode);
      changed();
    },
    getRenderMode: () => renderMode,
    setRenderParams(update: Partial<RenderParams>) {
      params = mergeParams(params, update);
      drawer().setRenderParams(params);
      changed();
    },
    getRenderParams: () => params,
    resetRenderParams() {
      params = DEFAULT_RENDER_PARAMS;
      drawer().setRenderParams(params);
      changed();
    },
    onChange(listener: () => void) {
      listeners.add(listener);
      return () => { listeners.delete(listener); };
    },
    showImageRegion(x: number, y: number, width: number, height: number) {
      const rect = activeItem().imageToViewportRectangle(x, y, width, height);
      // No viewport.update() here: OSD's own update must see the change to recompute the levels.
      viewer.viewport.fitBounds(rect, true);
      viewer.forceRedraw();
    },
    async whenFullyLoaded() {
      // Let OSD run at least one update for the current view, then wait for a frame that was drawn
      // with every visible item fully loaded and nothing animating.
      let stable = 0;
      for (let frame = 0; stable < 3; frame++) {
        await nextFrame();
        if (destroyed) {
          throw new LanternaError('viewer destroyed');
        }
        const count = viewer.world.getItemCount();
        let loaded = false;
        let allLoaded = true;
        for (let i = 0; i < count; i++) {
          const ti = viewer.world.getItemAt(i);
          if (ti.getOpacity() > 0) {
            loaded = true;
            allLoaded &&= ti.getFullyLoaded();
          }
        }
        loaded &&= allLoaded;
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
      listeners.clear();
      detach();
      widget?.destroy();
      viewer.destroy();
    },
  };
  return api;
}
