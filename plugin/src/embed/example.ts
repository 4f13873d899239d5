/**
 * The embedding example page (`embed.html?manifest=URL[&image=URL]`, docs/embedding.md): the page
 * makes its own plain OpenSeadragon 6 viewer (its navigation buttons, its navigator, its own image if
 * `image` is given) and then hands it to {@link attachLanterna} with the manifest. The "Relighting"
 * button destroys the Lanterna viewer (the page's viewer draws its own image again with a standard
 * drawer) and attaches a new one. Exposes the page's viewer as `window.hostViewer` and the current
 * Lanterna viewer as `window.lanterna` (undefined while detached).
 */
import OpenSeadragon from 'openseadragon';
import type { LanternaViewer } from '../api/viewer-api';
import { attachLanterna } from './attach';

declare global {
  interface ImportMeta {
    /** Vite's build-time glob import (here: the URLs of OpenSeadragon's button images). */
    glob(pattern: string, options: { eager: true; query: '?url'; import: 'default' }): Record<string, string>;
  }
  interface Window {
    lanterna?: LanternaViewer;
    /** The page's own OpenSeadragon viewer. */
    hostViewer?: OpenSeadragon.Viewer;
  }
}

const params = new URLSearchParams(window.location.search);
const manifest = params.get('manifest');
const image = params.get('image');
const status = document.getElementById('status');
const toggle = document.getElementById('toggle');

/** Show a line of text in the corner (what went wrong), or nothing. */
function say(text: string): void {
  if (status) {
    status.textContent = text;
    status.hidden = text === '';
  }
}

/** OpenSeadragon's button images (its npm package's), bundled with the page. */
const BUTTON_IMAGES = import.meta.glob('../../../node_modules/openseadragon/build/openseadragon/images/*.png',
  { eager: true, query: '?url', import: 'default' });

/** The `navImages` option for OpenSeadragon's buttons, by button and state, from {@link BUTTON_IMAGES}. */
function navImages(): Record<string, Record<string, string>> {
  const url = (name: string): string =>
    Object.entries(BUTTON_IMAGES).find(([path]) => path.endsWith(`/${name}.png`))?.[1] ?? '';
  const buttons: Record<string, string> = {
    zoomIn: 'zoomin', zoomOut: 'zoomout', home: 'home', fullpage: 'fullpage', rotateleft: 'rotateleft',
    rotateright: 'rotateright', flip: 'flip', previous: 'previous', next: 'next',
  };
  return Object.fromEntries(Object.entries(buttons).map(([button, file]) => [button, {
    REST: url(`${file}_rest`), GROUP: url(`${file}_grouphover`), HOVER: url(`${file}_hover`),
    DOWN: url(`${file}_pressed`),
  }]));
}

// A portal's viewer, as it would be made without Lanterna: OpenSeadragon's own controls and navigator.
const hostViewer = OpenSeadragon({
  id: 'osd',
  showNavigationControl: true,
  showNavigator: true,
  navigatorPosition: 'TOP_RIGHT',
  prefixUrl: '',
  navImages: navImages() as unknown as OpenSeadragon.NavImages,
  ...(image ? { tileSources: { type: 'image', url: image } } : {}),
});
window.hostViewer = hostViewer;

/** Attach a Lanterna viewer for the manifest to the page's viewer. */
function attach(url: string): void {
  say('');
  // A plain drag pans, as it did before Lanterna came: the light follows the light widget.
  const lanterna = attachLanterna(hostViewer, { manifest: url, mode: 'pan' });
  window.lanterna = lanterna;
  lanterna.ready.catch((error: unknown) => {
    if (window.lanterna === lanterna) { // not one destroyed since
      say(error instanceof Error ? error.message : String(error));
    }
  });
}

if (manifest && toggle) {
  attach(manifest);
  toggle.hidden = false;
  toggle.setAttribute('aria-pressed', 'true');
  toggle.addEventListener('click', () => {
    const on = window.lanterna !== undefined;
    if (on) {
      window.lanterna?.destroy();
      window.lanterna = undefined;
    } else {
      attach(manifest);
    }
    toggle.setAttribute('aria-pressed', String(!on));
  });
} else {
  say('Add ?manifest=URL of a Lanterna manifest to this page\'s address.');
}
