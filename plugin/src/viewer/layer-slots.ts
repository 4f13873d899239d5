/**
 * The viewer's layers: one slot per manifest layer, whose plane information is loaded and whose
 * TiledImage is added (at opacity 0, so it loads nothing) on first use.
 */
import OpenSeadragon from 'openseadragon';
import { UnknownLayerError, type LayerInfo } from '../api/viewer-api';
import { loadLayer, type InfoCache, type LoadedLayer } from '../iiif/load';
import type { ManifestLayer } from '../iiif/manifest';
import type { OverlayLevel } from '../iiif/overlays';
import type { RelightLayer } from '../iiif/relight-service';
import type { ImageGeometry } from '../iiif/image-info';
import { wholeLevelTiling, type WholeLevelView } from '../iiif/whole-levels';
import { layerKindOf, type LayerKind } from '../layers/layer-kinds';
import { HOME_MAX_PIXEL_RATIO } from '../math/home-zoom';
import { currentLevel, homeLevelOf } from '../math/levels';
import { addBundleItem } from '../tiles/add-item';
import { minPixelRatioOf } from './osd-viewer';

/** One manifest layer and what has been opened of it. */
export interface LayerSlot {
  /** Replaced (with new overlay levels) by {@link LayerSlots.setOverlays}. */
  info: ManifestLayer;
  /** The layer's kind, looked up once when the slot is added. */
  readonly kind: LayerKind;
  loaded?: LoadedLayer;
  item?: Promise<OpenSeadragon.TiledImage>;
  tiledImage?: OpenSeadragon.TiledImage;
}

/** Options of {@link LayerSlots}. */
export interface LayerSlotsOptions {
  /** `fetch` options for the info.json requests. */
  readonly fetchInit?: RequestInit;
  /** info.json documents already requested. */
  readonly infoCache: InfoCache;
  /** Longest side (px) up to which a layer loads by whole levels (`wholeLevelTiling`); 0: tiles always. */
  readonly wholeLevelMaxSide: number;
  /** Called once per new layer item (e.g. to tell the drawer how to draw it). */
  register(item: OpenSeadragon.TiledImage, layer: RelightLayer): void;
}

/** The layer slots of a viewer, in manifest order. */
export class LayerSlots {
  readonly #viewer: OpenSeadragon.Viewer;
  readonly #options: LayerSlotsOptions;
  readonly #slots = new Map<string, LayerSlot>();

  constructor(viewer: OpenSeadragon.Viewer, options: LayerSlotsOptions) {
    this.#viewer = viewer;
    this.#options = options;
  }

  /** Add a slot per manifest layer. */
  add(layers: readonly ManifestLayer[]): void {
    for (const info of layers) {
      this.#slots.set(info.id, { info, kind: layerKindOf(info.layer) });
    }
  }

  /** Replace every layer's overlay levels (those of a rebuilt overlay); a layer not in `overlays` has none. */
  setOverlays(overlays: ReadonlyMap<string, readonly OverlayLevel[]>): void {
    for (const slot of this.#slots.values()) {
      const levels = overlays.get(slot.info.id) ?? [];
      slot.info = { ...slot.info, overlays: levels };
      if (slot.loaded) {
        slot.loaded = { ...slot.loaded, overlays: levels };
      }
    }
  }

  /** The slot of a layer, if any. */
  get(id: string): LayerSlot | undefined {
    return this.#slots.get(id);
  }

  /**
   * The slot of a layer.
   *
   * @throws {@link UnknownLayerError} when no layer has this id
   */
  require(id: string): LayerSlot {
    const slot = this.#slots.get(id);
    if (!slot) {
      throw new UnknownLayerError(`no layer ${JSON.stringify(id)} (layers: ${this.names()})`);
    }
    return slot;
  }

  /** The layer ids, comma-separated (for error messages). */
  names(): string {
    return [...this.#slots.keys()].join(', ');
  }

  /** The layers, in manifest order. */
  list(): LayerInfo[] {
    return [...this.#slots.values()].map(({ info, kind }) => ({
      id: info.id, label: info.label, layerType: info.layer.layerType, shading: kind.shading, modes: [...kind.modes],
    }));
  }

  /** Hide every layer item but `slot`'s. */
  hideOthers(slot: LayerSlot): void {
    for (const other of this.#slots.values()) {
      if (other !== slot) {
        other.tiledImage?.setOpacity(0);
      }
    }
  }

  /** A layer's plane information, loaded once. */
  async loadedOf(slot: LayerSlot): Promise<LoadedLayer> {
    slot.loaded ??= await loadLayer(slot.info, this.#options.fetchInit, this.#options.infoCache);
    return slot.loaded;
  }

  /** Add a (invisible) TiledImage of a slot's loaded planes; `what` names it in errors. */
  addItem(slot: LayerSlot, loaded: LoadedLayer, what: string): Promise<OpenSeadragon.TiledImage> {
    const whole = wholeLevelTiling(loaded.infos, loaded.geometry, this.#options.wholeLevelMaxSide,
      openingView(this.#viewer, loaded.geometry));
    return addBundleItem(this.#viewer, {
      infos: whole?.infos ?? loaded.infos,
      geometry: whole?.geometry ?? loaded.geometry,
      cutoffLevel: whole?.cutoffLevel,
      formats: loaded.layer.planes.map((p) => p.format),
      previewIndex: slot.kind.previewPlane,
      opacity: 0,
      what,
    });
  }

  /** Load a layer's plane information and add its (invisible) TiledImage, once. */
  itemOf(slot: LayerSlot): Promise<OpenSeadragon.TiledImage> {
    slot.item ??= (async () => {
      const loaded = await this.loadedOf(slot);
      const item = await this.addItem(slot, loaded, `layer ${loaded.id}`);
      this.#options.register(item, loaded.layer);
      slot.tiledImage = item;
      return item;
    })();
    slot.item.catch(() => { slot.item = undefined; });
    return slot.item;
  }
}

/**
 * The on-screen width of a layer item about to open (layers are 1 wide in viewport units): at the
 * current zoom, or for the first item at the home view (fitted, at most `HOME_MAX_PIXEL_RATIO` CSS px
 * per image px: `math/home-zoom.ts`).
 */
function openingView(viewer: OpenSeadragon.Viewer, geometry: ImageGeometry): WholeLevelView {
  const container = viewer.viewport.getContainerSize();
  const displayWidth = viewer.world.getItemCount() === 0
    ? Math.min(container.x, container.y * geometry.width / geometry.height, HOME_MAX_PIXEL_RATIO * geometry.width)
    : viewer.viewport.getZoom(false) * container.x;
  return { displayWidth, minPixelRatio: minPixelRatioOf(viewer) };
}

/**
 * The current level (`docs/annotations.md`, "Levels"): counted from the home view, where it is the
 * coarsest level of `slot`'s overlay (of its pyramid when it has none); 0 when the layer is not open.
 */
export function levelOf(viewer: OpenSeadragon.Viewer, slot: LayerSlot | null): number {
  const loaded = slot?.loaded;
  if (!slot?.tiledImage || !loaded) {
    return 0;
  }
  return currentLevel({
    zoom: viewer.viewport.getZoom(true),
    homeZoom: viewer.viewport.getHomeZoom(),
    homeLevel: homeLevelOf(slot.info.overlays.map((o) => o.level), loaded.geometry.scaleFactors,
      loaded.geometry.width, loaded.geometry.height),
  });
}
