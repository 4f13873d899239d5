/**
 * `@lanterna/plugin/mirador`: the Lanterna plugins for Mirador 4. Pass them to `Mirador.viewer(config,
 * lanternaMiradorPlugins)` (docs/mirador.md).
 */
import type { MiradorPlugin } from './types';
import { uiPlugins } from './ui/index';
import { viewerPlugin } from './viewer-plugin';

export const lanternaMiradorPlugins: MiradorPlugin[] = [viewerPlugin, ...uiPlugins];

export { getWindowViewer, setWindowViewer, watchWindowViewer } from './registry';
export type * from './types';
