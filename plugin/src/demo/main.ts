/**
 * The viewer page: `index.html?manifest=URL`. Exposes the viewer as `window.lanterna`.
 */
import { createViewer, type LanternaViewer } from '../index';

declare global {
  interface Window {
    lanterna?: LanternaViewer;
  }
}

function showError(message: string): void {
  const box = document.getElementById('error');
  if (box) {
    box.textContent = message;
    box.hidden = false;
  }
}

const params = new URLSearchParams(window.location.search);
const manifest = params.get('manifest');
if (!manifest) {
  showError('No manifest given: open this page as …/viewer/?manifest=URL_OF_MANIFEST.json');
} else {
  const lanterna = createViewer({ element: 'viewer', manifest: new URL(manifest, window.location.href).href });
  window.lanterna = lanterna;
  const label = document.getElementById('label');
  const modeButton = document.getElementById('mode');
  const homeButton = document.getElementById('home');
  modeButton?.addEventListener('click', () => {
    const next = lanterna.getMode() === 'light' ? 'pan' : 'light';
    lanterna.setMode(next);
    modeButton.textContent = next === 'light' ? 'Light' : 'Pan';
    modeButton.setAttribute('aria-pressed', String(next === 'light'));
  });
  homeButton?.addEventListener('click', () => { lanterna.viewer.viewport.goHome(); });
  lanterna.ready.then(() => {
    const text = lanterna.layer?.label ?? '';
    if (label) {
      label.textContent = text;
    }
    document.title = text ? `${text} · Lanterna` : 'Lanterna viewer';
  }, (error: unknown) => {
    showError(error instanceof Error ? `${error.name}: ${error.message}` : String(error));
  });
}
