/**
 * The window's Lanterna controls and annotation following for Mirador 4 (docs/mirador.md): the
 * "Lanterna" companion window, the top-bar button that opens it, and Mirador's annotation panel
 * driving the Lanterna view.
 */
import type { MiradorPlugin } from '../types';
import { annotationFollowerPlugin } from './annotation-follower';
import { companionWindowPlugin } from './companion-window';
import { topBarButtonPlugin } from './top-bar-button';

export const uiPlugins: MiradorPlugin[] = [companionWindowPlugin, topBarButtonPlugin, annotationFollowerPlugin];

export { LANTERNA_CONTENT } from './companion-window';
