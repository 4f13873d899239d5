/**
 * The ready bundle `dist/mirador/lanterna-mirador.js`: Mirador 4 with React, the Lanterna plugins and
 * OpenSeadragon 6, as one classic script. It defines `window.Mirador` (all of Mirador's exports, as
 * `mirador.min.js` does) plus `Mirador.lanternaPlugins`, so that a page does
 * `Mirador.viewer({id, windows: [{manifestId}]}, Mirador.lanternaPlugins)` (docs/mirador.md), and
 * `Mirador.lanternaWindowViewer(windowId)`, a window's running Lanterna viewer (or null).
 */
import * as Mirador from 'mirador';
import { lanternaMiradorPlugins } from './index';
import { getWindowViewer, watchWindowViewer } from './registry';

const global = globalThis as unknown as { Mirador?: unknown };
global.Mirador = {
  ...Mirador,
  lanternaPlugins: lanternaMiradorPlugins,
  lanternaWindowViewer: getWindowViewer,
  lanternaWatchWindowViewer: watchWindowViewer,
};
