/**
 * `getState` / `setState` of the viewer: the {@link ViewState} read from and applied to the viewer.
 * Geometry goes between CSS px of the viewer element and image pixels through OpenSeadragon's
 * viewport (layers are 1 viewport unit wide at x = 0, so an image pixel is 1/width of a unit).
 */
import OpenSeadragon from 'openseadragon';
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import type { ImageRect, ViewState, ViewStateUpdate } from '../state/view-state';

/** The viewer's state (see `LanternaViewer.getState`). @throws {@link LanternaError} before `ready` */
export function readViewState(api: LanternaViewer): ViewState {
  const width = api.manifest?.layer.width;
  if (width === undefined || !api.getActiveLayer()) {
    throw new LanternaError('the viewer is not ready yet (await ready)');
  }
  const viewport = api.viewer.viewport;
  const b = viewport.getBoundsNoRotate(true);
  const lens = api.getLens();
  const c = viewport.viewerElementToViewportCoordinates(new OpenSeadragon.Point(lens.center[0], lens.center[1]));
  const edge = viewport.viewerElementToViewportCoordinates(
    new OpenSeadragon.Point(lens.center[0] + lens.radius, lens.center[1]));
  const light = api.getLight();
  return {
    layer: api.getActiveLayer(),
    mode: api.getRenderMode(),
    params: api.getRenderParams(),
    light: [light.lu, light.lv],
    overlays: api.getOverlaysVisible(),
    view: [b.x * width, b.y * width, b.width * width, b.height * width],
    rotation: viewport.getRotation(true),
    lens: {
      ...lens,
      center: [c.x * width, c.y * width],
      radius: Math.hypot(edge.x - c.x, edge.y - c.y) * width,
    },
  };
}

/**
 * Centre the view on the region and zoom so that it just fits (rotation kept): the inverse of the
 * `view` that {@link readViewState} reads, with no constraints applied (as `fitBounds` without them).
 */
function showView(api: LanternaViewer, view: ImageRect, width: number): void {
  const viewport = api.viewer.viewport;
  const [x, y, w, h] = view.map((v) => v / width) as [number, number, number, number];
  const aspect = viewport.getAspectRatio();
  const zoom = w / h >= aspect ? 1 / w : 1 / (h * aspect);
  viewport.panTo(new OpenSeadragon.Point(x + w / 2, y + h / 2), true);
  viewport.zoomTo(zoom, undefined, true);
}

/**
 * Apply a state (see `LanternaViewer.setState`): layer first, then mode, parameters, light, overlays,
 * rotation and view, and last the lens (its centre placed by the new view).
 */
export async function applyViewState(api: LanternaViewer, update: ViewStateUpdate): Promise<void> {
  await api.ready;
  const width = api.manifest?.layer.width ?? 1;
  if (update.layer !== undefined && update.layer !== api.getActiveLayer()) {
    await api.setActiveLayer(update.layer);
  }
  if (update.mode !== undefined) {
    api.setRenderMode(update.mode);
  }
  if (update.params !== undefined) {
    api.resetRenderParams();
    api.setRenderParams(update.params);
  }
  if (update.light !== undefined) {
    api.setLight(update.light[0], update.light[1]);
  }
  if (update.overlays !== undefined) {
    api.setOverlaysVisible(update.overlays);
  }
  const viewport = api.viewer.viewport;
  if (update.rotation !== undefined) {
    viewport.setRotation(update.rotation, true);
  }
  if (update.view !== undefined) {
    showView(api, update.view, width);
  }
  api.viewer.forceRedraw();
  const lens = update.lens;
  if (lens === undefined) {
    return;
  }
  const { center, radius, ...rest } = lens;
  if (lens.enabled === false) {
    await api.setLens(rest); // where a hidden lens sits shows nothing
    return;
  }
  const css = (ix: number, iy: number): OpenSeadragon.Point => viewport.viewportToViewerElementCoordinates(
    new OpenSeadragon.Point(ix / width, iy / width));
  const at = center ?? readViewState(api).lens.center;
  const c = css(at[0], at[1]);
  const r = radius === undefined ? undefined : css(at[0] + radius, at[1]).minus(c);
  await api.setLens({
    ...rest,
    center: [c.x, c.y],
    ...(r === undefined ? {} : { radius: Math.hypot(r.x, r.y) }),
  });
}
