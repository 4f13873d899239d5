/**
 * What the viewer tells the drawer about the lens and the overlays (implemented by `RelightDrawer`).
 */
import type { RelightLayer } from '../iiif/relight-service';
import type { AnnotationDisplay } from '../lens/lens-state';
import type { RenderMode } from '../render/modes';
import type { RenderParams } from '../render/params';

/** The lens as the drawer needs it: a circle in CSS px of the viewer element and how to draw inside. */
export interface DrawerLens {
  readonly x: number;
  readonly y: number;
  readonly radius: number;
  /** Opacity of the lens layer over the base layer, 0–1. */
  readonly opacity: number;
  readonly mode: RenderMode;
  readonly params: RenderParams;
}

/** Drawer hooks for the lens and the overlays. */
export interface Compositor {
  /** Draw `item` (a lens TiledImage of `layer`) inside the lens only. */
  setLensItem(item: object, layer: RelightLayer): void;
  /**
   * Draw `item` (a plain RGBA overlay image: a level, or one patch) over the layers, premultiplied
   * source-over; overlay items are drawn in increasing `order` (ties: world order).
   */
  setOverlayItem(item: object, order?: number): void;
  /** The lens, or null when it is off. */
  setLens(lens: DrawerLens | null): void;
  /** Where overlays are drawn relative to the lens (ignored while the lens is off). */
  setOverlayDisplay(display: AnnotationDisplay): void;
}
