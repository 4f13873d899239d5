/**
 * Preset library files: export (download `presets.json`), import (a file chosen or dropped on the
 * page). An import that cannot be used changes nothing and throws an error naming the file and,
 * for a library that does not fit, the JSON path (`PresetError`).
 */
import type { LanternaViewer } from '../api/viewer-api';
import { LanternaError } from '../errors';
import { serializeLibrary } from '../presets/library';

/** A file that is not JSON. */
export class PresetFileError extends LanternaError {}

/** Download the viewer's library as `presets.json`. */
export function exportLibrary(lanterna: Pick<LanternaViewer, 'getPresetLibrary'>, name = 'presets.json'): void {
  const blob = new Blob([serializeLibrary(lanterna.getPresetLibrary())], { type: 'application/json' });
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.hidden = true;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => { URL.revokeObjectURL(url); }, 0);
}

/** Read `file` as a library and make it the viewer's; returns how many entries it has. */
export async function importLibrary(lanterna: Pick<LanternaViewer, 'setPresetLibrary'>, file: File): Promise<number> {
  const text = await file.text();
  let doc: unknown;
  try {
    doc = JSON.parse(text);
  } catch (error) {
    throw new PresetFileError(`${file.name}: not a JSON file (${error instanceof Error ? error.message : String(error)})`);
  }
  const library = lanterna.setPresetLibrary(doc, file.name);
  return library.base.length + library.lens.length;
}

/**
 * Accept `.json` files dropped anywhere on `target`: `onFile` gets the first one. Returns a function
 * that stops listening.
 */
export function acceptDroppedFiles(target: HTMLElement, onFile: (file: File) => void): () => void {
  const hasFiles = (e: DragEvent): boolean => [...(e.dataTransfer?.types ?? [])].includes('Files');
  const over = (e: DragEvent): void => {
    if (hasFiles(e)) {
      e.preventDefault();
      if (e.dataTransfer) {
        e.dataTransfer.dropEffect = 'copy';
      }
    }
  };
  const drop = (e: DragEvent): void => {
    const file = e.dataTransfer?.files[0];
    if (file) {
      e.preventDefault();
      onFile(file);
    }
  };
  target.addEventListener('dragover', over);
  target.addEventListener('drop', drop);
  return () => {
    target.removeEventListener('dragover', over);
    target.removeEventListener('drop', drop);
  };
}
