/**
 * The OpenSeadragon viewer a Lanterna viewer runs on: its options (the Lanterna drawer, no
 * navigator, level selection) and access to its drawer.
 */
import OpenSeadragon from 'openseadragon';
import { RelightDrawer } from '../drawer/relight-drawer';
import { LanternaError } from '../errors';

/** Create the OpenSeadragon viewer in `element`; `osd` overrides the defaults. */
export function createOsdViewer(element: HTMLElement, osd?: Partial<OpenSeadragon.Options>): OpenSeadragon.Viewer {
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
    gestureSettingsMouse: { clickToZoom: false, dblClickToZoom: true },
    gestureSettingsTouch: { flickEnabled: false },
    silenceMultiImageWarnings: true,
    ...osd,
  });
}

/**
 * The viewer's drawer.
 *
 * @throws {@link LanternaError} if the viewer is not using the Lanterna drawer
 */
export function relightDrawerOf(viewer: OpenSeadragon.Viewer): RelightDrawer {
  const d = viewer.drawer as unknown;
  if (!(d instanceof RelightDrawer)) {
    throw new LanternaError('the viewer is not using the Lanterna drawer (is WebGL2 available?)');
  }
  return d;
}
