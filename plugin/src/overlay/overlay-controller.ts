/**
 * The overlay TiledImages of a viewer (`docs/annotations.md`, "Viewer"): one per overlay level
 * image, made on first use, stretched over the canvas like the layers. Only the active layer's
 * level matching the current level is visible; the others have opacity 0, so they load nothing.
 */
import type OpenSeadragon from 'openseadragon';
import { imageInfo, type InfoCache } from '../iiif/load';
import type { ManifestLayer } from '../iiif/manifest';
import { overlayAt, type OverlayLevel } from '../iiif/overlays';
import { wholeLevelTiling } from '../iiif/whole-levels';
import { addBundleItem } from '../tiles/add-item';
import { overlayItemWidth } from './overlay-state';

export { overlayItemWidth, overlayState, type OverlayState } from './overlay-state';

/** Options of {@link OverlayController}. */
export interface OverlayControllerOptions {
  /** `fetch` options for the info.json requests. */
  readonly fetchInit?: RequestInit;
  /** info.json documents already requested. */
  readonly infoCache: InfoCache;
  /** Longest side (px) up to which an overlay level image loads by whole levels; 0: tiles always. */
  readonly wholeLevelMaxSide: number;
  /** Called once per new overlay item (e.g. to tell the drawer how to draw it). */
  register(item: OpenSeadragon.TiledImage, level: OverlayLevel): void;
  /** Called when an overlay item could not be opened. */
  onError(error: unknown): void;
}

/** Creates and shows overlay items. */
export class OverlayController {
  readonly #viewer: OpenSeadragon.Viewer;
  readonly #options: OverlayControllerOptions;
  readonly #items = new Map<string, Promise<OpenSeadragon.TiledImage>>();
  readonly #opened = new Map<string, OpenSeadragon.TiledImage>();
  #wanted = '';

  constructor(viewer: OpenSeadragon.Viewer, options: OverlayControllerOptions) {
    this.#viewer = viewer;
    this.#options = options;
  }

  /** The key of the item shown now ('' = none). */
  get shownKey(): string {
    return this.#wanted;
  }

  /**
   * Show `layer`'s overlay for `level` (nothing if it has none there, or if `visible` is false);
   * hide every other overlay item.
   */
  show(layer: ManifestLayer | null, level: number, visible: boolean): void {
    const ov = visible && layer ? overlayAt(layer.overlays, level) : null;
    const key = ov ? keyOf(ov) : '';
    if (key === this.#wanted) {
      return;
    }
    this.#wanted = key;
    for (const [k, item] of this.#opened) {
      if (k !== key) {
        item.setOpacity(0);
      }
    }
    if (!ov || !layer) {
      return;
    }
    this.#itemOf(ov, layer.layer.width).then((item) => {
      if (this.#wanted === key) {
        item.setOpacity(1);
      }
    }).catch((error: unknown) => { this.#options.onError(error); });
  }

  /** True while the wanted overlay item is still being opened. */
  isBusy(): boolean {
    return this.#wanted !== '' && !this.#opened.has(this.#wanted) && this.#items.has(this.#wanted);
  }

  /** The TiledImage shown now, if it is open. */
  shownItem(): OpenSeadragon.TiledImage | null {
    return this.#opened.get(this.#wanted) ?? null;
  }

  #itemOf(level: OverlayLevel, canvasWidth: number): Promise<OpenSeadragon.TiledImage> {
    const key = keyOf(level);
    let pending = this.#items.get(key);
    if (!pending) {
      pending = (async () => {
        const { info, geometry } = await imageInfo(level.serviceId, level.embedded, this.#options.fetchInit,
          this.#options.infoCache);
        const whole = wholeLevelTiling([info], geometry, this.#options.wholeLevelMaxSide);
        const item = await addBundleItem(this.#viewer, {
          infos: whole?.infos ?? [info],
          geometry: whole?.geometry ?? geometry,
          cutoffLevel: whole?.cutoffLevel,
          formats: ['png'],
          width: overlayItemWidth(level, canvasWidth),
          opacity: 0,
          what: `overlay level ${level.level} of layer ${level.layer}`,
        });
        this.#options.register(item, level);
        this.#opened.set(key, item);
        return item;
      })();
      this.#items.set(key, pending);
      pending.catch(() => { this.#items.delete(key); });
    }
    return pending;
  }
}

function keyOf(level: OverlayLevel): string {
  return `${level.layer}#${level.level}`;
}
