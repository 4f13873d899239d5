/**
 * Waiting for a viewer to settle: every visible item fully loaded and drawn, nothing animating.
 */
import type OpenSeadragon from 'openseadragon';
import { LanternaError } from '../errors';

function nextFrame(): Promise<void> {
  return new Promise((resolve) => { requestAnimationFrame(() => { resolve(); }); });
}

/**
 * Resolve when every tile needed for the current view is loaded and drawn.
 *
 * @param busy - true while items not yet in the world (overlays, the lens) are still being opened
 * @param destroyed - true once the viewer is destroyed (the promise then rejects)
 */
export async function whenFullyLoaded(viewer: OpenSeadragon.Viewer, busy: () => boolean,
  destroyed: () => boolean): Promise<void> {
  // Let OSD run at least one update for the current view, then wait for a frame that was drawn
  // with every visible item fully loaded and nothing animating.
  let stable = 0;
  for (let frame = 0; stable < 3; frame++) {
    await nextFrame();
    if (destroyed()) {
      throw new LanternaError('viewer destroyed');
    }
    const count = viewer.world.getItemCount();
    let loaded = false;
    let allLoaded = !busy();
    for (let i = 0; i < count; i++) {
      const ti = viewer.world.getItemAt(i);
      if (ti.getOpacity() > 0) {
        loaded = true;
        allLoaded &&= ti.getFullyLoaded();
      }
    }
    loaded &&= allLoaded;
    stable = loaded && !(viewer as unknown as { isAnimating(): boolean }).isAnimating() && frame >= 2 ? stable + 1 : 0;
    if (stable === 1) {
      viewer.forceRedraw();
    }
  }
}
