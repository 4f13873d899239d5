/**
 * The OpenSeadragon viewer a Lanterna viewer runs on: its options (the Lanterna drawer, no
 * navigator, level selection) and access to its drawer.
 */
import OpenSeadragon from 'openseadragon';
import { RelightDrawer, WebGLUnavailableError } from '../drawer/relight-drawer';

/**
 * Create the OpenSeadragon viewer in `element`; `osd` overrides the defaults.
 *
 * @throws {@link WebGLUnavailableError} without WebGL2 (OpenSeadragon would throw a bare Error)
 */
export function createOsdViewer(element: HTMLElement, osd?: Partial<OpenSeadragon.Options>): OpenSeadragon.Viewer {
  if (!RelightDrawer.isSupported()) {
    throw new WebGLUnavailableError('WebGL2 is not available in this browser, so the Lanterna drawer cannot start');
  }
  return OpenSeadragon({
    element,
    drawer: RelightDrawer,
    crossOriginPolicy: 'Anonymous',
    showNavigator: false,
    showNavigationControl: false,
    blendTime: 0,
    immediateRender: false,
    // Levels finer than needed (render ratio < 0.75) are skipped, so at 1 screen px = 2 image px the
    // next coarser level is drawn, never a half-faded finer one.
    minPixelRatio: 0.75,
    maxZoomPixelRatio: 16,
    minZoomImageRatio: 0.05,
    visibilityRatio: 0.1,
    maxImageCacheCount: 150,
    // At most 8 bundles (8·K plane requests) at a time: OpenSeadragon's time limit (`timeout`) runs
    // from a job's start, so without a limit a tile queued behind hundreds of plane requests in the
    // browser could time out on a slow network without anything being wrong.
    imageLoaderLimit: 8,
    gestureSettingsMouse: { clickToZoom: false, dblClickToZoom: true },
    gestureSettingsTouch: { flickEnabled: false },
    silenceMultiImageWarnings: true,
    ...osd,
  });
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
