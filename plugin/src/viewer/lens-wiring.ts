/**
 * The viewer's lens: its state, the pointer gestures that move and size it, the ring drawn around
 * it, the lens items (see {@link LensController}) and what the drawer is told about it.
 */
import type OpenSeadragon from 'openseadragon';
import { RenderModeError, UnknownLayerError } from '../api/viewer-api';
import type { Compositor } from '../drawer/compositor';
import type { RelightLayer } from '../iiif/relight-service';
import { LensController } from '../lens/lens-controller';
import { updateLens, type LensState, type LensUpdate } from '../lens/lens-state';
import { lensAfterResize, type Circle } from '../math/lens';
import { DEFAULT_RENDER_MODE, isRenderMode, type RenderMode } from '../render/modes';
import type { RenderParams } from '../render/params';
import type { DragMode } from '../ui/interaction';
import { attachLensGestures, type LensGestures } from '../ui/lens-gestures';
import { createLensRing, type LensRing } from '../ui/lens-ring';
import type { LayerSlot, LayerSlots } from './layer-slots';

/** Options of {@link LensWiring}. */
export interface LensWiringOptions {
  /** The lens when the viewer starts. */
  readonly initial: LensState;
  readonly slots: LayerSlots;
  /** The active layer's slot, if any. */
  active(): LayerSlot | null;
  /** What a plain drag does outside the lens. */
  getDragMode(): DragMode;
  /** The drawer's lens hooks. */
  compositor(): Compositor;
  /** Compile the programs a layer needs in a mode (see `RelightDrawer.prepare`). */
  prepare(layer: RelightLayer, mode: RenderMode, params: RenderParams): void;
  /** Called after any change of the lens (redraw and notify). */
  changed(): void;
  /** Called when a lens item could not be opened. */
  onError(error: unknown): void;
}

/** The lens of a viewer. Create it before the viewer's own drag handling (its gestures come first). */
export class LensWiring {
  readonly #options: LensWiringOptions;
  readonly #gestures: LensGestures;
  readonly #items: LensController;
  readonly #ring: LensRing;
  readonly #viewer: OpenSeadragon.Viewer;
  #lens: LensState;
  /** The viewer's size (CSS px) the lens was last placed in. */
  #size: { width: number; height: number };

