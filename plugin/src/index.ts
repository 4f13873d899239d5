/**
 * Lanterna OpenSeadragon plugin: relightable IIIF images (PTM, HSH, shape and material, images) on the web.
 *
 * @packageDocumentation
 */
export { createViewer } from './viewer/viewer';
export { attachLanterna } from './embed/attach';
export {
  RenderModeError, UnknownLayerError, type AttachLanternaOptions, type CreateViewerOptions, type LanternaViewer,
  type LayerInfo,
} from './api/viewer-api';
export { RelightDrawer, RELIGHT_DRAWER_TYPE, WebGLUnavailableError, type PixelData } from './drawer/relight-drawer';
export { FloatTargetsUnavailableError } from './drawer/screen-filter';
export { BundleTileSource, type BundleTileSourceOptions } from './tiles/bundle-tile-source';
export { BUNDLE_DATA_TYPE, registerBundleType, type PlaneBundle } from './tiles/bundle';
export { bundleKey } from './tiles/tile-key';
export { loadRelightManifest, loadLayer, fetchJson, type LoadedLayer, type LoadedManifest } from './iiif/load';
export {
  parseManifest, findPaintingImage, findPaintingImages, labelText, idFromUrl, type ManifestInfo, type ManifestLayer,
} from './iiif/manifest';
export {
  parseRelightService, expectedChannels, svbrdfMapIndices, RELIGHT_PROFILE, RELIGHT_SERVICE_TYPE, SVBRDF_MAPS,
  type RelightLayer, type PlaneGroup, type LayerType, type PtmColorspace, type InputColorSpace,
} from './iiif/relight-service';
export { imageGeometry, commonGeometry, type ImageGeometry } from './iiif/image-info';
export { LanternaError, attempt } from './errors';
export {
  ManifestError, MissingRelightServiceError, RelightServiceError, ImageInfoError, MismatchedPlanesError, FetchError,
  OverlayError, AnnotationPageError,
} from './iiif/errors';
export { ShaderError } from './gl/compile';
export { ptmWeights, relightPtmPixel, BASES, PTM_BASIS_TERMS, type LightBasis } from './math/ptm-basis';
export { hshWeights } from './math/hsh-basis';
export {
  pcaPlaneWeights, pcaWeights, rbfWeights, bilinearWeights, MAX_PCA_PLANES, type PcaBasis, type PcaColorspace, type PcaType,
} from './math/pca-weights';
export {
  lightFromPointer, lightFromProjection, nudgeLight, OVERHEAD_LIGHT, type Light, type NudgeDirection,
  lightAngles, lightFromAngles, type LightAngles,
} from './math/light';
export { RENDER_MODES, MODE_LABELS, isRenderMode, type RenderMode, type ShadingClass } from './render/modes';
export { applicableModes, shadingClass } from './layers/layer-kinds';
export {
  DEFAULT_RENDER_PARAMS, PARAM_SPECS, mergeParams, relevantParams, type RenderParams, type RenderParamName,
} from './render/params';
export { createControls, type Controls } from './panel/controls';
export { createLensControls, type LensControls } from './panel/lens-controls';
export { createLightTools } from './panel/light-tools';
export { createPresetsPanel, type PresetsPanelOptions } from './panel/presets-panel';
export { createAbout } from './panel/about';
export {
  annotationMeta, annotationTitle, createAnnotationList, type AnnotationListViewer,
} from './panel/annotation-list';
export type { PanelSection } from './panel/panel-dom';
export { createHypertext, NO_ANNOTATION_TEXT, type HypertextWidget } from './panel/hypertext';
export { sanitizeHtml } from './ui/sanitize-html';
export type { DragMode } from './ui/interaction';
export { routeGesture, routeWheel, isLensAction, type GestureAction, type GestureStart } from './ui/gesture-routing';
export {
  ANNOTATION_DISPLAYS, LensOptionError, type AnnotationDisplay, type LensState, type LensUpdate,
} from './lens/lens-state';
export { lensHit, LENS_BORDER_PX, type Circle, type LensHit } from './math/lens';
export { currentLevel, homeLevelOf, screenLevelOf, type LevelView } from './math/levels';
export { parseOverlays, OVERLAY_SERVICE_TYPE, OVERLAY_PROFILE, type OverlayLevel } from './iiif/overlays';
export {
  parseAnnotationPage, referencedPages, applicationOrder, PATCH_SERVICE_TYPE, PATCH_PROFILE,
  type PatchAnnotation, type PatchRenderState,
} from './iiif/annotation-page';
export { AnnotationSet } from './annotations/annotation-set';
export {
  drawPlan, patchRect, outlineRect, levelRect, levelKey, type DrawPlanInput, type PlannedItem, type PlannedLevel,
  type PlannedPatch, type ViewportRect,
} from './annotations/draw-plan';
export type { OverlayState } from './overlay/overlay-controller';
export {
  PRESETS_PROFILE, PRESETS_TYPE, PresetError, addPreset, emptyLibrary, entryLayer, libraryLayers,
  presetId, serializeLibrary, type LensPresetEntry, type Preset, type PresetDataset, type PresetEntry,
  type PresetLibrary, type PresetTarget,
} from './presets/library';
export { parsePresetLibrary } from './presets/read-library';
export { PresetIndexError } from './viewer/preset-actions';
export { PHYSDIM_PROFILE, type LabelValue, type PhysicalScale, type PhysicalUnits } from './iiif/manifest';
export { createMeasurement, type MeasurementWidget } from './measure/measure-widget';
export { measureAt, imagePixelAt } from './measure/measure-at';
export {
  materialOf, plotOf, swatchOf, type Material, type Measurement, type MeasurementKind, type MeasurementPlot,
} from './measure/plot-of';
export { PlanePixels } from './measure/plane-pixels';
export { dequantise } from './measure/dequantise';
export { measurementCaption } from './measure/caption';
export { brdfSlice, sliceAngles, toneMapSlice, wardLobe, SLICE_SIZE } from './math/brdf-slice';
export { reflectanceDisk, diskLight, hshColor, ptmColor, DISK_SIZE } from './math/reflectance-disk';
export {
  DEFAULT_LENS_VIEW, roundState, sameState, type ImageRect, type LensViewState, type ViewState, type ViewStateUpdate,
} from './state/view-state';
export { decodeHash, encodeHash, checkLayers, HASH_VERSION, type DecodedHash } from './state/hash-codec';
export { crc32, encodePng, readChunks, readTexts, textChunk, PngError, type PngChunk } from './state/png';
export { chooseScaleBar, type ScaleBar } from './math/scale-bar';
export type { SnapshotOptions, ViewStateApi } from './api/view-state-api';
export { mountViewTools, type ViewTools, type ViewToolsOptions } from './tools/view-tools';
export { attachUrlState, type UrlStateOptions } from './tools/url-state';
export { createHelpOverlay, type HelpOverlay } from './tools/help-overlay';
export { createScaleBar, type ScaleBarWidget } from './tools/scale-bar';
export { createAnnotator, MAX_PIXELS, MAX_SIDE, type Annotator, type AnnotatorOptions } from './annotate/annotator';
export { patchFrame, destination, frameImageRect, type PatchFrame } from './annotate/patch-frame';
export { infoSlug, patchFileName, nextOrder } from './annotate/patch-name';
export { StrokeHistory, type Operation, type Stroke, type StrokePoint, type StrokeTool } from './annotate/stroke-history';
export { brushWidth } from './annotate/pen-width';
export { parseStatus, waitForBuild, type BuildStatus } from './annotate/build-status';
export { AuthoringRequestError, type PatchMeta } from './annotate/patch-upload';
