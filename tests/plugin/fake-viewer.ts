/** A fake OpenSeadragon viewer for the tests: its events, the world's update and redraws. */
import type OpenSeadragon from 'openseadragon';

type Handler = (event: Record<string, unknown>) => void;

/** What a test can do with the fake viewer. */
export interface FakeViewer {
  readonly viewer: OpenSeadragon.Viewer;
  /** Raise a viewer event. */
  readonly raise: (name: string, event: Record<string, unknown>) => void;
  /** Calls of `viewer.world.update` so far. */
  readonly updates: () => number;
  /** Handlers added and not removed. */
  readonly handlers: () => number;
}

export function fakeViewer(): FakeViewer {
  const handlers = new Map<string, Set<Handler>>();
  let updates = 0;
  const viewer = {
    addHandler: (name: string, h: Handler) => { handlers.set(name, (handlers.get(name) ?? new Set()).add(h)); },
    removeHandler: (name: string, h: Handler) => { handlers.get(name)?.delete(h); },
    world: { update: () => { updates++; } },
    forceRedraw: () => undefined,
  };
  return {
    viewer: viewer as unknown as OpenSeadragon.Viewer,
    raise: (name, e) => { for (const h of handlers.get(name) ?? []) { h(e); } },
    updates: () => updates,
    handlers: () => [...handlers.values()].reduce((n, s) => n + s.size, 0),
  };
}
