/**
 * The OpenSeadragon viewer a Lanterna viewer runs on: its options (the Lanterna drawer, no
 * navigator, level selection, the tile cache's size), the capped home zoom and access to its drawer.
 */
import OpenSeadragon from 'openseadragon';
import { RelightDrawer, WebGLUnavailableError } from '../drawer/relight-drawer';
import { homeZoom } from '../math/home-zoom';
import { cacheTileCount } from './cache-budget';

/** OpenSeadragon's own `minPixelRatio`: full detail (up to 2 image px per screen px). */
const FULL_DETAIL = 0.5;

/** Planes per bundle assumed until the manifest says (a PTM: three plane groups). */
const DEFAULT_PLANES = 3;

/**
 * Create the OpenSeadragon viewer in `element`; `osd` overrides the defaults.
 *
 * @throws {@link WebGLUnavailableError} without WebGL2 (OpenSeadragon would throw a bare Error)
 */
export function createOsdViewer(element: HTMLElement, osd?: Partial<OpenSeadragon.Options>): OpenSeadragon.Viewer {
  if (!RelightDrawer.isSupported()) {
    throw new WebGLUnavailableError('WebGL2 is not available in this browser, so the Lanterna drawer cannot start');
  }
  const viewer = OpenSeadragon({
    element,
    drawer: RelightDrawer,
    crossOriginPolicy: 'Anonymous',
    showNavigator: false,
    showNavigationControl: false,
    blendTime: 0,
    immediateRender: false,
    // Full detail. Tests that need a level chosen exactly (a zoom of 1/2 showing the next coarser
    // level, never a half-faded finer one) pass 0.75 through `osd` (the demo page: ?minPixelRatio=).
    minPixelRatio: FULL_DETAIL,
    maxZoomPixelRatio: 16,
    minZoomImageRatio: 0.05,
    visibilityRatio: 0.1,
    // Sized by the view (cache-budget.ts); sized again for the manifest's layers by sizeTileCache.
    maxImageCacheCount: cacheTileCount({
      width: element.clientWidth, height: element.clientHeight,
      minPixelRatio: osd?.minPixelRatio ?? FULL_DETAIL, planes: DEFAULT_PLANES,
    }),
    // At most 8 bundles (8·K plane requests) at a time: OpenSeadragon's time limit (`timeout`) runs
    // from a job's start, so without a limit a tile queued behind hundreds of plane requests in the
    // browser could time out on a slow network without anything being wrong.
    imageLoaderLimit: 8,
    gestureSettingsMouse: { clickToZoom: false, dblClickToZoom: true },
    gestureSettingsTouch: { flickEnabled: false },
    silenceMultiImageWarnings: true,
    ...osd,
  });
  if (osd?.defaultZoomLevel === undefined) {
    capHomeZoom(viewer);
  }
  return viewer;
}

/**
 * Cap the home zoom at `HOME_MAX_PIXEL_RATIO` CSS px per image px (`math/home-zoom.ts`), so a
 * small image shows small and centred: OpenSeadragon's `defaultZoomLevel` is set, before each
 * `goHome` (the `home` event comes before the home bounds are read) and on each resize, to the capped
 * zoom when it is below the fitting one (0, OpenSeadragon's fit, otherwise).
 */
function capHomeZoom(viewer: OpenSeadragon.Viewer): void {
  const update = (): void => {
    const viewport = viewer.viewport as OpenSeadragon.Viewport & { defaultZoomLevel: number };
    const item = viewer.world.getItemAt(0) as OpenSeadragon.TiledImage | undefined;
    if (!item) {
      return;
    }
    viewport.defaultZoomLevel = 0;
    const fitZoom = viewport.getHomeZoom();
    const unit = new OpenSeadragon.Point(1, 0);
    const containerWidth = viewport.deltaPixelsFromPointsNoRotate(unit, false).x / viewport.getZoom(false);
    const capped = homeZoom({
      fitZoom, containerWidth, imagePxPerUnit: item.getContentSize().x / item.getBounds().width,
    });
    viewport.defaultZoomLevel = capped < fitZoom ? capped : 0;
  };
  viewer.addHandler('home', update);
  viewer.addHandler('resize', update);
}

/**
 * The viewer's drawer.
 *
 * @throws {@link WebGLUnavailableError} if the viewer is not using the Lanterna drawer (it needs WebGL2)
 */
export function relightDrawerOf(viewer: OpenSeadragon.Viewer): RelightDrawer {
  const d = viewer.drawer as unknown;
  if (!(d instanceof RelightDrawer)) {
    throw new WebGLUnavailableError('WebGL2 is not available, so the Lanterna drawer could not start');
  }
  return d;
}

/**
 * Size the tile cache for the viewer's view and its heaviest layer (`planes` plane groups per
 * bundle), unless the caller set `maxImageCacheCount` itself (see cache-budget.ts).
 */
export function sizeTileCache(viewer: OpenSeadragon.Viewer, planes: number, osd?: Partial<OpenSeadragon.Options>): void {
  if (osd?.maxImageCacheCount !== undefined) {
    return;
  }
  const size = viewer.viewport.getContainerSize();
  relightDrawerOf(viewer).setTileCacheCount(cacheTileCount({
    width: size.x, height: size.y, minPixelRatio: minPixelRatioOf(viewer), planes,
  }));
}

/** The viewer's `minPixelRatio` (an option OpenSeadragon keeps on the viewer; untyped there). */
export function minPixelRatioOf(viewer: OpenSeadragon.Viewer): number {
  return (viewer as unknown as { minPixelRatio?: number }).minPixelRatio ?? FULL_DETAIL;
}
