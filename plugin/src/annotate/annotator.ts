/**
 * The Annotate tool of the advanced viewer (docs/viewer.md "Annotating"): the view in the viewer
 * defines the patch (its rectangle, and the level shown at this zoom), a drawing surface is laid over
 * it and the toolbox drives it; the patch is downloaded as `L_X_Y_W_H_O_INFO.png` or uploaded to the
 * authoring API, after which the page polls the rebuild status and refreshes the overlay without a
 * reload. While annotating, mouse pan and zoom are off; the panel's light, layer and mode still work.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import { allowsAuthoring, storedToken, storeToken } from '../panel/authoring-token';
import { authoringUrls, layerUrls } from '../panel/authoring-url';
import { shownText, waitForBuild } from './build-status';
import { createDrawSurface, type DrawSurface } from './draw-surface';
import { patchFrame, type PatchFrame } from './patch-frame';
import { nextOrder, patchFileName } from './patch-name';
import { AuthoringRequestError, patchMeta, postPatch, putLevelTexts, readStatus } from './patch-upload';
import { canvasPng } from './stroke-render';
import { createToolbox } from './toolbox';

/** Largest drawing the server takes: a side, and the pixel count (docs/serving.md). */
export const MAX_SIDE = 8192;
export const MAX_PIXELS = 16_800_000;

/** Options of {@link createAnnotator}. */
export interface AnnotatorOptions {
  /** The dataset's manifest URL: the authoring API is found from it. */
  readonly manifestUrl: string;
  /** Where the toolbox goes. @default the viewer element's parent */
  readonly container?: HTMLElement;
  /** Re-read the overlays after a new build. @default `lanterna.refreshAnnotations` */
  readonly refresh?: () => Promise<void>;
  /** Milliseconds between status reads after an upload. @default 1000 */
  readonly pollMs?: number;
  /** Milliseconds between status reads in the background, so that others' changes appear. @default 15000 */
  readonly backgroundMs?: number;
}

/** The Annotate tool. */
export interface Annotator {
  /** The toolbox (hidden while not annotating). */
  readonly element: HTMLElement;
  /** Whether the server accepts patches (asked once); starts the background status poll if so. */
  probe(): Promise<boolean>;
  isActive(): boolean;
  /** Start a patch on the current view; throws a `LanternaError` when the view shows no image. */
  start(): void;
  /** Stop annotating (the drawing is dropped). */
  stop(): void;
  /** The patch being drawn, or null. */
  frame(): PatchFrame | null;
  /** Call `listener` when annotating starts or stops; returns an unsubscribe function. */
  onChange(listener: () => void): () => void;
  destroy(): void;
}

type Viewer = Pick<LanternaViewer, 'viewer' | 'getState' | 'getImageRegion' | 'getOverlayState' | 'manifest'
  | 'getActiveLayer' | 'getAnnotations' | 'refreshAnnotations'>;

