/** The window's Lanterna controls for Mirador (placeholder until the controls land). */
import type { MiradorPlugin } from '../types';

export const uiPlugins: MiradorPlugin[] = [];
