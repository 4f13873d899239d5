/**
 * The page's toolbar: what a drag does, Home (into the free area), zoom in and out, the lens, the
 * annotations (disabled, saying where they are, on layers without any), Annotate (when the server
 * takes patches), Measure, and the panel toggle. The
 * `#tools` container is left for page widgets mounted later.
 */
import type { Annotator, LanternaViewer, MeasurementWidget } from '../index';
import type { Layout } from './layout';

/** Zoom factor of the zoom buttons. */
const ZOOM_STEP = 1.5;

function byId<T extends HTMLElement = HTMLButtonElement>(id: string): T | null {
  return document.getElementById(id) as T | null;
}

/** Wire the toolbar's buttons to `lanterna`; `attempt` runs an action and reports its errors. */
export function wireToolbar(lanterna: LanternaViewer, layout: Layout, attempt: (action: () => unknown) => void): void {
  const modeButton = byId('mode');
  modeButton?.addEventListener('click', () => {
    const next = lanterna.getMode() === 'pan' ? 'light' : 'pan'; // from measure: pan
    lanterna.setMode(next);
    modeButton.textContent = next === 'light' ? 'Drag: light' : 'Drag: pan';
    modeButton.setAttribute('aria-pressed', String(next === 'light'));
  });
  byId('home')?.addEventListener('click', () => { layout.home(); });
  const zoom = (factor: number): void => {
    const { viewport } = lanterna.viewer;
    viewport.zoomBy(factor);
    viewport.applyConstraints();
  };
  byId('zoom-in')?.addEventListener('click', () => { zoom(ZOOM_STEP); });
  byId('zoom-out')?.addEventListener('click', () => { zoom(1 / ZOOM_STEP); });
  const lensButton = byId('lens');
  lensButton?.addEventListener('click', () => {
    attempt(() => lanterna.setLens({ enabled: !lanterna.getLens().enabled }));
  });
  const overlaysButton = byId('overlays');
  overlaysButton?.addEventListener('click', () => {
    lanterna.setOverlaysVisible(!lanterna.getOverlaysVisible());
  });
  const sync = (): void => {
    lensButton?.setAttribute('aria-pressed', String(lanterna.getLens().enabled));
    if (!overlaysButton) {
      return;
    }
    const layers = lanterna.manifest?.layers ?? [];
    const annotated = layers.filter((l) => l.overlays.length > 0);
    const here = annotated.some((l) => l.id === lanterna.getActiveLayer());
    overlaysButton.hidden = annotated.length === 0;
    overlaysButton.disabled = !here;
    overlaysButton.setAttribute('aria-pressed', String(here && lanterna.getOverlaysVisible()));
    overlaysButton.title = here ? 'Show the annotations of the current level'
      : `No annotations on this layer; annotated: ${annotated.map((l) => l.label).join(', ')}`;
  };
  lanterna.onChange(sync);
  void lanterna.ready.then(sync, () => undefined);
}

/** Hide the toolbar's buttons (nothing to act on). */
export function hideToolbarButtons(): void {
  for (const button of document.querySelectorAll<HTMLElement>('#toolbar button')) {
    button.hidden = true;
  }
}

/**
 * The Measure button: shown when a layer can be measured (every layer can: images show their value),
 * it turns measurement mode on and off; the Drag button shows what a drag does meanwhile.
 */
export function wireMeasureButton(lanterna: LanternaViewer, measurement: MeasurementWidget): void {
  const button = byId('measure');
  const modeButton = byId('mode');
  if (!button) {
    return;
  }
  button.hidden = false;
  const sync = (): void => {
    const on = measurement.isEnabled();
    button.setAttribute('aria-pressed', String(on));
    if (modeButton) {
      const mode = lanterna.getMode();
      modeButton.textContent = mode === 'measure' ? 'Drag: measure' : mode === 'light' ? 'Drag: light' : 'Drag: pan';
      modeButton.setAttribute('aria-pressed', String(mode === 'light'));
    }
  };
  button.addEventListener('click', () => {
    measurement.setEnabled(!measurement.isEnabled());
    sync();
  });
  modeButton?.addEventListener('click', () => {
    if (measurement.isEnabled()) {
      measurement.setEnabled(false);
      lanterna.setMode('pan'); // the Drag button's own handler already ran: keep its choice visible
    }
    sync();
  });
  lanterna.onChange(sync);
  sync();
}

/**
 * The Annotate button: shown once the server says it takes patches (`GET /api/` → authoring true),
 * it starts a patch on the current view and stops it.
 */
export function wireAnnotateButton(annotator: Annotator, attempt: (action: () => unknown) => void): void {
  const button = byId('annotate');
  if (!button) {
    return;
  }
  const sync = (): void => { button.setAttribute('aria-pressed', String(annotator.isActive())); };
  button.addEventListener('click', () => {
    attempt(() => { if (annotator.isActive()) { annotator.stop(); } else { annotator.start(); } });
  });
  annotator.onChange(sync);
  // The toolbox sits below the toolbar, which wraps onto more rows on narrow screens.
  const toolbar = byId<HTMLElement>('toolbar');
  if (toolbar) {
    const place = (): void => {
      document.documentElement.style.setProperty('--lanterna-toolbar-bottom', `${toolbar.getBoundingClientRect().bottom}px`);
    };
    new ResizeObserver(place).observe(toolbar);
    place();
  }
  void annotator.probe().then((allowed) => {
    button.hidden = !allowed;
    button.dataset.checked = 'true';
  });
  sync();
}
