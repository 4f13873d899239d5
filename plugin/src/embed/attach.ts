/**
 * `attachLanterna`: a Lanterna viewer on an OpenSeadragon 6 viewer the page already made and keeps
 * (its options, its navigation controls, its other items). The page's viewer gets the Lanterna drawer
 * through OpenSeadragon's public `requestDrawer`; the rest is `createViewer`'s own wiring
 * (`viewer/viewer.ts`), so the returned API is the same. What OpenSeadragon 6.1 allows and what
 * happens to the page's items is in docs/embedding.md.
 */
import type OpenSeadragon from 'openseadragon';
import type { AttachLanternaOptions, LanternaViewer } from '../api/viewer-api';
import { RelightDrawer, WebGLUnavailableError } from '../drawer/relight-drawer';
import { LanternaError } from '../errors';
import { PatchTileSource } from '../overlay/patch-source';
import { BundleTileSource } from '../tiles/bundle-tile-source';
import { relightDrawerOf } from '../viewer/osd-viewer';
import { wireViewer } from '../viewer/viewer';
import { hostProblem, type HostViewer } from './host-check';
import { restoreCandidates } from './host-drawer';

type ItemEvent = { item: OpenSeadragon.TiledImage };

/**
 * Per page viewer: whether a Lanterna viewer is attached now, and how to stop removing the items a
 * destroyed one was still opening.
 */
const attachments = new WeakMap<OpenSeadragon.Viewer, { live: boolean; stop: () => void }>();

/** A TiledImage Lanterna made: a layer or lens layer (plane bundles) or an overlay level or patch. */
function isLanternaItem(item: OpenSeadragon.TiledImage): boolean {
  const source = item.source as unknown;
  return source instanceof BundleTileSource || source instanceof PatchTileSource;
}

/**
 * Show a Lanterna manifest in an OpenSeadragon 6 viewer the page made: the viewer's drawer becomes
 * the Lanterna drawer and Lanterna adds its layers' TiledImages (at x = 0, 1 wide). The page's own
 * items stay in the world, hidden (opacity 0: they load nothing) while Lanterna is attached.
 *
 * `destroy()` removes Lanterna's items, handlers and widgets, gives the page's items their opacity
 * back and gives the viewer a standard drawer again (the one it had, else `'webgl'`, else `'canvas'`).
 *
 * @example
 * ```ts
 * const viewer = OpenSeadragon({ element: 'osd', showNavigationControl: true });
 * const lanterna = attachLanterna(viewer, { manifest: 'https://example.org/datasets/ushabti/manifest.json' });
 * await lanterna.ready;
 * lanterna.setLight(0.5, 0.5);
 * ```
 *
 * @throws {@link LanternaError} if `viewer` is not a running OpenSeadragon 6 viewer or already has
 *   Lanterna attached; {@link WebGLUnavailableError} without WebGL2
 */
export function attachLanterna(viewer: OpenSeadragon.Viewer, options: AttachLanternaOptions): LanternaViewer {
  const before = attachments.get(viewer);
  const problem = hostProblem(viewer, before?.live === true);
  if (problem !== null) {
    throw new LanternaError(problem);
  }
  const host = viewer as unknown as Required<HostViewer>;
  if (!RelightDrawer.isSupported()) {
    throw new WebGLUnavailableError('WebGL2 is not available in this browser, so the Lanterna drawer cannot start');
  }
  before?.stop();
  const previous = (viewer.drawer as { getType?: () => string } | null)?.getType?.() ?? null;
  const hostCacheCount = host.maxImageCacheCount;
  // Its own (empty) drawer options, not the page's `drawerOptions.custom` (meant for another drawer).
  if (host.requestDrawer.call(viewer, RelightDrawer, { mainDrawer: true, drawerOptions: {} }) === false) {
    throw new WebGLUnavailableError('the Lanterna drawer could not start on this viewer (WebGL2)');
  }

  const items = new Set<OpenSeadragon.TiledImage>();
  // The page's items, hidden while Lanterna is attached (at opacity 0 they load nothing; the Lanterna
  // drawer cannot draw them), with the opacity each gets back.
  const hidden = new Map<OpenSeadragon.TiledImage, number>();
  const hide = (item: OpenSeadragon.TiledImage): void => {
    hidden.set(item, item.getOpacity());
    item.setOpacity(0);
  };
  for (let i = 0; i < viewer.world.getItemCount(); i++) {
    hide(viewer.world.getItemAt(i));
  }
  const onAdd = (event: ItemEvent): void => {
    if (isLanternaItem(event.item)) {
      items.add(event.item);
    } else {
      hide(event.item);
    }
  };
  const onRemove = (event: ItemEvent): void => {
    items.delete(event.item);
    hidden.delete(event.item);
  };
  viewer.world.addHandler('add-item', onAdd);
  viewer.world.addHandler('remove-item', onRemove);
  attachments.set(viewer, { live: true, stop: () => undefined });

  const release = (): void => {
    viewer.world.removeHandler('add-item', onAdd);
    viewer.world.removeHandler('remove-item', onRemove);
    attachments.delete(viewer);
    if (host.isDestroyed()) {
      return; // the page destroyed its viewer first: nothing to give back
    }
    if (hostCacheCount !== undefined) {
      relightDrawerOf(viewer).setTileCacheCount(hostCacheCount);
    }
    for (const item of [...items]) {
      viewer.world.removeItem(item);
    }
    items.clear();
    for (const [item, opacity] of hidden) {
      if (viewer.world.getIndexOfItem(item) !== -1 && item.getOpacity() === 0) {
        item.setOpacity(opacity);
      }
    }
    hidden.clear();
    for (const type of restoreCandidates(previous)) {
      if (host.requestDrawer.call(viewer, type, { mainDrawer: true }) !== false) {
        break;
      }
    }
    // Items still opening when destroy() came are removed as they arrive, until Lanterna comes again.
    const sweep = (event: ItemEvent): void => {
      if (isLanternaItem(event.item)) {
        viewer.world.removeItem(event.item);
      }
    };
    viewer.world.addHandler('add-item', sweep);
    attachments.set(viewer, { live: false, stop: () => { viewer.world.removeHandler('add-item', sweep); } });
  };
  return wireViewer(viewer, options, { release });
}
