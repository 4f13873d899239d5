/**
 * The rebuild status of a layer's overlay (`GET …/status`, docs/serving.md) and waiting for a new
 * build: after an upload the page polls until the served build changes and the state is `done`.
 * Pure: the fetch and the sleep are given.
 */

/** What `GET …/layers/<layer>/status` returns. */
export interface BuildStatus {
  readonly layer: string;
  readonly state: 'done' | 'queued' | 'building';
  readonly build: number;
  readonly fingerprint: string | null;
  readonly patches: number;
  readonly error: string | null;
}

const STATES = ['done', 'queued', 'building'] as const;

function isState(v: unknown): v is BuildStatus['state'] {
  return STATES.includes(v as BuildStatus['state']);
}

/** Read a status document, or throw an `Error` saying what is wrong with it. */
export function parseStatus(doc: unknown): BuildStatus {
  if (typeof doc !== 'object' || doc === null) {
    throw new Error('the status is not a JSON object');
  }
  const d = doc as Record<string, unknown>;
  const served = (typeof d.served === 'object' && d.served !== null ? d.served : {}) as Record<string, unknown>;
  if (!isState(d.state) || typeof served.build !== 'number') {
    throw new Error('the status has no "state" (done, queued, building) or no "served.build"');
  }
  return {
    layer: typeof d.layer === 'string' ? d.layer : '', state: d.state, build: served.build,
    fingerprint: typeof served.fingerprint === 'string' ? served.fingerprint : null,
    patches: typeof d.patches === 'number' ? d.patches : 0, error: typeof d.error === 'string' ? d.error : null,
  };
}

/** Whether `status` shows a finished build other than `build`. */
export function isNewBuild(status: BuildStatus, build: number): boolean {
  return status.state === 'done' && status.build !== build;
}

/** How {@link waitForBuild} polls. */
export interface PollOptions {
  /** Read the status now. */
  readonly read: () => Promise<BuildStatus>;
  /** Wait between two reads. */
  readonly sleep: () => Promise<void>;
  /** Stop waiting (the page is closing): resolves with null. */
  readonly cancelled?: () => boolean;
  /** Called with each status read (the toolbox shows "queued", "building…"). */
  readonly onStatus?: (status: BuildStatus) => void;
}

/**
 * Poll until a build other than `build` is served and the rebuild is done; its status, or null if
 * cancelled. A rebuild that failed (`error`, state done, build unchanged) rejects with that error.
 */
export async function waitForBuild(build: number, options: PollOptions): Promise<BuildStatus | null> {
  for (;;) {
    if (options.cancelled?.()) {
      return null;
    }
    const status = await options.read();
    options.onStatus?.(status);
    if (isNewBuild(status, build)) {
      return status;
    }
    if (status.state === 'done' && status.error !== null) {
      throw new Error(`the overlay was not rebuilt: ${status.error}`);
    }
    await options.sleep();
  }
}

/**
 * What the status says once the new build is in the viewer. A patch shows at the zoom it was drawn
 * at unless the home level moved meanwhile (docs/annotations.md "Levels": every patch of a coarser
 * level removed): then the text says which way to zoom.
 */
export function shownText(id: string, build: number, level: number, shown: number): string {
  const where = shown === level ? 'is shown' : `is served; zoom ${shown < level ? 'out' : 'in'} to see level ${level}`;
  return `Uploaded ${id}: build ${build} of the overlay ${where}.`;
}
