/**
 * The authoring token of the browser tab (sessionStorage `lanterna.authoringToken`, asked once with a
 * password field) and the server's answer to "may I write?" (`GET {server}/api/` →
 * `{"authoring": true}`); shared by the presets' "Save to dataset" and the Annotate toolbox.
 */
import type { AuthoringUrls } from './authoring-url';

/** Where the token is kept for the browser tab's session. */
export const TOKEN_KEY = 'lanterna.authoringToken';

/** The token kept for this tab, or ''. */
export function storedToken(): string {
  try {
    return sessionStorage.getItem(TOKEN_KEY) ?? '';
  } catch {
    return '';
  }
}

/** Keep `token` for this tab (null: forget it, e.g. after a 401). */
export function storeToken(token: string | null): void {
  try {
    if (token === null) {
      sessionStorage.removeItem(TOKEN_KEY);
    } else {
      sessionStorage.setItem(TOKEN_KEY, token);
    }
  } catch {
    // storage off: the token is asked each time
  }
}

/** The answers so far, by API URL: the page asks once, whoever asks first. */
const answers = new Map<string, Promise<boolean>>();

/**
 * Whether the server at `urls` accepts writes (false for a static host, which has no API); asked
 * once per page (the presets' save and the Annotate button share the answer).
 */
export function allowsAuthoring(urls: AuthoringUrls): Promise<boolean> {
  let answer = answers.get(urls.api);
  if (!answer) {
    answer = askServer(urls.api);
    answers.set(urls.api, answer);
  }
  return answer;
}

async function askServer(api: string): Promise<boolean> {
  try {
    const response = await fetch(api, { headers: { Accept: 'application/json' } });
    if (!response.ok) {
      return false;
    }
    const doc: unknown = await response.json();
    return typeof doc === 'object' && doc !== null && 'authoring' in doc && doc.authoring === true;
  } catch {
    return false;
  }
}

/** A password field and its send button, shown when a token is needed. */
export interface TokenRow {
  readonly element: HTMLElement;
  readonly input: HTMLInputElement;
  /** Show the row (empty, focused). */
  ask(): void;
  hide(): void;
}

/**
 * The token row: a password field (`name="authoring-token"`) and a button named `sendName` labelled
 * `sendLabel`; `send(token)` is called on the button or Enter.
 */
export function createTokenRow(sendName: string, sendLabel: string, send: (token: string) => void): TokenRow {
  const element = document.createElement('div');
  element.className = 'lanterna-token-row';
  element.hidden = true;
  const input = document.createElement('input');
  Object.assign(input, { type: 'password', name: 'authoring-token', autocomplete: 'off', placeholder: 'Authoring token' });
  input.setAttribute('aria-label', 'Authoring token');
  const button = document.createElement('button');
  button.type = 'button';
  button.name = sendName;
  button.textContent = sendLabel;
  element.append(input, button);
  const go = (): void => {
    if (input.value) {
      send(input.value);
    }
  };
  button.addEventListener('click', go);
  input.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') {
      e.preventDefault();
      go();
    }
  });
  return {
    element, input,
    ask() {
      element.hidden = false;
      input.value = '';
      input.focus();
    },
    hide() {
      element.hidden = true;
    },
  };
}
