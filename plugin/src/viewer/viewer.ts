/**
 * `createViewer`: an OpenSeadragon viewer showing the relightable layers of a Lanterna manifest,
 * one TiledImage per layer (inactive layers at opacity 0, so they load nothing), the active layer's
 * annotation overlay for the current level, and the lens.
 *
 * The parts live next to it in `viewer/` (the OpenSeadragon options, the layer slots, the lens and the
 * overlays; the API types are in `api/`); this module wires them to the light, the render mode and
 * the parameters.
 */
import type OpenSeadragon from 'openseadragon';
import {
  RenderModeError, type AttachLanternaOptions, type CreateViewerOptions, type LanternaViewer,
} from '../api/viewer-api';
import { LanternaError } from '../errors';
import { fetchJson, type InfoCache } from '../iiif/load';
import { parseManifest, type ManifestInfo } from '../iiif/manifest';
import { DEFAULT_WHOLE_LEVEL_MAX_SIDE } from '../iiif/whole-levels';
import { initialLens } from '../lens/lens-state';
import { lightFromProjection, type Light } from '../math/light';
import { overlayState } from '../overlay/overlay-controller';
import { emptyLibrary, entryLayer, type PresetLibrary } from '../presets/library';
import { parsePresetLibrary } from '../presets/read-library';
import { DEFAULT_RENDER_MODE, isRenderMode, type RenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, mergeParams, type RenderParams } from '../render/params';
import { RelightDrawer } from '../drawer/relight-drawer';
import { attachInteraction, type DragMode } from '../ui/interaction';
import { createLightWidget, type LightWidget } from '../ui/light-widget';
import { AnnotationWiring, fetchAnnotations, fetchPatches, focusPatch } from './annotation-wiring';
import { whenFullyLoaded } from './fully-loaded';
import { LayerSlots, levelOf, type LayerSlot } from './layer-slots';
import { LensWiring } from './lens-wiring';
import { ViewerNotices } from './notices';
import { createOsdViewer, relightDrawerOf, sizeTileCache } from './osd-viewer';
import { OverlayWiring } from './overlay-wiring';
import { applyPresetEntry, capturePreset } from './preset-actions';
import { openPresetLibrary, presetDataset, selectLayers } from './preset-library';
import { snapshotPng } from './snapshot';
import { applyViewState, readViewState } from './view-state';

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
  const viewer = createOsdViewer(element, options.osd);
  return wireViewer(viewer, options, { osd: options.osd, release: () => { viewer.destroy(); } });
}

/** What {@link wireViewer} needs besides the viewer options. */
export interface ViewerHost {
  /** The OpenSeadragon options the viewer was made with (createViewer's `osd`): a tile cache size there wins. */
  readonly osd?: Partial<OpenSeadragon.Options>;
  /** Called last by `destroy()`: destroy the viewer (createViewer), or give it back to its page (attachLanterna). */
  readonly release: () => void;
}

/**
 * Wire a Lanterna viewer onto an OpenSeadragon viewer whose drawer is the {@link RelightDrawer}: the
 * layer slots, lens, overlays, annotations, light widget, notices and interaction, and the returned
 * API. The one wiring of {@link createViewer} and `attachLanterna` (`embed/attach.ts`).
 */
