/**
 * Mirador's annotation panel driving the Lanterna view (docs/mirador.md): an `add` plugin of
 * `Window` (rendered once per window, drawing nothing) that follows the window's
 * `selectedAnnotationId` and `hoveredAnnotationIds`. Selecting an annotation runs its
 * {@link selectionPlan} on the window's Lanterna viewer (fit its region, show the overlays, focus a
 * patch); hovering one of our patches outlines it (`highlightAnnotation`).
 */
import { useEffect, useRef } from 'react';
import type { LanternaViewer } from '../../api/viewer-api';
import type { MiradorPlugin, MiradorState } from '../types';
import { canvasSize, findAnnotation, type Size } from './annotation-target';
import { useWindowViewer } from './companion-window';
import { parts } from './mirador-parts';
import { hoverPatch, selectionPlan, type SelectionStep, type ViewerFacts } from './selection-plan';

interface FollowerProps {
  readonly windowId: string;
  readonly selectedAnnotationId?: string | null;
  readonly hoveredAnnotationIds?: readonly string[];
  /** The annotation pages (JSON) of the window's visible canvases. */
  readonly annotationPages: readonly unknown[];
  /** The size of the window's first visible canvas, when the manifest gives it. */
  readonly canvas: Size | null;
}

/** What the plan needs of a ready viewer. */
export function viewerFacts(viewer: LanternaViewer, canvas: Size | null): ViewerFacts | null {
  const image = viewer.layer?.geometry;
  if (!image) {
    return null;
  }
  const layers = viewer.getLayers().map((l) => l.id);
  return {
    layers,
    activeLayer: viewer.getActiveLayer(),
    patches: layers.flatMap((id) => viewer.getAnnotations(id)),
    image: { width: image.width, height: image.height },
    canvas,
  };
}

/** Run the steps in order on the viewer (each waits for the one before). */
async function runSteps(viewer: LanternaViewer, steps: readonly SelectionStep[]): Promise<void> {
  for (const s of steps) {
    switch (s.step) {
      case 'focus':
        await viewer.focusAnnotation(s.patch);
        break;
      case 'layer':
        await viewer.setActiveLayer(s.layer);
        break;
      case 'overlays':
        viewer.setOverlaysVisible(true);
        break;
      case 'region':
        viewer.showImageRegion(...s.region);
        break;
    }
  }
}

function AnnotationFollower(props: FollowerProps): null {
  const { windowId, selectedAnnotationId = null, hoveredAnnotationIds = [] } = props;
  const viewer = useWindowViewer(windowId);
  const latest = useRef(props);
  latest.current = props;
  useEffect(() => {
    if (!viewer || !selectedAnnotationId) {
      return undefined;
    }
    let live = true;
    viewer.ready.then(async () => {
      const { annotationPages, canvas } = latest.current;
      const facts = viewerFacts(viewer, canvas);
      if (live && facts) {
        await runSteps(viewer, selectionPlan(findAnnotation(annotationPages, selectedAnnotationId), facts));
      }
    }).catch((error: unknown) => { viewer.reportError(error); });
    return () => { live = false; };
  }, [viewer, selectedAnnotationId]);
  const hovered = hoveredAnnotationIds[0] ?? null;
  useEffect(() => {
    if (!viewer) {
      return undefined;
    }
    const patch = hovered ? hoverPatch(findAnnotation(latest.current.annotationPages, hovered), {
      patches: viewer.getLayers().flatMap((l) => viewer.getAnnotations(l.id)),
    }) : null;
    if (!patch) {
      return undefined;
    }
    viewer.highlightAnnotation(patch);
    return () => { viewer.highlightAnnotation(null); };
  }, [viewer, hovered]);
  return null;
}

const NO_PAGES: readonly unknown[] = [];

/** The window's annotation pages (their JSON), in canvas then page order. */
function annotationPages(state: MiradorState, windowId: string): readonly unknown[] {
  const all = parts.getAnnotations(state) ?? {};
  const pages = parts.getVisibleCanvasIds(state, { windowId })
    .flatMap((canvasId) => Object.values(all[canvasId] ?? {}).map((page) => page.json));
  return pages.length === 0 ? NO_PAGES : pages;
}

/** The plugin: the window's selection, hover, annotation pages and canvas size from Mirador's state. */
export const annotationFollowerPlugin: MiradorPlugin = {
  name: 'LanternaAnnotationFollower',
  target: 'Window',
  mode: 'add',
  component: AnnotationFollower,
  mapStateToProps: (state: MiradorState, { windowId }: Record<string, unknown>) => {
    if (typeof windowId !== 'string') {
      return { annotationPages: NO_PAGES, canvas: null };
    }
    const win = parts.getWindow(state, { windowId });
    const [canvasId] = parts.getVisibleCanvasIds(state, { windowId });
    const manifest = parts.getManifest(state, { windowId })?.json;
    return {
      selectedAnnotationId: win?.selectedAnnotationId ?? null,
      hoveredAnnotationIds: win?.hoveredAnnotationIds,
      annotationPages: annotationPages(state, windowId),
      canvas: canvasId === undefined ? null : canvasSize(manifest, canvasId),
    };
  },
};