  constructor(viewer: OpenSeadragon.Viewer, options: LensWiringOptions) {
    this.#options = options;
    this.#lens = options.initial;
    this.#gestures = attachLensGestures(viewer, {
      getLens: () => this.#circle(),
      setLens: (c) => { void this.set({ center: [c.x, c.y], radius: c.radius }); },
      getDragMode: () => options.getDragMode(),
    });
    this.#items = new LensController({
      createItem: async (layerId) => {
        const slot = options.slots.get(layerId);
        if (!slot) {
          throw new UnknownLayerError(`no layer ${JSON.stringify(layerId)}`);
        }
        const loaded = await options.slots.loadedOf(slot);
        const item = await options.slots.addItem(slot, loaded, `the lens layer ${loaded.id}`);
        options.compositor().setLensItem(item, loaded.layer);
        return item;
      },
      onError: (error) => { options.onError(error); },
      onShown: () => { viewer.forceRedraw(); },
    });
    this.#ring = createLensRing(viewer.element);
    this.#viewer = viewer;
    const size = viewer.viewport.getContainerSize();
    this.#size = { width: size.x, height: size.y };
    viewer.addHandler('resize', this.#onResize);
  }

  /** Keep the lens over the same part of the view, and inside the viewer, on every resize. */
  readonly #onResize = (e: { newContainerSize: OpenSeadragon.Point }): void => {
    const after = { width: e.newContainerSize.x, height: e.newContainerSize.y };
    const before = this.#size;
    this.#size = after;
    if (after.width <= 0 || after.height <= 0) {
      return;
    }
    const { center: [x, y], radius } = this.#lens;
    const next = lensAfterResize({ x, y, radius }, before, after);
    this.#lens = { ...this.#lens, center: [next.x, next.y], radius: next.radius };
    void this.apply();
  };

  /** True while a gesture belongs to the lens: no light, no pan. */
  claimed(): boolean {
    return this.#gestures.claimed();
  }

  /** True while the lens item is still being opened. */
  isBusy(): boolean {
    return this.#items.isBusy();
  }

  /** Re-clip the lens item to the lens at the current view. */
  updateClip(): void {
    this.#items.updateClip();
  }

  /** The lens (`layer` resolved to an id). */
  get(): LensState {
    return { ...this.#lens, layer: this.#layerId() };
  }

  /** Change the lens (see `LanternaViewer.setLens`). */
  set(update: LensUpdate): Promise<void> {
    const mode = this.#check(update);
    const next = updateLens(this.#lens, { ...update, mode });
    const slot = next.layer ? this.#options.slots.get(next.layer) : this.#options.active();
    if (slot && next.enabled) {
      this.#options.prepare(slot.info.layer, next.mode, next.params);
    }
    this.#lens = next;
    if (update.center !== undefined) {
      // A centre given now is in the element's size now, which OpenSeadragon may not have seen yet
      // (its resize event comes a frame later): the next resize starts from this size.
      const element = this.#viewer.element;
      if (element.clientWidth > 0 && element.clientHeight > 0) {
        this.#size = { width: element.clientWidth, height: element.clientHeight };
      }
    }
    return this.apply();
  }

  /**
   * The active layer changed to `slot`'s: a lens that follows the active layer keeps its mode if it
   * applies there, and is shown again.
   */
  async followActive(slot: LayerSlot): Promise<void> {
    if (this.#lens.layer) {
      return;
    }
    if (!slot.kind.modes.includes(this.#lens.mode)) {
      this.#lens = { ...this.#lens, mode: DEFAULT_RENDER_MODE };
    }
    await this.apply();
  }

  /** Push the lens to the ring, the lens items and the drawer. */
  apply(): Promise<void> {
    const lens = this.#lens;
    const circle = this.#circle();
    this.#ring.update(circle ?? { x: 0, y: 0, radius: 0 }, circle !== null);
    const c = this.#options.compositor();
    c.setLens(circle ? { ...circle, opacity: lens.opacity, mode: lens.mode, params: lens.params } : null);
    c.setOverlayDisplay(circle ? lens.annotations : 'everywhere');
    const shown = this.#items.show(this.#layerId(), circle);
    this.#options.changed();
    return shown;
  }

  /** Remove the gestures and the ring. */
  destroy(): void {
    this.#viewer.removeHandler('resize', this.#onResize);
    this.#gestures.destroy();
    this.#ring.destroy();
  }

  #circle(): Circle | null {
    const lens = this.#lens;
    return lens.enabled ? { x: lens.center[0], y: lens.center[1], radius: lens.radius } : null;
  }

  #layerId(): string {
    return this.#lens.layer || this.#options.active()?.info.id || '';
  }

  /** Check a lens update against the layers; returns the mode to use. */
  #check(update: LensUpdate): RenderMode {
    const lens = this.#lens;
    const layerId = update.layer ?? lens.layer;
    const slot = layerId ? this.#options.slots.get(layerId) : this.#options.active();
    if (!slot) {
      throw new UnknownLayerError(`no layer ${JSON.stringify(layerId)} for the lens `
        + `(layers: ${this.#options.slots.names()})`);
    }
    const modes = slot.kind.modes;
    if (update.mode !== undefined) {
      if (!isRenderMode(update.mode) || !modes.includes(update.mode)) {
        throw new RenderModeError(`lens mode ${JSON.stringify(update.mode)} does not apply to layer `
          + `${slot.info.id} (${slot.info.layer.layerType}); it supports ${modes.join(', ')}`);
      }
      return update.mode;
    }
    return modes.includes(lens.mode) ? lens.mode : DEFAULT_RENDER_MODE;
  }
}
