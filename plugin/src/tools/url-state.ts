/**
 * `attachUrlState`: keep the page's URL hash and the viewer's state in step (`docs/viewer-api.md`,
 * "The link format"). On `ready` the hash's state is restored; as the state changes the hash is
 * rewritten (debounced, `history.replaceState`: no history entry per change); a `hashchange` (a
 * link pasted into the address bar) restores again. Before a hash is written the viewer is set to
 * the rounded state it encodes, so what the page shows is exactly what the link shows. The viewer
 * element's `data-lanterna-link` holds the hash last written (the page shows exactly that state).
 */
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import { checkLayers, decodeHash, encodeHash } from '../state/hash-codec';
import { roundState, sameState, type ViewState } from '../state/view-state';

/** Options of {@link attachUrlState}. */
export interface UrlStateOptions {
  /** Quiet time after the last change before the hash is written, ms. @default 300 */
  readonly delayMs?: number;
}

/** Start syncing; returns a function that stops it. */
export function attachUrlState(lanterna: LanternaViewer, options: UrlStateOptions = {}): () => void {
  const delay = options.delayMs ?? 300;
  let shown: ViewState | null = null; // the rounded state last applied and written
  let timer: ReturnType<typeof setTimeout> | undefined;
  let chain: Promise<void> = Promise.resolve();
  let stopped = false;

  /**
   * Show `target` rounded (unless it is shown exactly already) and write its hash. The hash encodes
   * exactly the numbers applied, and a link's numbers round to themselves, so a page opened on the
   * link applies the same numbers.
   */
  const settle = async (target: ViewState): Promise<void> => {
    const rounded = roundState(target);
    if (!sameState(lanterna.getState(), rounded, 0)) {
      await lanterna.setState(rounded);
    }
    shown = rounded;
    const hash = encodeHash(rounded);
    if (hash !== window.location.hash) {
      window.history.replaceState(window.history.state, '', hash);
    }
    lanterna.viewer.element.dataset.lanternaLink = hash;
  };
  /** Run `step` after the steps before it (restores and writes never overlap); errors become notices. */
  const exclusive = (step: () => Promise<void>): Promise<void> => {
    chain = chain.then(async () => {
      if (!stopped) {
        await step();
      }
    }).catch((error: unknown) => { lanterna.reportError(error); });
    return chain;
  };
  const write = (): Promise<void> => exclusive(async () => {
    if (lanterna.viewer.element.dataset.lanternaSnapshot !== undefined) {
      schedule(); // a scaled snapshot is moving the view: it puts it back after
      return;
    }
    const now = lanterna.getState();
    if (shown === null || !sameState(now, shown)) {
      await settle(now);
    }
  });
  const schedule = (): void => {
    clearTimeout(timer);
    timer = setTimeout(() => { void write(); }, delay);
  };

  const restore = (): Promise<void> => exclusive(async () => {
    const decoded = decodeHash(window.location.hash);
    const problems = [...decoded.problems];
    if (decoded.state !== null) {
      const checked = checkLayers(decoded.state, lanterna.getLayers(), lanterna.getActiveLayer());
      problems.push(...checked.problems);
      const update = checked.state ?? {};
      try {
        await lanterna.setState(update);
      } catch (error) {
        problems.push(error instanceof Error ? error.message : String(error));
      }
      // What was asked for where it applied, the viewer's own state elsewhere.
      const now = lanterna.getState();
      const lens = { ...now.lens, ...update.lens };
      await settle({ ...now, ...update, lens: { ...lens, layer: lens.layer || now.layer } });
    }
    if (problems.length > 0) {
      lanterna.reportError(new LanternaError(`The link's view could not be restored in full; ignored: ${problems.join('; ')}`));
    }
  });

  const onHashChange = (): void => {
    if (shown === null || window.location.hash !== encodeHash(shown)) {
      shown = null;
      void restore();
    }
  };
  const unsubscribe = lanterna.onChange(schedule);
  const viewer = lanterna.viewer;
  viewer.addHandler('viewport-change', schedule);
  window.addEventListener('hashchange', onHashChange);
  lanterna.ready.then(async () => {
    await restore();
    schedule();
  }, () => undefined);
  return () => {
    stopped = true;
    clearTimeout(timer);
    unsubscribe();
    viewer.removeHandler('viewport-change', schedule);
    window.removeEventListener('hashchange', onHashChange);
  };
}