/** Make the Annotate tool for `lanterna`. */
export function createAnnotator(lanterna: Viewer, options: AnnotatorOptions): Annotator {
  const urls = authoringUrls(options.manifestUrl);
  const refresh = options.refresh ?? (() => lanterna.refreshAnnotations());
  const listeners = new Set<() => void>();
  let surface: DrawSurface | null = null;
  let orders: number[] = [];
  let uploaded = false;
  let busy = false;
  let destroyed = false;
  let mouseNav = true;
  const builds = new Map<string, number>();
  const layer = (): string => lanterna.getActiveLayer();
  /** The layer the patch is drawn for: the active one when it was started (the layer may be switched meanwhile). */
  let patchLayer = '';
  const endpoints = (id = layer()): ReturnType<typeof layerUrls> | null => (urls ? layerUrls(urls, id) : null);

  const toolbox = createToolbox((token) => { void upload(token); });
  (options.container ?? lanterna.viewer.element.parentElement ?? document.body).appendChild(toolbox.element);
  const { buttons } = toolbox;
  const sync = (): void => {
    const h = surface?.history;
    buttons.undo.disabled = !h?.canUndo;
    buttons.redo.disabled = !h?.canRedo;
    buttons.clear.disabled = h?.isEmpty ?? true;
    buttons.download.disabled = h?.isEmpty ?? true;
    buttons.upload.disabled = busy || !urls || (h?.isEmpty ?? true);
    buttons.close.textContent = uploaded && (h?.isEmpty ?? true) ? 'Done' : 'Cancel';
  };
  const notify = (): void => {
    sync();
    for (const l of [...listeners]) {
      l();
    }
  };

  const knownOrders = async (): Promise<void> => {
    orders = lanterna.getAnnotations(patchLayer).map((a) => a.order); // the published ones
    const where = endpoints(patchLayer);
    if (!where) {
      return;
    }
    try {
      const response = await fetch(where.patches, { headers: { Accept: 'application/json' }, cache: 'no-store' });
      if (response.ok) {
        const doc = await response.json() as { patches?: { order?: unknown }[] };
        orders = (doc.patches ?? []).map((p) => p.order).filter((o): o is number => typeof o === 'number');
        // A layer with level images but no patch records yet (a GIMP or scene overlay): its first
        // change puts each level image in the store as a patch of order 0 (docs/annotations.md).
        const levels = lanterna.manifest?.layers.find((l) => l.id === patchLayer)?.overlays.length ?? 0;
        if (orders.length === 0 && levels > 0) {
          orders = [0];
        }
      }
    } catch {
      // no API (a static host): numbered after the published patches
    }
  };

  const onKey = (e: KeyboardEvent): void => {
    const target = e.target as HTMLElement | null;
    if (!surface || !(e.ctrlKey || e.metaKey) || target?.closest('input, textarea, select')) {
      return;
    }
    const key = e.key.toLowerCase();
    if (key === 'z' || key === 'y') {
      e.preventDefault();
      e.stopPropagation();
      if (key === 'y' || e.shiftKey) {
        surface.redo();
      } else {
        surface.undo();
      }
    }
  };

  const start = (): void => {
    if (surface) {
      return;
    }
    const region = lanterna.getImageRegion();
    const canvas = lanterna.manifest?.layer;
    const frame = region && canvas ? patchFrame(region, lanterna.getOverlayState().level, canvas.width, canvas.height)
      : null;
    if (!frame) {
      throw new LanternaError('Nothing to annotate here: bring the object into view first.');
    }
    if (frame.width > MAX_SIDE || frame.height > MAX_SIDE || frame.width * frame.height > MAX_PIXELS) {
      throw new LanternaError(`This view makes a ${frame.width}×${frame.height} px patch, larger than the server `
        + `takes (${MAX_SIDE} px a side): zoom in.`);
    }
    patchLayer = layer();
    surface = createDrawSurface(lanterna, frame, () => toolbox.brush(), notify);
    uploaded = false;
    mouseNav = lanterna.viewer.isMouseNavEnabled();
    lanterna.viewer.setMouseNavEnabled(false);
    document.addEventListener('keydown', onKey, true);
    const label = lanterna.manifest?.layers.find((l) => l.id === patchLayer)?.label ?? patchLayer;
    toolbox.setTitle(`Annotate ${label}: level ${frame.level}, ${frame.w}×${frame.h} px at ${frame.x}, ${frame.y}`);
    toolbox.setStatus(`Draw on the ${frame.width}×${frame.height} px patch.`);
    toolbox.element.hidden = false;
    void knownOrders();
    notify();
  };
  const stop = (): void => {
    if (!surface) {
      return;
    }
    surface.destroy();
    surface = null;
    document.removeEventListener('keydown', onKey, true);
    lanterna.viewer.setMouseNavEnabled(mouseNav);
    toolbox.element.hidden = true;
    toolbox.token.hide();
    notify();
  };

  const fileName = (frame: PatchFrame): string => {
    const t = toolbox.texts();
    return patchFileName(frame, nextOrder(orders), t.textsFor === 'patch' ? t.short : '');
  };
  const download = async (): Promise<void> => {
    if (!surface) {
      return;
    }
    const url = URL.createObjectURL(await canvasPng(surface.canvas));
    const a = Object.assign(document.createElement('a'), { href: url, download: fileName(surface.frame) });
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => { URL.revokeObjectURL(url); }, 60_000);
    toolbox.setStatus(`Downloaded ${a.download}.`);
  };

  const sleep = (ms: number) => () => new Promise<void>((r) => { setTimeout(r, ms); });
  const upload = async (token: string): Promise<void> => {
    const where = endpoints(patchLayer);
    const current = surface;
    if (!where || !current || busy) {
      return;
    }
    busy = true;
    sync();
    current.setEnabled(false);
    const t = toolbox.texts();
    const forPatch = t.textsFor === 'patch';
    let posted = false;
    try {
      const before = await readStatus(where).then((s) => s.build, () => -1);
      const state = lanterna.getState();
      const meta = patchMeta(current.frame, {
        short: forPatch ? t.short : '', long: forPatch ? t.long : '', motivation: t.motivation, author: t.author,
        state: { layer: state.layer, mode: state.mode, params: { ...state.params }, light: state.light },
      });
      toolbox.setStatus('Uploading…');
      const id = await postPatch(where, token, meta, await canvasPng(current.canvas));
      posted = true;
      uploaded = true;
      toolbox.clearTexts();
      storeToken(token);
      toolbox.token.hide();
      if (!forPatch && (t.short || t.long)) {
        await putLevelTexts(where, token, current.frame.level, t.short, t.long);
      }
      toolbox.setStatus(`Uploaded ${id}: rebuilding the overlay…`);
      const done = await waitForBuild(before, {
        read: () => readStatus(where), sleep: sleep(options.pollMs ?? 1000), cancelled: () => destroyed,
        onStatus: (s) => { if (s.state !== 'done') { toolbox.setStatus(`Uploaded ${id}: the overlay is ${s.state}…`); } },
      });
      if (done) {
        builds.set(patchLayer, done.build);
        await refresh();
        toolbox.setStatus(shownText(id, done.build, current.frame.level, lanterna.getOverlayState().level));
      }
    } catch (error) {
      if (error instanceof AuthoringRequestError && error.status === 401) {
        storeToken(null);
        toolbox.token.ask();
      }
      toolbox.setStatus(error instanceof Error ? error.message : String(error), false);
    } finally {
      busy = false;
      current.setEnabled(true);
      if (posted) {
        current.reset(); // the drawing is in the store now (and in the overlay once rebuilt)
      }
      sync();
    }
  };
  const uploadClicked = (): void => {
    const token = storedToken();
    if (token) {
      void upload(token);
    } else {
      toolbox.token.ask();
      toolbox.setStatus('The server asks for the authoring token (kept for this tab only).');
    }
  };

  buttons.undo.addEventListener('click', () => surface?.undo());
  buttons.redo.addEventListener('click', () => surface?.redo());
  buttons.clear.addEventListener('click', () => surface?.clear());
  buttons.download.addEventListener('click', () => {
    download().catch((e: unknown) => { toolbox.setStatus(e instanceof Error ? e.message : String(e), false); });
  });
  buttons.upload.addEventListener('click', uploadClicked);
  buttons.close.addEventListener('click', stop);

  let timer: ReturnType<typeof setInterval> | undefined;
  const backgroundPoll = async (): Promise<void> => {
    const where = endpoints();
    if (!where || busy || document.hidden) {
      return;
    }
    const id = layer();
    const status = await readStatus(where);
    const seen = builds.get(id);
    if (status.state === 'done') {
      builds.set(id, status.build);
      if (seen !== undefined && seen !== status.build) {
        await refresh();
      }
    }
  };
  let probed: Promise<boolean> | null = null;
  const probe = (): Promise<boolean> => {
    probed ??= (urls ? allowsAuthoring(urls) : Promise.resolve(false)).then((allowed) => {
      if (allowed && !destroyed) {
        const tick = (): void => { backgroundPoll().catch(() => undefined); };
        tick();
        timer = setInterval(tick, options.backgroundMs ?? 15_000);
      }
      return allowed;
    });
    return probed;
  };
  sync();
  return {
    element: toolbox.element, probe,
    isActive: () => surface !== null,
    start, stop, frame: () => surface?.frame ?? null,
    onChange(listener) {
      listeners.add(listener);
      return () => { listeners.delete(listener); };
    },
    destroy() {
      destroyed = true;
      stop();
      clearInterval(timer);
      toolbox.element.remove();
      listeners.clear();
    },
  };
}
