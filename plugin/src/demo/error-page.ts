/**
 * The viewer page's error message: what went wrong opening a dataset, the URL, and what to check.
 */
import {
  FetchError, ImageInfoError, ManifestError, MissingRelightServiceError, WebGLUnavailableError,
} from '../index';

/** The parts of the message. */
export interface ErrorMessage {
  readonly title: string;
  /** The problem (the error's own message: it names the failing URL). */
  readonly problem: string;
  /** What to check. */
  readonly hint: string;
}

/** A hint for a failed request. */
function fetchHint(error: FetchError): string {
  if (error.status === 0) {
    return error.message.startsWith('no answer')
      ? 'The server did not answer in time: check that it is running, or try again later.'
      : 'Check that the server is running and, if it is on another host, that it allows cross-origin '
        + 'requests (Access-Control-Allow-Origin).';
  }
  if (error.status === 404 || error.status === 410) {
    return 'There is no document at this URL: check the manifest parameter of the page.';
  }
  if (error.status >= 200 && error.status < 300) {
    return 'The URL does not point at a JSON document: check that it is the dataset\'s manifest.json.';
  }
  return 'The server answered with an error: try again later, or ask its administrator.';
}

/** What to tell the reader about an error that stopped the viewer from opening. */
export function describeOpenError(error: unknown): ErrorMessage {
  const title = 'Cannot open this dataset';
  if (!(error instanceof Error)) {
    return { title, problem: String(error), hint: '' };
  }
  const problem = error.message;
  let hint = 'See the browser console for details.';
  if (error instanceof FetchError) {
    hint = fetchHint(error);
  } else if (error instanceof MissingRelightServiceError) {
    hint = 'This is a IIIF manifest, but not a Lanterna one: its image has no LanternaRelight service.';
  } else if (error instanceof ManifestError) {
    hint = 'The manifest does not follow the Lanterna dataset format (docs/dataset-format.md).';
  } else if (error instanceof ImageInfoError) {
    hint = 'An image\'s info.json is not a usable IIIF Image API 3 document for this layer.';
  } else if (error instanceof WebGLUnavailableError) {
    hint = 'The viewer needs WebGL2, which this browser or device does not provide (or has turned off).';
  }
  return { title, problem, hint };
}

/** Fill the page's error box (`#error`) and show it. */
export function showErrorBox(box: HTMLElement, message: ErrorMessage, manifestUrl: string | null): void {
  const h = document.createElement('h2');
  h.textContent = message.title;
  const problem = document.createElement('p');
  problem.className = 'problem';
  problem.textContent = message.problem;
  const parts: HTMLElement[] = [h, problem];
  if (manifestUrl) {
    const where = document.createElement('p');
    where.className = 'url';
    where.append('Manifest: ');
    const code = document.createElement('code');
    code.textContent = manifestUrl;
    where.appendChild(code);
    parts.push(where);
  }
  if (message.hint) {
    const hint = document.createElement('p');
    hint.className = 'hint';
    hint.textContent = message.hint;
    parts.push(hint);
  }
  const again = document.createElement('button');
  again.type = 'button';
  again.textContent = 'Try again';
  again.addEventListener('click', () => { window.location.reload(); });
  parts.push(again);
  box.replaceChildren(...parts);
  box.setAttribute('role', 'alert');
  box.hidden = false;
}
