/**
 * The viewer page: `index.html?manifest=URL[&layer=ID][&mode=MODE]`. Exposes the viewer as
 * `window.lanterna`.
 */
import { createControls, createLensControls, createViewer, type LanternaViewer, type RenderMode } from '../index';

declare global {
  interface Window {
    lanterna?: LanternaViewer;
  }
}

function showError(error: unknown): void {
  const box = document.getElementById('error');
  if (box) {
    box.textContent = typeof error === 'string' ? error
      : error instanceof Error ? `${error.name}: ${error.message}` : String(error);
    box.hidden = false;
  }
}

const params = new URLSearchParams(window.location.search);
const manifest = params.get('manifest');
if (!manifest) {
  showError('No manifest given: open this page as …/viewer/?manifest=URL_OF_MANIFEST.json');
} else {
  const layer = params.get('layer') ?? undefined;
  const mode = params.get('mode');
  const lanterna = createViewer({ element: 'viewer', manifest: new URL(manifest, window.location.href).href, layer });
  window.lanterna = lanterna;
  const label = document.getElementById('label');
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
    lanterna.setLens({ enabled: !lanterna.getLens().enabled }).catch(showError);
  });
  overlaysButton?.addEventListener('click', () => {
    lanterna.setOverlaysVisible(!lanterna.getOverlaysVisible());
  });
  lanterna.onChange(syncButtons);
  lanterna.ready.then(() => {
    const text = lanterna.manifest?.label ?? '';
    if (label) {
      label.textContent = text;
    }
    document.title = text ? `${text} · Lanterna` : 'Lanterna viewer';
    if (mode !== null) {
      lanterna.setRenderMode(mode as RenderMode); // throws RenderModeError for an unknown mode
    }
    if (panel) {
      createControls(lanterna, panel, showError);
      createLensControls(lanterna, panel, showError);
      panel.hidden = false;
    }
    if (overlaysButton) {
      overlaysButton.hidden = !lanterna.manifest?.layers.some((l) => l.overlays.length > 0);
    }
    syncButtons();
  }).catch(showError);
}
