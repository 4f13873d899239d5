/**
 * Saving a snapshot as a file: `NAME_layer_mode.png`.
 */
import type { LanternaViewer } from '../api/viewer-api';

/** A file-name part: letters (accents dropped), digits, `-` and `.`, other runs as `_` (at most 60 characters). */
export function fileNamePart(text: string): string {
  return text.normalize('NFKD').replace(/\p{M}+/gu, '').replace(/[^\w.-]+/g, '_').replace(/^_+|_+$/g, '').slice(0, 60);
}

/** The snapshot's file name: `NAME_layer_mode.png` (NAME: `name`, else the dataset's label). */
export function snapshotFileName(lanterna: LanternaViewer, name?: string): string {
  const parts = [name ?? lanterna.manifest?.label ?? '', lanterna.getActiveLayer(), lanterna.getRenderMode()]
    .map(fileNamePart);
  return `${(parts[0] || 'lanterna')}_${parts.slice(1).join('_')}.png`;
}

/** Take a snapshot and save it (through a download link). */
export async function downloadSnapshot(lanterna: LanternaViewer, name?: string): Promise<void> {
  const blob = await lanterna.snapshot();
  const url = URL.createObjectURL(blob);
  const link = document.createElement('a');
  link.href = url;
  link.download = snapshotFileName(lanterna, name);
  link.hidden = true;
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => { URL.revokeObjectURL(url); }, 10_000);
}
