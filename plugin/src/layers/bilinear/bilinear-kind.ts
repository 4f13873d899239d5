/**
 * The `bilinear` layer kind (contract `layerType: "bilinear"`): Relight's R × R octahedral grid of
 * PCA basis samples, the light's four grid neighbours interpolated (`bilinearWeights`), drawn by
 * the shared PCA program.
 */
import { pcaKind } from '../pca/pca-kind';

/** The row of `bilinear` layers in `LAYER_KINDS`. */
export const BILINEAR_KIND = pcaKind('bilinear');
