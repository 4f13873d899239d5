/**
 * The viewer's annotation overlays: whether they are shown, the overlay items (see
 * {@link OverlayController}) and the hypertext widget that shows the current level's texts.
 */
import type OpenSeadragon from 'openseadragon';
import { drawPlan, type PlannedItem } from '../annotations/draw-plan';
import type { PatchAnnotation } from '../iiif/annotation-page';
import type { InfoCache } from '../iiif/load';
import type { ManifestLayer } from '../iiif/manifest';
import { OverlayController, overlayState, type OverlayState } from '../overlay/overlay-controller';
import { createHypertext, type HypertextWidget } from '../panel/hypertext';

/** Options of {@link OverlayWiring}. */
export interface OverlayWiringOptions {
  /** Whether overlays are shown at first. */
  readonly visible: boolean;
  /** Whether to show the hypertext widget. */
  readonly hypertext: boolean;
  /** The hypertext widget's distance from the viewer's bottom edge, CSS px. */
  readonly bottom: number;
  /** `fetch` options for the info.json requests. */
  readonly fetchInit?: RequestInit;
  /** info.json documents already requested. */
  readonly infoCache: InfoCache;
  /** Longest side (px) up to which an overlay level image loads by whole levels; 0: tiles always. */
  readonly wholeLevelMaxSide: number;
  /** Called for every new overlay item and when its drawing order changes (to tell the drawer). */
  register(item: OpenSeadragon.TiledImage, order: number): void;
  /** Called when an overlay item could not be opened. */
  onError(error: unknown): void;
}

/** The overlays of a viewer. */
export class OverlayWiring {
  readonly #items: OverlayController;
  readonly #hypertext: HypertextWidget | null;
  #visible: boolean;
  #shown: OverlayState = { level: 0, available: false, short: '', long: '' };

  constructor(viewer: OpenSeadragon.Viewer, options: OverlayWiringOptions) {
    this.#visible = options.visible;
    this.#items = new OverlayController(viewer, {
      fetchInit: options.fetchInit,
      infoCache: options.infoCache,
      wholeLevelMaxSide: options.wholeLevelMaxSide,
      register: (item, order) => { options.register(item, order); },
      onError: (error) => { options.onError(error); },
    });
    this.#hypertext = options.hypertext ? createHypertext(viewer.element, options.bottom) : null;
  }

  /** Whether overlays are shown. */
  get visible(): boolean {
    return this.#visible;
  }

  /** Show or hide the overlays (takes effect at the next {@link OverlayWiring.sync}). */
  setVisible(visible: boolean): void {
    this.#visible = visible;
    this.invalidate();
  }

  /** Make the next {@link OverlayWiring.sync} refresh the hypertext widget. */
  invalidate(): void {
    this.#shown = { ...this.#shown, level: -1 };
  }

  /** True while the wanted overlay item is still being opened. */
  isBusy(): boolean {
    return this.#items.isBusy();
  }

  /**
   * Show `layer`'s overlay for `level` (if visible), hiding the others: its pyramid, or its visible
   * patches when some of that level are `hidden` (`annotations/draw-plan.ts`).
   */
  show(layer: ManifestLayer, level: number, patches: readonly PatchAnnotation[], hidden: ReadonlySet<string>): void {
    this.#items.show(this.#visible ? this.plan(layer, level, patches, hidden) : []);
  }

  /** What {@link OverlayWiring.show} draws (when overlays are visible). */
  plan(layer: ManifestLayer, level: number, patches: readonly PatchAnnotation[],
    hidden: ReadonlySet<string>): PlannedItem[] {
    return drawPlan({ levels: layer.overlays, patches, hidden, level, canvasWidth: layer.layer.width });
  }

  /** Resolves once the overlay items shown now are open. */
  whenOpen(): Promise<void> {
    return this.#items.whenOpen();
  }

  /** Remove the overlay items not shown now (after the overlays were rebuilt: their ids changed). */
  retireHidden(): void {
    this.#items.retire(() => false);
  }

  /** Bring the hypertext widget in line with `layer` at `level`; true when the overlay state changed. */
  sync(layer: ManifestLayer, level: number): boolean {
    const state = overlayState(layer, level);
    const shown = this.#shown;
    if (state.level === shown.level && state.available === shown.available
      && state.short === shown.short && state.long === shown.long) {
      return false;
    }
    this.#shown = state;
    this.#hypertext?.update(state, layer.overlays.length > 0, this.#visible);
    return true;
  }

  /** Remove the hypertext widget. */
  destroy(): void {
    this.#hypertext?.destroy();
  }
}
