/**
 * Error classes raised while reading a Lanterna manifest or its IIIF image services.
 */
import { LanternaError } from '../errors';

/** The manifest is not a usable IIIF Presentation 3 manifest (no canvas, no painting image...). */
export class ManifestError extends LanternaError {}

/** The painting image has no `LanternaRelight` service. */
export class MissingRelightServiceError extends ManifestError {}

/** The `LanternaRelight` service block breaks the contract (`docs/dataset-format.md`). */
export class RelightServiceError extends ManifestError {}

/** An IIIF `info.json` is malformed or disagrees with the relight service block. */
export class ImageInfoError extends LanternaError {}

/** The plane groups of one layer do not share width, height, tile size and scale factors. */
export class MismatchedPlanesError extends ImageInfoError {}

/** A network request failed (HTTP status or network error). */
export class FetchError extends LanternaError {
  /** The URL that failed. */
  readonly url: string;
  /** HTTP status, or 0 for a network error. */
  readonly status: number;
  constructor(url: string, status: number, message: string, options?: ErrorOptions) {
    super(message, options);
    this.url = url;
    this.status = status;
  }
}

/** A `LanternaOverlayLevel` annotation breaks the contract (`docs/annotations.md`). */
export class OverlayError extends ManifestError {}

/** A layer's annotation page (`docs/annotations.md`, "Individual annotations") breaks the contract. */
export class AnnotationPageError extends ManifestError {}
