/**
 * Waiting before a snapshot: until the view is fully loaded, or some of its tiles failed.
 */
import type { LanternaViewer } from '../api/viewer-api';

/**
 * Resolve once the view is fully loaded, or as soon as some of its tiles could not be loaded (a
 * `tiles-failed` notice: the snapshot then shows what is drawn, a coarser level there).
 */
export function loadedOrFailed(api: LanternaViewer): Promise<void> {
  const failed = (): boolean => api.getNotices().some((n) => n.kind === 'tiles-failed');
  let stop = (): void => undefined;
  const onFailure = new Promise<void>((resolve) => {
    stop = api.onChange(() => {
      if (failed()) {
        resolve();
      }
    });
  });
  return (failed() ? Promise.resolve() : Promise.race([api.whenFullyLoaded(), onFailure])).finally(() => { stop(); });
}
