/**
 * The `rbf` layer kind (contract `layerType: "rbf"`): Relight's Gaussian RBF interpolation of the
 * PCA basis sampled at the acquisition lights (`rbfWeights`: Relight's kernel, not OpenLIME 1.2.6's
 * adaptive one), drawn by the shared PCA program.
 */
import { pcaKind } from '../pca/pca-kind';

/** The row of `rbf` layers in `LAYER_KINDS`. */
export const RBF_KIND = pcaKind('rbf');
