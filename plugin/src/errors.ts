/**
 * The base class of the plugin's errors. Each folder declares its own subclasses (`iiif/errors.ts`,
 * `gl/compile.ts`, …) next to the code that throws them.
 */

/** Base class of every error the plugin raises on purpose. */
export class LanternaError extends Error {
  constructor(message: string, options?: ErrorOptions) {
    super(message, options);
    this.name = new.target.name;
  }
}
