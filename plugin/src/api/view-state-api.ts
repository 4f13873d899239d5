/**
 * The view-state part of the viewer's API: the state as a link holds it, and snapshots
 * (`docs/viewer-api.md`, "View state" and "Snapshots"). Types only.
 */
import type { ViewState, ViewStateUpdate } from '../state/view-state';

/** Options of {@link ViewStateApi.snapshot}. */
export interface SnapshotOptions {
  /**
   * Draw the image region in view (clipped to the image) at this many output pixels per image pixel
   * (1: full resolution), tile by tile, instead of the canvas at device resolution. The viewer moves
   * while it draws and is put back after. @default the canvas's device pixels
   */
  scale?: number;
}

/** What a viewer offers for shareable views. */
export interface ViewStateApi {
  /**
   * What the viewer shows: layer, mode, every parameter, light, overlays, the image region in view,
   * rotation and the lens, geometry in image pixels. Throws a `LanternaError` before `ready`.
   */
  getState(): ViewState;
  /**
   * Show a state (any subset of {@link getState}'s; the rest stays), in this order: layer, mode,
   * parameters, light, overlays, rotation, view, lens. Rejects with `UnknownLayerError`,
   * `RenderModeError` or `LensOptionError` for a field the dataset cannot show (the fields before it
   * are applied).
   */
  setState(state: ViewStateUpdate): Promise<void>;
  /**
   * The current view as a PNG once it is fully loaded: device pixels, the same as `readPixels`, with
   * the dataset label, layer, mode, parameters, light, view and a link hash in `iTXt` chunks.
   */
  snapshot(options?: SnapshotOptions): Promise<Blob>;
}
