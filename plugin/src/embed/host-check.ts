/**
 * Whether `attachLanterna` can take a page's viewer: an OpenSeadragon 6 viewer (it has
 * `requestDrawer`), not destroyed, without a Lanterna viewer attached already. Pure: the viewer is only
 * looked at.
 */

/** The members of an OpenSeadragon 6 viewer attaching needs (typed locally: the shipped types lack some). */
export interface HostViewer {
  requestDrawer?: (candidate: unknown, options?: { mainDrawer?: boolean; drawerOptions?: object }) => unknown;
  isDestroyed?: () => boolean;
  /** The viewer's `maxImageCacheCount` option (its tile cache's size). */
  maxImageCacheCount?: number;
}

/** What is wrong with attaching to `viewer` (one line), or null when nothing is. */
export function hostProblem(viewer: unknown, attached: boolean): string | null {
  const host = (typeof viewer === 'object' && viewer !== null ? viewer : {}) as HostViewer;
  if (typeof host.requestDrawer !== 'function') {
    return 'attachLanterna needs an OpenSeadragon 6 viewer (this one has no requestDrawer)';
  }
  if (typeof host.isDestroyed === 'function' && host.isDestroyed()) {
    return 'attachLanterna: this OpenSeadragon viewer has been destroyed';
  }
  if (attached) {
    return 'this OpenSeadragon viewer already has Lanterna attached: destroy() that one first';
  }
  return null;
}