export function wireViewer(viewer: OpenSeadragon.Viewer, options: AttachLanternaOptions,
  host: ViewerHost): LanternaViewer {
  let dragMode: DragMode = options.mode ?? 'light';
  // Raw (lu, lv) numbers become a Light (clamped) here and in setLight only; the widget and the
  // pointer hand over Lights already made by lightFromPointer or nudgeLight.
  let light = lightFromProjection(options.light?.[0] ?? 0, options.light?.[1] ?? 0);
  let renderMode: RenderMode = DEFAULT_RENDER_MODE;
  let params: RenderParams = DEFAULT_RENDER_PARAMS;
  let manifest: ManifestInfo | null = null;
  let library: PresetLibrary = emptyLibrary();
  let active: LayerSlot | null = null;
  const initial = initialLens(viewer.element.clientWidth || 640, viewer.element.clientHeight || 480);
  const infoCache: InfoCache = new Map();
  const listeners = new Set<() => void>();
  let destroyed = false;

  const drawer = () => relightDrawerOf(viewer);

  const notify = (): void => {
    for (const l of listeners) {
      l();
    }
  };
  const changed = (): void => {
    viewer.forceRedraw();
    notify();
  };
  // The corner widgets and the notices sit above the host's controls along the bottom edge.
  const inset = options.bottomInset ?? 0;
  const widget: LightWidget | null = options.lightIndicator === false ? null : createLightWidget(viewer.element, {
    bottom: 12 + inset,
    getLight: () => light,
    setLight: (l) => { applyLight(l); },
  });

  // Above the light widget (12 px from the bottom, 96 px high), if there is one.
  const notices = new ViewerNotices(viewer, {
    show: options.notices !== false, bottom: (widget ? 120 : 12) + inset, onChange: notify,
  });
  const reportError = (error: unknown): void => {
    if (destroyed) {
      return; // e.g. an item that was still opening
    }
    console.warn('[lanterna]', error);
    notices.reportError(error);
  };
  if (viewer.drawer instanceof RelightDrawer) {
    viewer.drawer.setEvents({ context: (lost) => { notices.setContextLost(lost); }, error: reportError });
  }

  const applyLight = (next: Light): void => {
    light = next;
    drawer().setLight(light);
    widget?.update(light);
    changed();
  };

  const wholeLevelMaxSide = options.wholeLevelMaxSide ?? DEFAULT_WHOLE_LEVEL_MAX_SIDE;
  const slots = new LayerSlots(viewer, {
    fetchInit: options.fetchInit,
    infoCache,
    wholeLevelMaxSide,
    register: (item, layer) => { drawer().setLayer(item, layer); },
  });

  // The lens's gestures come before the light drag and the pan.
  const lens = new LensWiring(viewer, {
    initial,
    slots,
    active: () => active,
    getDragMode: () => dragMode,
    compositor: drawer,
    prepare: (layer, mode, lensParams) => { drawer().prepare(layer, mode, lensParams); },
    changed,
    onError: reportError,
  });

  const detach = attachInteraction(viewer, {
    getMode: () => dragMode,
    setLight: (l) => { applyLight(l); },
    getLight: () => light,
    claimed: () => lens.claimed(),
  });

  const overlays = new OverlayWiring(viewer, {
    visible: options.overlays ?? true,
    hypertext: options.hypertext !== false,
    bottom: 12 + inset,
    fetchInit: options.fetchInit,
    infoCache,
    wholeLevelMaxSide,
    register: (item, order) => { drawer().setOverlayItem(item, order); },
    onError: reportError,
  });
  const annotations = new AnnotationWiring(viewer);
  const canvasWidth = (): number => manifest?.layer.width ?? 1;
  const activeId = (): string => active?.info.id ?? '';

  /** Bring overlays, hypertext and the lens clip in line with the view (cheap; called every frame). */
  const sync = (): void => {
    if (destroyed || !active) {
      return;
    }
    const lv = levelOf(viewer, active);
    overlays.show(active.info, lv, annotations.set.list(active.info.id), annotations.set.hidden(active.info.id));
    lens.updateClip();
    if (overlays.sync(active.info, lv)) {
      notify();
    }
  };
  viewer.addHandler('viewport-change', sync);
  viewer.addHandler('update-viewport', sync);

  const activate = async (slot: LayerSlot): Promise<void> => {
    const item = await slots.itemOf(slot);
    if (destroyed) {
      return;
    }
    slots.hideOthers(slot);
    item.setOpacity(1);
    active = slot;
    if (!slot.kind.modes.includes(renderMode)) {
      renderMode = DEFAULT_RENDER_MODE;
      drawer().setRenderMode(renderMode);
    }
    drawer().prepare(slot.info.layer, renderMode);
    widget?.setLit(slot.kind.lit);
    overlays.invalidate();
    sync();
    await lens.followActive(slot);
    changed();
  };

  let pageError: unknown = null;
  const ready = (async () => {
    const doc = await fetchJson(options.manifest, options.fetchInit);
    const whole = parseManifest(doc);
    const opened = await openPresetLibrary(whole, options.presets, options.manifest, options.fetchInit);
    library = opened.library;
    const parsed = selectLayers(whole, options.layers, library);
    manifest = parsed;
    sizeTileCache(viewer, Math.max(...parsed.layers.map((l) => l.layer.planes.length)), host.osd);
    slots.add(parsed.layers);
    // A page that cannot be read leaves the list empty, with a notice; the overlays still show.
    const patches = await fetchPatches(doc, parsed.layers.map((l) => l.id), options.fetchInit)
      .catch((error: unknown) => { pageError = error; return []; });
    annotations.set.replace(patches);
    const firstEntry = options.layers === 'presets' ? library.base[0] : undefined;
    const first = options.layer ?? (firstEntry ? entryLayer(library, firstEntry) : undefined);
    await activate(slots.require(first ?? parsed.layers[0]?.id ?? ''));
    for (const error of [opened.error, pageError]) {
      if (error !== null) {
        reportError(error);
      }
    }
    applyLight(light);
  })().catch((error: unknown) => {
    if (destroyed) {
      // Whatever failed: destroy() took the viewer (or its drawer) away while it was opening.
      throw new LanternaError('the viewer was destroyed before it was ready', { cause: error });
    }
    // Always a LanternaError, whatever failed underneath (OpenSeadragon, the browser).
    throw error instanceof LanternaError ? error
      : new LanternaError(`cannot open the viewer: ${error instanceof Error ? error.message : String(error)}`,
        { cause: error });
  });
  // Avoid an unhandled rejection if the caller never awaits `ready`.
  ready.catch(() => undefined);

  const activeItem = (): OpenSeadragon.TiledImage => {
    if (!active?.tiledImage) {
      throw new LanternaError('the layer is not open yet (await ready)');
    }
    return active.tiledImage;
  };

  /** Fetch the manifest and annotation pages again and show the rebuilt overlays (no page reload). */
  const refreshAnnotations = async (): Promise<void> => {
    await ready;
    const next = await fetchAnnotations(options.manifest, slots.list().map((l) => l.id), options.fetchInit);
    if (destroyed || !manifest) {
      return;
    }
    slots.setOverlays(next.overlays);
    manifest = { ...manifest, layers: manifest.layers.map((l) => ({ ...l, overlays: next.overlays.get(l.id) ?? [] })) };
    annotations.replace(next.patches, canvasWidth());
    overlays.invalidate();
    sync();
    // Open the new items, then remove the previous build's (other levels, other ids).
    await overlays.whenOpen().catch(reportError);
    if (destroyed) {
      return;
    }
    overlays.retireHidden();
    changed();
  };

  const api: LanternaViewer = {
    ready,
    viewer,
    get manifest() { return manifest; },
    get layer() { return active?.loaded ?? null; },
    setLight(lu: number, lv: number) {
      applyLight(lightFromProjection(lu, lv));
    },
    getLight: () => light,
    setMode(m: DragMode) { dragMode = m; },
    getMode: () => dragMode,
    getLayers: () => slots.list(),
    async setActiveLayer(id: string) {
      await activate(slots.require(id));
    },
    getActiveLayer: () => active?.info.id ?? '',
    setRenderMode(mode: RenderMode) {
      if (!isRenderMode(mode)) {
        throw new RenderModeError(`unknown render mode ${JSON.stringify(mode)}`);
      }
      if (!active) {
        throw new RenderModeError('no layer is open yet (await ready)');
      }
      const modes = active.kind.modes;
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
      overlays.setVisible(visible);
      sync();
      changed();
    },
    getOverlaysVisible: () => overlays.visible,
    getOverlayState: () => overlayState(active?.info ?? null, levelOf(viewer, active)),
    setLens: (update) => lens.set(update),
    getLens: () => lens.get(),
    resetRenderParams() {
      params = DEFAULT_RENDER_PARAMS;
      drawer().setRenderParams(params);
      changed();
    },
    getNotices: () => notices.list(),
    reportError,
    dismissErrors: () => { notices.dismissErrors(); },
    retryFailedTiles: () => { notices.retryTiles(); },
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
    // Busy also while the drawer has put a frame off or still has textures to upload.
    whenFullyLoaded: () => whenFullyLoaded(viewer, () => overlays.isBusy() || lens.isBusy() || !drawer().isSettled(),
      () => destroyed),
    readPixels: () => drawer().readPixels(),
    getImageRegion() {
      if (!active?.tiledImage || !manifest) {
        return null;
      }
      const bounds = active.tiledImage.viewportToImageRectangle(viewer.viewport.getBounds(true));
      const x0 = Math.max(0, bounds.x);
      const y0 = Math.max(0, bounds.y);
      const x1 = Math.min(manifest.layer.width, bounds.x + bounds.width);
      const y1 = Math.min(manifest.layer.height, bounds.y + bounds.height);
      const r = (v: number): number => Math.round(v * 100) / 100;
      return x1 > x0 && y1 > y0 ? [r(x0), r(y0), r(x1 - x0), r(y1 - y0)] : null;
    },
    getAnnotations: (layerId?: string) => annotations.set.list(layerId ?? activeId()),
    setAnnotationHidden(id: string, hidden: boolean) {
      if (annotations.set.setHidden(annotations.require(id, activeId()), hidden)) {
        sync();
        changed();
      }
    },
    isAnnotationHidden(id: string) {
      const patch = annotations.set.find(id, activeId());
      return patch !== undefined && annotations.set.hidden(patch.layer).has(id);
    },
    highlightAnnotation(id: string | null) {
      annotations.highlight(id === null ? null : annotations.require(id, activeId()), canvasWidth());
    },
    focusAnnotation: (id: string) => focusPatch(api, annotations.require(id, activeId())),
    refreshAnnotations,
    getPresetLibrary: () => library,
    setPresetLibrary(doc: unknown, source = 'the preset library') {
      if (!manifest) {
        throw new LanternaError('the viewer is not ready yet (await ready)');
      }
      library = parsePresetLibrary(doc, source, presetDataset(manifest, slots.list()));
      notify();
      return library;
    },
    applyPreset: (target, index) => applyPresetEntry(api, library, target, index),
    capturePreset: (target, label, withView = false) => capturePreset(api, target, label, withView),
    getState: () => readViewState(api),
    setState: (state) => applyViewState(api, state),
    snapshot: (snapshotOptions) => snapshotPng(api, snapshotOptions),
    destroy() {
      if (destroyed) {
        return;
      }
      destroyed = true;
      listeners.clear();
      detach();
      lens.destroy();
      annotations.destroy();
      overlays.destroy();
      notices.destroy();
      widget?.destroy();
      viewer.removeHandler('viewport-change', sync);
      viewer.removeHandler('update-viewport', sync);
      host.release();
    },
  };
  return api;
}
