/**
 * The simplified viewer page (docs/simple-viewer.md):
 * `simple.html?manifest=URL[&presets=URL][&kiosk=1][&idle=SECONDS]`. Opens only the layers the
 * preset library uses, shows its two menus and two toggles (and a fullscreen button), and exposes
 * the viewer as `window.lanterna`. `document.body.dataset.state` is `loading`, `ready` or
 * `unavailable`; `dataset.idleResets` counts the kiosk's returns to the start.
 */
import { createScaleBar, createViewer, type LanternaViewer } from '../index';
import { wireFullscreenButton } from './fullscreen';
import { createIdleTimer, type IdleTimer } from './idle-timer';
import { lockDownKiosk } from './kiosk';
import { bridgeNotices } from './notices-bridge';
import { readPageOptions, RETRY_SECONDS, type SimplePageOptions } from './page-options';
import { createPageNote } from './page-note';
import { startSimpleViewer, type SimpleElements } from './simple-viewer';
import { createUnavailableScreen } from './unavailable';

declare global {
  interface Window {
    lanterna?: LanternaViewer;
  }
}

/** An element of the page (simple.html has them all). */
function byId<T extends HTMLElement = HTMLElement>(id: string): T {
  const element = document.getElementById(id);
  if (!element) {
    throw new Error(`simple.html has no #${id}`);
  }
  return element as T;
}

const body = document.body;
const panel = byId('controls');
const note = createPageNote(byId('note'));
let screen = createUnavailableScreen(byId('unavailable'), RETRY_SECONDS);
const elements: SimpleElements = {
  baseMenu: byId('base-menu'), baseList: byId('base-list'), lensMenu: byId('lens-menu'), lensList: byId('lens-list'),
  lensToggle: byId<HTMLButtonElement>('lens-toggle'), measureToggle: byId<HTMLButtonElement>('measure-toggle'),
};

/** The object could not be opened: the calm screen, and another try later. */
function unavailable(error: unknown, options: SimplePageOptions | null): void {
  console.error('[lanterna]', error);
  panel.hidden = true;
  body.dataset.state = 'unavailable';
  screen.show(options?.kiosk ? null : error instanceof Error ? error.message : String(error), options !== null);
  if (options) {
    setTimeout(() => { void open(options); }, options.retrySeconds * 1000);
  }
}

let idle: IdleTimer | null = null;

/** Open the object and build the controls (again after a failure). */
async function open(options: SimplePageOptions): Promise<void> {
  body.dataset.state = 'loading';
  let lanterna: LanternaViewer;
  try {
    lanterna = createViewer({
      element: 'viewer', manifest: options.manifest, presets: options.presets, layers: 'presets',
      lightIndicator: false, hypertext: false, notices: false, wholeLevelMaxSide: options.wholeLevelMaxSide,
      ...(options.minPixelRatio === null ? {} : { osd: { minPixelRatio: options.minPixelRatio } }),
    });
  } catch (error) {
    unavailable(error, options); // e.g. no WebGL2
    return;
  }
  const unbridge = bridgeNotices(lanterna, note, options.kiosk);
  try {
    await lanterna.ready;
  } catch (error) {
    unbridge();
    lanterna.destroy();
    unavailable(error, options);
    return;
  }
  window.lanterna = lanterna;
  const label = lanterna.manifest?.label ?? '';
  byId('title').textContent = label;
  document.title = label ? `${label} · Lanterna` : 'Lanterna';
  screen.hide();
  panel.hidden = false;
  createScaleBar(lanterna); // shown when the canvas has a physical scale (a physdim service)
  const simple = await startSimpleViewer(lanterna, elements, note, options.kiosk);
  body.dataset.state = 'ready';
  idle?.destroy();
  idle = createIdleTimer({
    seconds: options.idleSeconds,
    target: window,
    onIdle: () => {
      void simple.reset().then(() => {
        note.clear();
        body.dataset.idleResets = String(Number(body.dataset.idleResets ?? 0) + 1);
      });
    },
  });
}

let options: SimplePageOptions | null = null;
try {
  options = readPageOptions(window.location.search, window.location.href);
} catch (error) {
  unavailable(error, null);
}
if (options) {
  screen = createUnavailableScreen(byId('unavailable'), options.retrySeconds);
  const fullscreen = byId<HTMLButtonElement>('fullscreen');
  if (options.kiosk) {
    lockDownKiosk(document); // fullscreen on the first gesture; no button to leave it
    fullscreen.hidden = true;
  } else {
    wireFullscreenButton(fullscreen, document);
  }
  void open(options);
}
