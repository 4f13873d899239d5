/**
 * The viewer page: `index.html?manifest=URL[&layer=ID][&mode=MODE][&wholeLevelMaxSide=PX]`. Exposes the viewer as
 * `window.lanterna`. Test-only: `&minPixelRatio=R` sets OpenSeadragon's `minPixelRatio` (the page
 * shows full detail otherwise; the browser tests pass 0.75 to get exact levels, tests/browser/render.mjs). A dataset that cannot be opened gives a message in the page (`#error`); errors
 * after that (switching layers, the lens) show as notices over the viewer.
 */
import { createControls, createLensControls, createViewer, type LanternaViewer, type RenderMode } from '../index';
import { mountViewTools } from '../index';
import { describeOpenError, showErrorBox } from './error-page';

declare global {
  interface Window {
    lanterna?: LanternaViewer;
  }
}

const errorBox = document.getElementById('error');
const label = document.getElementById('label');

/** Show the page's error box, and hide the controls that have nothing to act on. */
function showFatal(error: unknown, manifestUrl: string | null): void {
  console.error('[lanterna]', error);
  if (errorBox) {
    showErrorBox(errorBox, describeOpenError(error), manifestUrl);
  }
  for (const id of ['mode', 'home', 'lens', 'overlays']) {
    const button = document.getElementById(id);
    if (button) {
      button.hidden = true;
    }
  }
  if (label) {
    label.hidden = true;
  }
}

/** Open the viewer on `manifest` and wire the page's controls to it. */
function open(manifest: string, layer: string | undefined, mode: string | null, wholeLevelMaxSide: number | undefined,
  minPixelRatio: number | null): void {
  let lanterna: LanternaViewer;
  try {
    lanterna = createViewer({
      element: 'viewer', manifest, layer, wholeLevelMaxSide,
      ...(minPixelRatio === null ? {} : { osd: { minPixelRatio } }),
    });
  } catch (error) {
    showFatal(error, manifest); // e.g. no WebGL2
    return;
  }
  window.lanterna = lanterna;
  /** Run an action of a control; its errors become notices over the viewer. */
  const attempt = (action: () => unknown): void => {
    try {
      const result = action();
      if (result instanceof Promise) {
        result.catch((error: unknown) => { lanterna.reportError(error); });
      }
    } catch (error) {
      lanterna.reportError(error);
    }
  };
  const report = (error: unknown): void => { lanterna.reportError(error); };
  if (label) {
    label.textContent = 'Loading…';
  }
  const modeButton = document.getElementById('mode');
  const homeButton = document.getElementById('home');
  const panel = document.getElementById('panel');
  modeButton?.addEventListener('click', () => {
    const next = lanterna.getMode() === 'light' ? 'pan' : 'light';
    lanterna.setMode(next);
    modeButton.textContent = next === 'light' ? 'Drag: light' : 'Drag: pan';
    modeButton.setAttribute('aria-pressed', String(next === 'light'));
  });
  homeButton?.addEventListener('click', () => { lanterna.viewer.viewport.goHome(); });
  const lensButton = document.getElementById('lens');
  const overlaysButton = document.getElementById('overlays');
  const syncButtons = (): void => {
    lensButton?.setAttribute('aria-pressed', String(lanterna.getLens().enabled));
    overlaysButton?.setAttribute('aria-pressed', String(lanterna.getOverlaysVisible()));
  };
  lensButton?.addEventListener('click', () => {
    attempt(() => lanterna.setLens({ enabled: !lanterna.getLens().enabled }));
  });
  overlaysButton?.addEventListener('click', () => {
    lanterna.setOverlaysVisible(!lanterna.getOverlaysVisible());
  });
  lanterna.onChange(syncButtons);
  lanterna.ready.then(() => {
    const text = lanterna.manifest?.label ?? '';
    if (label) {
      label.textContent = text;
      label.hidden = text === '';
    }
    document.title = text ? `${text} · Lanterna` : 'Lanterna viewer';
    if (mode !== null) {
      attempt(() => { lanterna.setRenderMode(mode as RenderMode); }); // RenderModeError for an unknown mode
    }
    if (panel) {
      createControls(lanterna, panel, report);
      createLensControls(lanterna, panel, report);
      panel.hidden = false;
    }
    if (overlaysButton) {
      overlaysButton.hidden = !lanterna.manifest?.layers.some((l) => l.overlays.length > 0);
    }
    syncButtons();
    // View tools (issue #13): the URL hash, Snapshot and ? buttons, scale bar, help overlay, canvas keys.
    mountViewTools(lanterna, { toolbar: document.getElementById('toolbar'), home: () => { homeButton?.click(); } });
  }, (error: unknown) => {
    lanterna.destroy();
    showFatal(error, manifest);
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
    open(manifest, params.get('layer') ?? undefined, params.get('mode'), Number.isFinite(side) ? side : undefined,
      Number.isFinite(ratio) && ratio > 0 ? ratio : null);
  }
}
