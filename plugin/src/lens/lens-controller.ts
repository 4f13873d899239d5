/**
 * The lens's TiledImages: one per layer shown in the lens (a second TiledImage of the layer's
 * sources, so it shares cache records with the base layer through the bundle hash key), clipped
 * to the lens's bounding box in image pixels so that only the tiles under the lens load.
 */
import OpenSeadragon from 'openseadragon';
import { boundingBox, type Circle } from '../math/lens';

/** Options of {@link LensController}. */
export interface LensControllerOptions {
  /** Create the lens TiledImage of a layer (opacity 0). */
  createItem(layerId: string): Promise<OpenSeadragon.TiledImage>;
  /** Called when a lens item could not be opened. */
  onError(error: unknown): void;
  /** Called when the shown item changes (e.g. to redraw). */
  onShown(item: OpenSeadragon.TiledImage | null, layerId: string): void;
}

/** Margin of the clip rectangle around the lens, in CSS px (covers filtering at tile edges). */
const CLIP_MARGIN_CSS_PX = 4;

/** Creates, shows and clips lens items. */
export class LensController {
  readonly #options: LensControllerOptions;
  readonly #items = new Map<string, Promise<OpenSeadragon.TiledImage>>();
  readonly #opened = new Map<string, OpenSeadragon.TiledImage>();
  #wanted = '';
  #circle: Circle | null = null;

  constructor(options: LensControllerOptions) {
    this.#options = options;
  }

  /** True while the wanted lens item is still being opened (not once it failed to open). */
  isBusy(): boolean {
    return this.#wanted !== '' && !this.#opened.has(this.#wanted) && this.#items.has(this.#wanted);
  }

  /** The lens item shown now, if open. */
  shownItem(): OpenSeadragon.TiledImage | null {
    return this.#opened.get(this.#wanted) ?? null;
  }

  /** The lens item of a layer, creating it on first use. */
  itemOf(layerId: string): Promise<OpenSeadragon.TiledImage> {
    let pending = this.#items.get(layerId);
    if (!pending) {
      pending = this.#options.createItem(layerId).then((item) => {
        this.#opened.set(layerId, item);
        return item;
      });
      this.#items.set(layerId, pending);
      pending.catch(() => { this.#items.delete(layerId); });
    }
    return pending;
  }

  /**
   * Show the lens item of `layerId` clipped to `circle` (`null` = the lens is off: hide every lens
   * item). Resolves when the item is open and shown.
   */
  async show(layerId: string, circle: Circle | null): Promise<void> {
    this.#circle = circle;
    const key = circle ? layerId : '';
    const changed = key !== this.#wanted;
    this.#wanted = key;
    for (const [id, item] of this.#opened) {
      if (id !== key && item.getOpacity() !== 0) {
        item.setOpacity(0);
      }
    }
    if (!circle) {
      if (changed) {
        this.#options.onShown(null, '');
      }
      return;
    }
    try {
      const item = await this.itemOf(layerId);
      if (this.#wanted !== key) {
        return;
      }
      this.updateClip();
      if (item.getOpacity() !== 1) {
        item.setOpacity(1);
      }
      this.#options.onShown(item, layerId);
    } catch (error) {
      this.#options.onError(error);
    }
  }

  /** Re-clip the shown item to the lens at the current view (call when the view or the lens changes). */
  updateClip(): void {
    const item = this.shownItem();
    const circle = this.#circle;
    if (!item || !circle) {
      return;
    }
    const rect = clipRect(item, circle);
    const old = (item as unknown as { getClip(): OpenSeadragon.Rect | null }).getClip();
    if (!old || !sameRect(old, rect)) {
      item.setClip(rect);
    }
  }
}

/** The lens's bounding box in the item's image pixels (plus a small margin). */
export function clipRect(item: OpenSeadragon.TiledImage, circle: Circle): OpenSeadragon.Rect {
  const corners: [number, number][] = [];
  const m = CLIP_MARGIN_CSS_PX;
  for (const dx of [-1, 1]) {
    for (const dy of [-1, 1]) {
      const p = item.viewerElementToImageCoordinates(new OpenSeadragon.Point(
        circle.x + dx * (circle.radius + m), circle.y + dy * (circle.radius + m)));
      corners.push([p.x, p.y]);
    }
  }
  const [x, y, w, h] = boundingBox(corners);
  return new OpenSeadragon.Rect(x, y, w, h);
}

function sameRect(a: OpenSeadragon.Rect, b: OpenSeadragon.Rect): boolean {
  const eps = 1e-6 * Math.max(1, Math.abs(a.width), Math.abs(a.height));
  return Math.abs(a.x - b.x) < eps && Math.abs(a.y - b.y) < eps && Math.abs(a.width - b.width) < eps
    && Math.abs(a.height - b.height) < eps;
}
