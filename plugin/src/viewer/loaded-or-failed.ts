/**
 * Waiting before a snapshot: until the view is fully loaded, or, when some of its tiles failed,
 * until nothing else is loading (the snapshot then shows what is drawn: a coarser level there).
 */
import type { LanternaViewer } from '../api/viewer-api';

/** The parts of OpenSeadragon's image loader read here. */
interface LoaderLike {
  jobsInProgress?: number;
  jobQueue?: readonly unknown[];
}

function nextFrame(): Promise<void> {
  return new Promise((resolve) => { requestAnimationFrame(() => { resolve(); }); });
}

/** Resolve once the view is fully loaded, or its tiles failed and three frames passed with no tile loading. */
export async function loadedOrFailed(api: LanternaViewer): Promise<void> {
  let loaded = false;
  const whole = api.whenFullyLoaded().then(() => { loaded = true; });
  const osd = api.viewer as unknown as { imageLoader?: LoaderLike; isAnimating(): boolean };
  const loader = osd.imageLoader;
  let idle = 0;
  while (!loaded) {
    await nextFrame();
    const failed = api.getNotices().some((n) => n.kind === 'tiles-failed');
    const busy = (loader?.jobsInProgress ?? 0) > 0 || (loader?.jobQueue?.length ?? 0) > 0;
    idle = failed && !busy && !osd.isAnimating() ? idle + 1 : 0;
    if (idle >= 3) {
      return;
    }
  }
  await whole;
}
