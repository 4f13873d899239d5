/**
 * The running Lanterna viewer of each Mirador window, so that other plugins (the window's controls,
 * annotation selection) reach it through the public `LanternaViewer` API.
 */
import type { LanternaViewer } from '../api/viewer-api';

const viewers = new Map<string, LanternaViewer>();
const watchers = new Map<string, Set<(v: LanternaViewer | null) => void>>();

/** Record the viewer of a window (null: the window has none now) and tell the window's watchers. */
export function setWindowViewer(windowId: string, viewer: LanternaViewer | null): void {
  if ((viewers.get(windowId) ?? null) === viewer) {
    return;
  }
  if (viewer) {
    viewers.set(windowId, viewer);
  } else {
    viewers.delete(windowId);
  }
  for (const cb of [...(watchers.get(windowId) ?? [])]) {
    cb(viewer);
  }
}

/** The Lanterna viewer of a window, or null when the window shows none (not a Lanterna canvas). */
export function getWindowViewer(windowId: string): LanternaViewer | null {
  return viewers.get(windowId) ?? null;
}

/**
 * Call `cb` with the window's viewer now and on each change (a new canvas, the window closed);
 * returns the function that stops it.
 */
export function watchWindowViewer(windowId: string, cb: (v: LanternaViewer | null) => void): () => void {
  let set = watchers.get(windowId);
  if (!set) {
    set = new Set();
    watchers.set(windowId, set);
  }
  set.add(cb);
  cb(getWindowViewer(windowId));
  return () => {
    const current = watchers.get(windowId);
    current?.delete(cb);
    if (current?.size === 0) {
      watchers.delete(windowId);
    }
  };
}

/** The ids of the windows that have a viewer now. */
export function windowsWithViewers(): string[] {
  return [...viewers.keys()];
}
