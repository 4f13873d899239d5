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

/**
 * Run `action` and hand any error it throws, or its promise rejects with, to `report` (the page's
 * controls use it so that a failed action becomes a notice, never an unhandled error).
 */
export function attempt(action: () => unknown, report: (error: unknown) => void): void {
  try {
    const result = action();
    if (result instanceof Promise) {
      result.catch(report);
    }
  } catch (error) {
    report(error);
  }
}
