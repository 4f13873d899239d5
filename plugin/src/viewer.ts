/**
 * `createViewer`: an OpenSeadragon viewer showing the relightable layers of a Lanterna manifest,
 * one TiledImage per layer (inactive layers at opacity 0, so they load nothing), the active layer's
 * annotation overlay for the current level, and the lens.
 */
import OpenSeadragon from 'openseadragon';
import type { Compositor } from './compositor';
import { RelightDrawer, type PixelData } from './drawer/relight-drawer';
import { LanternaError } from './iiif/errors';
import { fetchJson, loadLayer, type InfoCache, type LoadedLayer } from './iiif/load';
import { parseManifest, type ManifestInfo, type ManifestLayer } from './iiif/manifest';
import type { LayerType } from './iiif/relight-service';
import { LensController } from './lens/lens-controller';
import { initialLens, updateLens, type LensState, type LensUpdate } from './lens/lens-state';
import { currentLevel, imagePxPerDevicePx, maxLevelOf } from './math/levels';
import { lightFromPointer, lightFromProjection, type Light } from './math/light';
import { OverlayController, overlayState, type OverlayState } from './overlay/overlay-controller';
import { applicableModes, DEFAULT_RENDER_MODE, isRenderMode, shadingClass, type RenderMode } from './render/modes';
import { DEFAULT_RENDER_PARAMS, mergeParams, type RenderParams } from './render/params';
import { addBundleItem } from './tiles/add-item';
import { createHypertext, type HypertextWidget } from './ui/hypertext';
import { attachInteraction, type DragMode } from './ui/interaction';
import { attachLensGestures } from './ui/lens-gestures';
import { createLensRing } from './ui/lens-ring';
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
  /** Show the hypertext widget of the annotation overlays. @default true */
  hypertext?: boolean;
  /** Show the annotation overlays. @default true */
  overlays?: boolean;
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
  /**
   * Show or hide the active layer's annotation overlays (and the hypertext widget).
   */
  setOverlaysVisible(visible: boolean): void;
  /** Whether overlays are shown. */
  getOverlaysVisible(): boolean;
  /**
   * The current level (docs/annotations.md) and the active layer's overlay there: `available` false
   * when it has no overlay image at that level; `long` is sanitised HTML.
   */
  getOverlayState(): OverlayState;
  /**
   * Change the lens (any subset; `params` are merged into the lens's own parameters, `layer` ''
   * follows the active layer). Throws {@link UnknownLayerError}, {@link RenderModeError} or
   * `LensOptionError` for bad arguments; resolves once the lens layer is open.
   */
  setLens(update: LensUpdate): Promise<void>;
  /** The lens (`layer` resolved to an id). */
  getLens(): LensState;
  /** Call `listener` after any change of light, layer, mode, parameters, lens, overlays or level; returns an unsubscribe function. */
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
  let lens: LensState = initialLens(element.clientWidth || 640, element.clientHeight || 480);
  let overlaysVisible = options.overlays ?? true;
  let overlayShown: OverlayState = { level: 0, available: false, short: '', long: '' };
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

  const notify = (): void => {
    for (const l of listeners) {
      l();
    }
  };
  const changed = (): void => {
    viewer.forceRedraw();
    notify();
  };

  const compositor = (): Compositor => drawer();
  const reportError = (error: unknown): void => {
    console.warn('[lanterna]', error);
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

  const lensCircle = (): { x: number; y: number; radius: number } | null =>
    (lens.enabled ? { x: lens.center[0], y: lens.center[1], radius: lens.radius } : null);

  const gestures = attachLensGestures(viewer, {
    getLens: lensCircle,
    setLens: (c) => { void api.setLens({ center: [c.x, c.y], radius: c.radius }); },
    getDragMode: () => dragMode,
  });

  const detach = attachInteraction(viewer, {
    getMode: () => dragMode,
    moveLight: (x, y, w, h) => {
      light = lightFromPointer(x, y, w, h);
      applyLight();
    },
    claimed: () => gestures.claimed(),
  });

  const addItem = (loaded: LoadedLayer, what: string): Promise<OpenSeadragon.TiledImage> => addBundleItem(viewer, {
    infos: loaded.infos,
    geometry: loaded.geometry,
    formats: loaded.layer.planes.map((p) => p.format),
    previewIndex: previewIndex(loaded.layer),
    opacity: 0,
    what,
  });

  const loadedOf = async (slot: LayerSlot): Promise<LoadedLayer> => {
    slot.loaded ??= await loadLayer(slot.info, options.fetchInit, infoCache);
    return slot.loaded;
  };

  /** Load a layer's plane information and add its (invisible) TiledImage, once. */
  const itemOf = (slot: LayerSlot): Promise<OpenSeadragon.TiledImage> => {
    slot.item ??= (async () => {
      const loaded = await loadedOf(slot);
      const item = await addItem(loaded, `layer ${loaded.id}`);
      drawer().setLayer(item, loaded.layer);
      slot.tiledImage = item;
      return item;
    })();
    slot.item.catch(() => { slot.item = undefined; });
    return slot.item;
  };

  const overlays = new OverlayController(viewer, {
    fetchInit: options.fetchInit,
    infoCache,
    register: (item) => { compositor().setOverlayItem(item); },
    onError: reportError,
  });
  const lensItems = new LensController({
    createItem: async (layerId) => {
      const slot = slots.get(layerId);
      if (!slot) {
        throw new UnknownLayerError(`no layer ${JSON.stringify(layerId)}`);
      }
      const loaded = await loadedOf(slot);
      const item = await addItem(loaded, `the lens layer ${loaded.id}`);
      compositor().setLensItem(item, loaded.layer);
      return item;
    },
    onError: reportError,
    onShown: () => { viewer.forceRedraw(); },
  });
  const ring = createLensRing(viewer.element);
  const hypertext: HypertextWidget | null = options.hypertext === false ? null : createHypertext(viewer.element);

  /** The current level, from the active layer's zoom. */
  const level = (): number => {
    const item = active?.tiledImage;
    const loaded = active?.loaded;
    if (!item || !loaded) {
      return 0;
    }
    const zoom = item.viewportToImageZoom(viewer.viewport.getZoom(true));
    return currentLevel(imagePxPerDevicePx(zoom, OpenSeadragon.pixelDensityRatio), maxLevelOf(loaded.geometry.scaleFactors));
  };

  /** Bring overlays, hypertext and the lens clip in line with the view (cheap; called every frame). */
  const sync = (): void => {
    if (destroyed || !active) {
      return;
    }
    const lv = level();
    overlays.show(active.info, lv, overlaysVisible);
    lensItems.updateClip();
    const state = overlayState(active.info, lv);
    if (state.level !== overlayShown.level || state.available !== overlayShown.available
      || state.short !== overlayShown.short || state.long !== overlayShown.long) {
      overlayShown = state;
      hypertext?.update(state, active.info.overlays.length > 0, overlaysVisible);
      notify();
    }
  };
  viewer.addHandler('viewport-change', sync);
  viewer.addHandler('update-viewport', sync);

  const lensLayerId = (): string => lens.layer || active?.info.id || '';

  /** Push the lens to the ring, the lens items and the drawer. */
  const applyLens = (): Promise<void> => {
    const circle = lensCircle();
    ring.update(circle ?? { x: 0, y: 0, radius: 0 }, circle !== null);
    const c = compositor();
    c.setLens(circle ? { ...circle, opacity: lens.opacity, mode: lens.mode, params: lens.params } : null);
    c.setOverlayDisplay(circle ? lens.annotations : 'everywhere');
    const shown = lensItems.show(lensLayerId(), circle);
    changed();
    return shown;
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
    overlayShown = { ...overlayShown, level: -1 };
    sync();
    if (!lens.layer) {
      // The lens follows the active layer: keep its mode if it applies there.
      if (!applicableModes(slot.info.layer).includes(lens.mode)) {
        lens = { ...lens, mode: DEFAULT_RENDER_MODE };
      }
      await applyLens();
    }
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
    if (!active?.tiledImage) {
      throw new LanternaError('the layer is not open yet (await ready)');
    }
    return active.tiledImage;
  };

  /** Check a lens update against the layers; returns the mode to use. */
  const checkLens = (update: LensUpdate): RenderMode => {
    const layerId = update.layer ?? lens.layer;
    const slot = layerId ? slots.get(layerId) : active;
    if (!slot) {
      throw new UnknownLayerError(`no layer ${JSON.stringify(layerId)} for the lens `
        + `(layers: ${[...slots.keys()].join(', ')})`);
    }
    const modes = applicableModes(slot.info.layer);
    if (update.mode !== undefined) {
      if (!isRenderMode(update.mode) || !modes.includes(update.mode)) {
        throw new RenderModeError(`lens mode ${JSON.stringify(update.mode)} does not apply to layer `
          + `${slot.info.id} (${slot.info.layer.layerType}); it supports ${modes.join(', ')}`);
      }
      return update.mode;
    }
    return modes.includes(lens.mode) ? lens.mode : DEFAULT_RENDER_MODE;
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
    setOverlaysVisible(visible: boolean) {
      overlaysVisible = visible;
      overlayShown = { ...overlayShown, level: -1 };
      sync();
      changed();
    },
    getOverlaysVisible: () => overlaysVisible,
    getOverlayState: () => overlayState(active?.info ?? null, level()),
    setLens(update: LensUpdate) {
      const mode = checkLens(update);
      const next = updateLens(lens, { ...update, mode });
      const layer = next.layer ? slots.get(next.layer)?.info : active?.info;
      if (layer && next.enabled) {
        drawer().prepare(layer.layer, next.mode, next.params);
      }
      lens = next;
      return applyLens();
    },
    getLens: () => ({ ...lens, layer: lensLayerId() }),
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
      sync();
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
        let allLoaded = !overlays.isBusy() && !lensItems.isBusy();
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
      gestures.destroy();
      ring.destroy();
      hypertext?.destroy();
      widget?.destroy();
      viewer.destroy();
    },
  };
  return api;
}
