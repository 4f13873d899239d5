/**
 * Where a viewer's preset library comes from (the `presets` option, else the manifest's service
 * block) and which layers it opens (the `layers` option). A library that cannot be read does not stop
 * the object from opening: the viewer starts with an empty library and shows the error as a notice.
 */
import { fetchJson } from '../iiif/load';
import type { ManifestInfo } from '../iiif/manifest';
import { applicableModes } from '../layers/layer-kinds';
import { emptyLibrary, libraryLayers, type PresetDataset, type PresetLibrary } from '../presets/library';
import { parsePresetLibrary } from '../presets/read-library';
import type { LayerInfo } from '../api/viewer-api';
import { UnknownLayerError } from '../api/viewer-api';

/** What the library checks need of a dataset: its layers (with the modes each supports) and size. */
export function presetDataset(manifest: ManifestInfo, layers?: readonly LayerInfo[]): PresetDataset {
  return {
    layers: layers ?? manifest.layers.map((l) => ({ id: l.id, modes: applicableModes(l.layer) })),
    width: manifest.layer.width,
    height: manifest.layer.height,
  };
}

/** The library read, or an empty one and why not. */
export interface OpenedLibrary {
  readonly library: PresetLibrary;
  readonly error: unknown;
}

/**
 * Read the library given as `option` (a URL, resolved against the manifest's, or a document), else the
 * manifest's own, checked against every layer of the manifest.
 */
export async function openPresetLibrary(manifest: ManifestInfo, option: string | object | undefined,
  manifestUrl: string, fetchInit?: RequestInit): Promise<OpenedLibrary> {
  try {
    let doc: unknown = option ?? manifest.presets;
    let source = option === undefined ? 'the manifest\'s presets' : 'the preset library';
    if (typeof option === 'string') {
      source = new URL(option, manifestUrl).href;
      doc = await fetchJson(source, fetchInit);
    }
    if (doc === null || doc === undefined) {
      return { library: emptyLibrary(), error: null };
    }
    return { library: parsePresetLibrary(doc, source, presetDataset(manifest)), error: null };
  } catch (error) {
    return { library: emptyLibrary(), error };
  }
}

/**
 * The manifest restricted to the `layers` option (ids in manifest order, or the layers the library's
 * entries use).
 *
 * @throws {@link UnknownLayerError} for an id the manifest does not have, or when nothing is left
 */
export function selectLayers(manifest: ManifestInfo, option: readonly string[] | 'presets' | undefined,
  library: PresetLibrary): ManifestInfo {
  if (option === undefined) {
    return manifest;
  }
  const wanted = option === 'presets' ? libraryLayers(library) : option;
  if (option === 'presets' && wanted.length === 0) {
    return manifest; // no presets: show the object as it is
  }
  for (const id of wanted) {
    if (!manifest.layers.some((l) => l.id === id)) {
      throw new UnknownLayerError(`no layer ${JSON.stringify(id)} in the manifest `
        + `(layers: ${manifest.layers.map((l) => l.id).join(', ')})`);
    }
  }
  const layers = manifest.layers.filter((l) => wanted.includes(l.id));
  const first = layers[0] ?? manifest.layers[0];
  return first ? { ...manifest, layers, imageId: first.imageId, layer: first.layer } : manifest;
}
