/**
 * The page's loading indicator: a thin bar in the toolbar while tiles of the view are loading (the
 * first opening, a layer switch, a zoom), gone once every visible item is fully loaded.
 */
import type { LanternaViewer } from '../index';

/** Whether some visible item of the viewer still loads tiles. */
export function isLoading(lanterna: LanternaViewer): boolean {
  const { world } = lanterna.viewer;
  for (let i = 0; i < world.getItemCount(); i++) {
    const item = world.getItemAt(i);
    if (item.getOpacity() > 0 && !item.getFullyLoaded()) {
      return true;
    }
  }
  return false;
}

/** Show `bar` while `lanterna` loads (checked once per animation frame). Returns a stop function. */
export function trackLoading(lanterna: LanternaViewer, bar: HTMLElement): () => void {
  let ready = false;
  let stopped = false;
  void lanterna.ready.then(() => { ready = true; }, () => { stopped = true; bar.hidden = true; });
  const tick = (): void => {
    if (stopped) {
      return;
    }
    const busy = !ready || isLoading(lanterna);
    if (bar.hidden === busy) {
      bar.hidden = !busy;
    }
    requestAnimationFrame(tick);
  };
  bar.hidden = false;
  requestAnimationFrame(tick);
  return () => {
    stopped = true;
    bar.hidden = true;
  };
}
