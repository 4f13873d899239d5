/**
 * The overlay TiledImages of a viewer (`docs/annotations.md`, "Viewer"): the items of a draw plan
 * (`annotations/draw-plan.ts`) — a level's pyramid, or the visible patches of a level drawn from
 * their own images — made on first use and placed in viewport units. Only the planned items are
 * visible; the others have opacity 0, so they load nothing. Items of an overlay that was rebuilt
 * are removed with {@link OverlayController.retire}.
 */
import type OpenSeadragon from 'openseadragon';
import type { PlannedItem, PlannedLevel, PlannedPatch } from '../annotations/draw-plan';
import { LanternaError } from '../errors';
import { imageInfo, type InfoCache } from '../iiif/load';
import { wholeLevelTiling } from '../iiif/whole-levels';
import { addBundleItem } from '../tiles/add-item';
import { PatchTileSource } from './patch-source';

export { overlayItemWidth, overlayState, type OverlayState } from './overlay-state';

/** Options of {@link OverlayController}. */
export interface OverlayControllerOptions {
  /** `fetch` options for the info.json requests. */
  readonly fetchInit?: RequestInit;
  /** info.json documents already requested. */
  readonly infoCache: InfoCache;
  /** Longest side (px) up to which an overlay level image loads by whole levels; 0: tiles always. */
  readonly wholeLevelMaxSide: number;
  /**
   * Called for every new overlay item and whenever its drawing order changes (e.g. to tell the
   * drawer how to draw it: overlay items are drawn in increasing `order`).
   */
  register(item: OpenSeadragon.TiledImage, order: number): void;
  /** Called when an overlay item could not be opened. */
  onError(error: unknown): void;
}

interface Opened {
  readonly item: OpenSeadragon.TiledImage;
  order: number;
}

/** Creates and shows overlay items. */
export class OverlayController {
  readonly #viewer: OpenSeadragon.Viewer;
  readonly #options: OverlayControllerOptions;
  readonly #items = new Map<string, Promise<OpenSeadragon.TiledImage>>();
  readonly #opened = new Map<string, Opened>();
  #wanted: readonly PlannedItem[] = [];
  #wantedKeys = new Set<string>();

  constructor(viewer: OpenSeadragon.Viewer, options: OverlayControllerOptions) {
    this.#viewer = viewer;
    this.#options = options;
  }

  /** Show the plan's items (opening those not open yet) and hide every other overlay item. */
  show(plan: readonly PlannedItem[]): void {
    const keys = new Set(plan.map((p) => p.key));
    if (keys.size === this.#wantedKeys.size && [...keys].every((k) => this.#wantedKeys.has(k))
      && plan.every((p) => (this.#opened.get(p.key)?.order ?? p.order) === p.order)) {
      return;
    }
    this.#wanted = plan;
    this.#wantedKeys = keys;
    for (const [k, opened] of this.#opened) {
      if (!keys.has(k)) {
        opened.item.setOpacity(0);
      }
    }
    for (const planned of plan) {
      this.#itemOf(planned).then((item) => {
        if (this.#wantedKeys.has(planned.key)) {
          this.#order(planned);
          item.setOpacity(1);
        }
      }).catch((error: unknown) => { this.#options.onError(error); });
    }
  }

  /** Resolves once the items shown now are open (rejects if one cannot be). */
  async whenOpen(): Promise<void> {
    await Promise.all(this.#wanted.map((p) => this.#itemOf(p)));
  }

  /** Remove the items that `keep` rejects and that are not shown now (those of a rebuilt overlay). */
  retire(keep: (key: string) => boolean): void {
    for (const [key, opened] of [...this.#opened]) {
      if (!keep(key) && !this.#wantedKeys.has(key)) {
        this.#opened.delete(key);
        this.#items.delete(key);
        this.#viewer.world.removeItem(opened.item);
      }
    }
  }

  /** True while a wanted overlay item is still being opened. */
  isBusy(): boolean {
    return this.#wanted.some((p) => !this.#opened.has(p.key) && this.#items.has(p.key));
  }

  #order(planned: PlannedItem): void {
    const opened = this.#opened.get(planned.key);
    if (opened && opened.order !== planned.order) {
      opened.order = planned.order;
      this.#options.register(opened.item, planned.order);
    }
  }

  #itemOf(planned: PlannedItem): Promise<OpenSeadragon.TiledImage> {
    const key = planned.key;
    let pending = this.#items.get(key);
    if (!pending) {
      pending = (async () => {
        const item = planned.kind === 'level' ? await this.#levelItem(planned) : await this.#patchItem(planned);
        if (this.#items.get(key) !== pending) {
          this.#viewer.world.removeItem(item); // retired while it opened
          return item;
        }
        this.#options.register(item, planned.order);
        this.#opened.set(key, { item, order: planned.order });
        return item;
      })();
      this.#items.set(key, pending);
      pending.catch(() => { this.#items.delete(key); });
    }
    return pending;
  }

  async #levelItem({ level, rect }: PlannedLevel): Promise<OpenSeadragon.TiledImage> {
    const { info, geometry } = await imageInfo(level.serviceId, level.embedded, this.#options.fetchInit,
      this.#options.infoCache);
    const whole = wholeLevelTiling([info], geometry, this.#options.wholeLevelMaxSide);
    return addBundleItem(this.#viewer, {
      infos: whole?.infos ?? [info],
      geometry: whole?.geometry ?? geometry,
      cutoffLevel: whole?.cutoffLevel,
      formats: ['png'],
      width: rect.width,
      opacity: 0,
      what: `overlay level ${level.level} of layer ${level.layer}`,
    });
  }

  #patchItem({ patch, rect, size, crop }: PlannedPatch): Promise<OpenSeadragon.TiledImage> {
    // The image of a patch id changes when it is replaced: its `modified` time keeps HTTP caches apart.
    const url = patch.modified ? `${patch.imageUrl}?v=${encodeURIComponent(patch.modified)}` : patch.imageUrl;
    const source = new PatchTileSource({ url, width: size.width, height: size.height, crop });
    return new Promise((resolve, reject) => {
      this.#viewer.addTiledImage({
        tileSource: source as unknown as OpenSeadragon.TileSource,
        x: rect.x,
        y: rect.y,
        width: rect.width,
        opacity: 0,
        success: (event: { item: OpenSeadragon.TiledImage }) => { resolve(event.item); },
        error: (event: { message?: string }) => {
          reject(new LanternaError(`cannot open patch ${patch.id} of layer ${patch.layer}: `
            + `${event.message ?? 'unknown error'}`));
        },
      } as unknown as Parameters<OpenSeadragon.Viewer['addTiledImage']>[0]);
    });
  }
}
