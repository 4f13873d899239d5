/**
 * Lanterna OpenSeadragon plugin: relightable IIIF images (PTM) on the web.
 *
 * @packageDocumentation
 */
export { createViewer, type CreateViewerOptions, type LanternaViewer } from './viewer';
export { RelightDrawer, RELIGHT_DRAWER_TYPE, WebGLUnavailableError, type PixelData } from './drawer/relight-drawer';
export { BundleTileSource, type BundleTileSourceOptions } from './tiles/bundle-tile-source';
export { BUNDLE_DATA_TYPE, registerBundleType, type PlaneBundle } from './tiles/bundle';
export { bundleKey } from './tiles/tile-key';
export { loadRelightManifest, fetchJson, type LoadedLayer } from './iiif/load';
export { parseManifest, findPaintingImage, labelText, type ManifestInfo } from './iiif/manifest';
export {
  parseRelightService, expectedChannels, RELIGHT_PROFILE, RELIGHT_SERVICE_TYPE,
  type RelightLayer, type PlaneGroup, type LayerType, type PtmColorspace,
} from './iiif/relight-service';
export { imageGeometry, commonGeometry, type ImageGeometry } from './iiif/image-info';
export {
  LanternaError, ManifestError, MissingRelightServiceError, RelightServiceError, ImageInfoError,
  MismatchedPlanesError, FetchError,
} from './iiif/errors';
export { ptmWeights, relightPtmPixel, BASES, PTM_BASIS_TERMS, type LightBasis } from './math/ptm-basis';
export {
  lightFromPointer, lightFromProjection, nudgeLight, OVERHEAD_LIGHT, type Light, type NudgeDirection,
} from './math/light';
export type { DragMode } from './ui/interaction';
