/**
 * The viewer's individual annotations (`docs/annotations.md`, "Individual annotations in the
 * viewer"): the layers' annotation pages fetched, their patches kept with the hidden ones
 * ({@link AnnotationSet}), the hover highlight (an outlined box on the patch's rectangle, an
 * OpenSeadragon overlay element), and the refresh after a rebuild (the manifest fetched again).
 */
import OpenSeadragon from 'openseadragon';
import type { LanternaViewer } from '../api/viewer-api';
import { AnnotationSet } from '../annotations/annotation-set';
import { outlineRect } from '../annotations/draw-plan';
import { LanternaError } from '../errors';
import { parseAnnotationPage, referencedPages, type PatchAnnotation } from '../iiif/annotation-page';
import { fetchJson } from '../iiif/load';
import { parseManifest } from '../iiif/manifest';
import type { OverlayLevel } from '../iiif/overlays';
import { isRenderMode } from '../render/modes';
import { DEFAULT_RENDER_PARAMS, mergeParams } from '../render/params';

/** The class of the highlight box. */
export const HIGHLIGHT_CLASS = 'lanterna-annotation-highlight';

/** What a manifest says of the annotations: every layer's overlay levels and patches. */
export interface AnnotationSnapshot {
  readonly overlays: ReadonlyMap<string, readonly OverlayLevel[]>;
  readonly patches: readonly PatchAnnotation[];
}

/**
 * The patches of every annotation page a manifest references (fetched in parallel).
 *
 * @throws {@link FetchError} or {@link AnnotationPageError} naming the page
 */
export async function fetchPatches(manifest: unknown, layerIds: readonly string[],
  init?: RequestInit): Promise<PatchAnnotation[]> {
  const pages = await Promise.all(referencedPages(manifest).map(async (url) =>
    parseAnnotationPage(await fetchJson(url, init), url, layerIds)));
  return pages.flat();
}

/**
 * The manifest at `url` fetched again, past the HTTP cache (`cache: 'no-cache'`: revalidated), with
 * its annotation pages: the overlay levels and patches of the layers in `layerIds`.
 */
export async function fetchAnnotations(url: string, layerIds: readonly string[],
  init?: RequestInit): Promise<AnnotationSnapshot> {
  const fresh: RequestInit = { ...init, cache: 'no-cache' };
  const doc = await fetchJson(url, fresh);
  const layers = parseManifest(doc).layers.filter((l) => layerIds.includes(l.id));
  const patches = await fetchPatches(doc, layerIds, fresh);
  return { overlays: new Map(layers.map((l) => [l.id, l.overlays])), patches };
}

/**
 * Fit the view to a patch's rectangle and restore the render state it was drawn under (layer, mode,
 * parameters, light; a layer or mode this dataset no longer has is left as it is). Without a
 * recorded state, the patch's own layer is shown.
 */
export async function focusPatch(api: LanternaViewer, patch: PatchAnnotation): Promise<void> {
  const s = patch.state;
  const layers = api.getLayers();
  const layer = s && layers.some((l) => l.id === s.layer) ? s.layer : patch.layer;
  const modes = layers.find((l) => l.id === layer)?.modes ?? [];
  const mode = s && isRenderMode(s.mode) && modes.includes(s.mode) ? s.mode : undefined;
  await api.setState({
    layer,
    ...(mode ? { mode } : {}),
    ...(s ? { params: mergeParams(DEFAULT_RENDER_PARAMS, s.params), light: s.light } : {}),
    view: [patch.x, patch.y, patch.w, patch.h],
  });
}

/** The annotations of a viewer and their highlight. */
export class AnnotationWiring {
  /** The patches per layer and the hidden ones. */
  readonly set = new AnnotationSet();
  readonly #viewer: OpenSeadragon.Viewer;
  #box: HTMLElement | null = null;
  #highlighted: PatchAnnotation | null = null;

  constructor(viewer: OpenSeadragon.Viewer) {
    this.#viewer = viewer;
  }

  /**
   * The patch `id`, of layer `preferred` if it has one.
   *
   * @throws {@link LanternaError} when no layer has it
   */
  require(id: string, preferred: string): PatchAnnotation {
    const patch = this.set.find(id, preferred);
    if (!patch) {
      throw new LanternaError(`no annotation ${JSON.stringify(id)}`);
    }
    return patch;
  }

  /** Outline `patch`'s rectangle over the view (null: no highlight); `canvasWidth` is 1 viewport unit. */
  highlight(patch: PatchAnnotation | null, canvasWidth: number): void {
    this.#highlighted = patch;
    if (!patch) {
      if (this.#box) {
        this.#viewer.removeOverlay(this.#box);
        this.#box = null;
      }
      return;
    }
    const r = outlineRect(patch, canvasWidth);
    const location = new OpenSeadragon.Rect(r.x, r.y, r.width, r.height);
    if (this.#box) {
      this.#viewer.updateOverlay(this.#box, location);
      return;
    }
    const box = document.createElement('div');
    box.className = HIGHLIGHT_CLASS;
    box.setAttribute('aria-hidden', 'true');
    Object.assign(box.style, {
      boxSizing: 'border-box', border: '2px solid #ffd54a', outline: '1px solid rgba(0, 0, 0, 0.7)',
      outlineOffset: '0', boxShadow: 'inset 0 0 0 1px rgba(0, 0, 0, 0.7)', pointerEvents: 'none',
    });
    this.#viewer.addOverlay({ element: box, location });
    this.#box = box;
  }

  /** Replace the patches (after a refresh); a highlighted patch that is gone loses its highlight. */
  replace(patches: readonly PatchAnnotation[], canvasWidth: number): void {
    this.set.replace(patches);
    const shown = this.#highlighted;
    if (shown) {
      const again = this.set.list(shown.layer).find((p) => p.id === shown.id) ?? null;
      this.highlight(again, canvasWidth);
    }
  }

  /** Remove the highlight. */
  destroy(): void {
    this.highlight(null, 1);
  }
}
