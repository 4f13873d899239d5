/**
 * The advanced viewer page (`docs/viewer.md`):
 * `index.html?manifest=URL[&layer=ID][&mode=MODE][&wholeLevelMaxSide=PX][&measure=1]`. Exposes the viewer as
 * `window.lanterna` and its measurement widget as `window.lanternaMeasure` (`&measure=1`: on at start). Test-only: `&minPixelRatio=R` sets OpenSeadragon's `minPixelRatio` (the page
 * shows full detail otherwise; the browser tests pass 0.75 to get exact levels, tests/browser/render.mjs).
 * A dataset that cannot be opened gives a message in the page (`#error`); errors after that
 * (switching layers, the lens, an unknown layer or mode in the URL) show as dismissible notices.
 */
import {
  createAbout, createAnnotationList, createAnnotator, createControls, createLensControls, createLightTools,
  createPresetsPanel, createViewer,
  LanternaError, MODE_LABELS, attempt as attemptReporting, createMeasurement, type MeasurementWidget, UnknownLayerError, isRenderMode, mountViewTools,
  type Annotator, type LanternaViewer,
} from '../index';
import { describeOpenError, showErrorBox } from './error-page';
import { createLayout } from './layout';
import { trackLoading } from './loading';
import { hideToolbarButtons, wireAnnotateButton, wireMeasureButton, wireToolbar } from './toolbar';

declare global {
  interface Window {
    lanterna?: LanternaViewer;
    /** The measurement widget (`&measure=1` turns it on at start). */
    lanternaMeasure?: MeasurementWidget;
  }
}

const errorBox = document.getElementById('error');
const label = document.getElementById('label');
const progress = document.getElementById('progress');

/** Show the page's error box, and hide the controls that have nothing to act on. */
function showFatal(error: unknown, manifestUrl: string | null): void {
  console.error('[lanterna]', error);
  if (errorBox) {
    showErrorBox(errorBox, describeOpenError(error), manifestUrl);
  }
  hideToolbarButtons();
  if (label) {
    label.hidden = true;
  }
  if (progress) {
    progress.hidden = true;
  }
}

/** What the page was asked for in its URL. */
interface PageOptions {
  readonly manifest: string;
  readonly layer: string | undefined;
  readonly mode: string | null;
  readonly wholeLevelMaxSide: number | undefined;
  readonly minPixelRatio: number | null;
  /** Measurement mode on at start. */
  readonly measure: boolean;
}

/** Set the URL's mode, or say why not and keep the default. */
function applyUrlMode(lanterna: LanternaViewer, mode: string): void {
  const layer = lanterna.getLayers().find((l) => l.id === lanterna.getActiveLayer());
  if (isRenderMode(mode) && layer?.modes.includes(mode)) {
    lanterna.setRenderMode(mode);
    return;
  }
  lanterna.reportError(new LanternaError(`The URL asks for the mode "${mode}", which ${isRenderMode(mode)
    ? `does not apply to the layer "${layer?.label ?? ''}"` : 'does not exist'}: showing ${
    MODE_LABELS[lanterna.getRenderMode()]} instead.`));
}

/** Build the panel's sections and the About box; the Annotate tool (its toolbox floats beside the panel). */
function buildPanel(lanterna: LanternaViewer, panel: HTMLElement, manifest: string): Annotator {
  const report = (error: unknown): void => { lanterna.reportError(error); };
  createControls(lanterna, panel, report);
  createLightTools(lanterna, panel);
  createLensControls(lanterna, panel, report);
  createPresetsPanel(lanterna, panel, { manifestUrl: manifest, onError: report });
  createAnnotationList(lanterna, panel, report);
  if (lanterna.manifest) {
    createAbout(lanterna.manifest, panel);
  }
  return createAnnotator(lanterna, { manifestUrl: manifest, container: panel.parentElement ?? document.body });
}

/** Open the viewer and wire the page's controls to it; `fallback` is the notice to show once ready. */
function open(page: PageOptions, fallback: string | null = null): void {
  let lanterna: LanternaViewer;
  try {
    lanterna = createViewer({
      element: 'viewer', manifest: page.manifest, layer: page.layer, wholeLevelMaxSide: page.wholeLevelMaxSide,
      ...(page.minPixelRatio === null ? {} : { osd: { minPixelRatio: page.minPixelRatio } }),
    });
  } catch (error) {
    showFatal(error, page.manifest); // e.g. no WebGL2
    return;
  }
  window.lanterna = lanterna;
  const measurement = createMeasurement(lanterna);
  window.lanternaMeasure = measurement;
  const stopLoading = progress ? trackLoading(lanterna, progress) : () => undefined;
  /** Run an action of a control; its errors become notices over the viewer. */
  const attempt = (action: () => unknown): void => {
    attemptReporting(action, (error) => { lanterna.reportError(error); });
  };
  if (label) {
    label.textContent = 'Loading…';
  }
  const panel = document.getElementById('panel');
  const toolbar = document.getElementById('toolbar');
  const toggle = document.getElementById('panel-toggle') as HTMLButtonElement | null;
  lanterna.ready.then(() => {
    const text = lanterna.manifest?.label ?? '';
    if (label) {
      label.textContent = text;
      label.title = text;
      label.hidden = text === '';
    }
    document.title = text ? `${text} · Lanterna` : 'Lanterna viewer';
    if (fallback) {
      lanterna.reportError(new LanternaError(fallback));
    }
    if (page.mode !== null) {
      attempt(() => { applyUrlMode(lanterna, page.mode ?? ''); });
    }
    measurement.setEnabled(page.measure);
    if (panel && toolbar && toggle) {
      const annotator = buildPanel(lanterna, panel, page.manifest);
      wireToolbar(lanterna, createLayout(lanterna, panel, toolbar, toggle), attempt);
      wireAnnotateButton(annotator, attempt);
      wireMeasureButton(lanterna, measurement);
    }
    // View tools (issue #13): the URL hash, Snapshot and ? buttons, scale bar, help overlay, canvas keys.
    mountViewTools(lanterna, {
      toolbar: document.getElementById('tools') ?? toolbar,
      home: () => { document.getElementById('home')?.click(); },
    });
  }, (error: unknown) => {
    lanterna.destroy();
    stopLoading();
    if (error instanceof UnknownLayerError && page.layer !== undefined && fallback === null) {
      delete window.lanterna;
      open({ ...page, layer: undefined },
        `The URL asks for the layer "${page.layer}", which this dataset does not have: showing its first layer.`);
      return;
    }
    showFatal(error, page.manifest);
  });
}

const params = new URLSearchParams(window.location.search);
const manifestParam = params.get('manifest');
if (!manifestParam) {
  showFatal(new Error('No manifest given: open this page as …/viewer/?manifest=URL_OF_MANIFEST.json'), null);
} else {
  let manifest: string | null = null;
  try {
    manifest = new URL(manifestParam, window.location.href).href;
  } catch {
    showFatal(new Error(`The manifest parameter is not a URL: ${JSON.stringify(manifestParam)}`), null);
  }
  if (manifest !== null) {
    const side = Number(params.get('wholeLevelMaxSide') ?? Number.NaN);
    const ratio = Number(params.get('minPixelRatio') ?? Number.NaN);
    open({
      manifest, layer: params.get('layer') ?? undefined, mode: params.get('mode'),
      wholeLevelMaxSide: Number.isFinite(side) ? side : undefined,
      minPixelRatio: Number.isFinite(ratio) && ratio > 0 ? ratio : null,
      measure: params.get('measure') === '1',
    });
  }
}
