/**
 * "Save to dataset": offered when the server says `GET {server}/api/` → `{"authoring": true}` (asked
 * once the library has been edited, so that a visitor's page makes no request it does not need); asks
 * for the authoring token once (a password field; kept in sessionStorage only) and `PUT`s the library
 * to `{server}/api/datasets/{name}/presets` with `Authorization: Bearer …`.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { serializeLibrary } from '../presets/library';
import { allowsAuthoring, createTokenRow, storedToken, storeToken } from './authoring-token';
import { authoringUrls, saveErrorText } from './authoring-url';

/** The save control: its element (hidden when the server does not allow authoring). */
export interface DatasetSave {
  readonly element: HTMLElement;
  /**
   * Ask the server (once) whether it allows authoring and show the control if it does; the element's
   * `data-checked` is then "true".
   */
  probe(): void;
}

/**
 * Build the control for the dataset at `manifestUrl`; `status` shows what happened (one line).
 */
export function createDatasetSave(lanterna: Pick<LanternaViewer, 'getPresetLibrary'>, manifestUrl: string,
  status: (text: string, ok: boolean) => void): DatasetSave {
  const element = document.createElement('div');
  element.className = 'lanterna-dataset-save';
  element.hidden = true;
  const button = document.createElement('button');
  button.type = 'button';
  button.name = 'presets-save-dataset';
  button.textContent = 'Save to dataset';
  const urls = authoringUrls(manifestUrl);
  if (urls) {
    button.title = `Write this library into the dataset "${urls.name}" on the server`;
  }

  const save = async (key: string): Promise<void> => {
    if (!urls) {
      return;
    }
    button.disabled = true;
    try {
      const response = await fetch(urls.presets, {
        method: 'PUT', body: serializeLibrary(lanterna.getPresetLibrary()),
        headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${key}` },
      });
      const body = await response.text();
      if (response.ok) {
        storeToken(key);
        tokenRow.hide();
        let count = lanterna.getPresetLibrary().base.length + lanterna.getPresetLibrary().lens.length;
        try {
          const doc = JSON.parse(body) as { presets?: unknown };
          count = typeof doc.presets === 'number' ? doc.presets : count;
        } catch {
          // keep the local count
        }
        status(`Saved to the dataset "${urls.name}" (${count} presets).`, true);
        return;
      }
      if (response.status === 401) {
        storeToken(null);
        tokenRow.ask();
      }
      status(saveErrorText(response.status, body), false);
    } catch (error) {
      status(`Not saved: ${error instanceof Error ? error.message : String(error)}`, false);
    } finally {
      button.disabled = false;
    }
  };
  button.addEventListener('click', () => {
    const key = storedToken();
    if (key) {
      void save(key);
    } else {
      tokenRow.ask();
    }
  });
  const tokenRow = createTokenRow('presets-send-token', 'Save', (key) => { void save(key); });
  element.append(button, tokenRow.element);
  let probed = false;
  const probe = (): void => {
    if (probed) {
      return;
    }
    probed = true;
    const checked = urls ? allowsAuthoring(urls) : Promise.resolve(false);
    void checked.then((allowed) => {
      element.hidden = !allowed;
      element.dataset.checked = 'true';
    });
  };
  return { element, probe };
}
