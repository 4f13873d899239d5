/**
 * The panel's presets section (`docs/viewer.md`): the library's base and lens lists (a click applies
 * an entry; × removes it), "Save as preset" (a name, the list, and for the base whether the view is
 * kept), export and import of the library as JSON (file picker, or a file dropped on the page) and,
 * once the library has been edited and if the server allows it, saving the library into the dataset. Plain DOM over the viewer's API.
 */
import type { LanternaViewer } from '../api/viewer-api';
import { addPreset, type PresetLibrary, type PresetTarget } from '../presets/library';
import { createDatasetSave } from './dataset-save';
import { removeEntry } from './library-edits';
import { button, labelled, mountSection, namedSelect, type PanelSection, titledSection } from './panel-dom';
import { acceptDroppedFiles, exportLibrary, importLibrary } from './preset-files';

/** Options of {@link createPresetsPanel}. */
export interface PresetsPanelOptions {
  /** The manifest's absolute URL (where the authoring API is found). */
  readonly manifestUrl: string;
  /** Where files may be dropped. @default document.body */
  readonly dropTarget?: HTMLElement;
  /** Errors (a preset that cannot be applied, an import that cannot be used). */
  readonly onError: (error: unknown) => void;
}

const TARGET_TITLES: Readonly<Record<PresetTarget, string>> = { base: 'Base presets', lens: 'Lens presets' };

/** The list of one target's entries. */
function entryList(lanterna: LanternaViewer, library: PresetLibrary, target: PresetTarget,
  onError: (error: unknown) => void): HTMLElement {
  const list = document.createElement('ul');
  list.className = 'lanterna-preset-list';
  list.dataset.target = target;
  list.setAttribute('aria-label', TARGET_TITLES[target]);
  library[target].forEach((entry, index) => {
    const item = document.createElement('li');
    const preset = library.presets[entry.preset];
    const apply = button(`apply-${target}`, entry.label, preset
      ? `Apply: ${preset.layer} · ${preset.mode}${target === 'lens' ? ' in the lens' : ''}` : entry.label);
    apply.className = 'lanterna-preset-apply';
    apply.addEventListener('click', () => { lanterna.applyPreset(target, index).catch(onError); });
    const remove = button(`remove-${target}`, '×', `Remove "${entry.label}" from the ${target} list`);
    remove.className = 'lanterna-preset-remove';
    remove.setAttribute('aria-label', `Remove ${entry.label}`);
    remove.addEventListener('click', () => {
      try {
        lanterna.setPresetLibrary(removeEntry(lanterna.getPresetLibrary(), target, index), 'the edited library');
      } catch (error) {
        onError(error);
      }
    });
    item.append(apply, remove);
    list.appendChild(item);
  });
  if (library[target].length === 0) {
    const empty = document.createElement('li');
    empty.className = 'lanterna-preset-empty';
    empty.textContent = 'None yet';
    list.appendChild(empty);
  }
  return list;
}

/** The "Save as preset" form. */
function saveForm(lanterna: LanternaViewer, onError: (error: unknown) => void,
  status: (text: string, ok: boolean) => void): HTMLElement {
  const form = document.createElement('div');
  form.className = 'lanterna-preset-save';
  const name = document.createElement('input');
  Object.assign(name, { type: 'text', name: 'preset-name', placeholder: 'Preset name', maxLength: 80 });
  const target = namedSelect('preset-target', [new Option('Base list', 'base'), new Option('Lens list', 'lens')]);
  const withView = document.createElement('input');
  Object.assign(withView, { type: 'checkbox', name: 'preset-with-view', checked: true });
  const viewRow = document.createElement('label');
  viewRow.className = 'lanterna-check';
  viewRow.append(withView, ' Include the current view');
  const save = button('preset-save', 'Save as preset', 'Add the current base (or lens) settings to the library');
  const sync = (): void => {
    viewRow.hidden = target.value !== 'base';
  };
  target.addEventListener('change', sync);
  sync();
  const run = (): void => {
    const label = name.value.trim();
    if (!label) {
      name.focus();
      status('Name the preset first.', false);
      return;
    }
    try {
      const which = target.value as PresetTarget;
      const preset = lanterna.capturePreset(which, label, which === 'base' && withView.checked);
      const opacity = which === 'lens' ? lanterna.getLens().opacity : undefined;
      const { library } = addPreset(lanterna.getPresetLibrary(), preset, which, opacity);
      lanterna.setPresetLibrary(library, 'the new preset');
      name.value = '';
      status(`Saved "${label}" in the ${which} list.`, true);
    } catch (error) {
      onError(error);
    }
  };
  save.addEventListener('click', run);
  name.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') {
      e.preventDefault();
      run();
    }
  });
  form.append(labelled('Save as preset', name), labelled('In', target), viewRow, save);
  return form;
}

/** Build the presets section into `parent` for a ready viewer. */
export function createPresetsPanel(lanterna: LanternaViewer, parent: HTMLElement,
  options: PresetsPanelOptions): PanelSection {
  const { onError } = options;
  const section = titledSection('lanterna-presets', 'Presets');
  const lists = document.createElement('div');
  lists.className = 'lanterna-preset-lists';
  const statusLine = document.createElement('output');
  statusLine.className = 'lanterna-presets-status';
  statusLine.setAttribute('role', 'status');
  const status = (text: string, ok: boolean): void => {
    statusLine.textContent = text;
    statusLine.dataset.ok = String(ok);
  };
  const file = document.createElement('input');
  Object.assign(file, { type: 'file', name: 'presets-file', accept: '.json,application/json', hidden: true });
  const exportButton = button('presets-export', 'Export', 'Download the library as presets.json');
  const importButton = button('presets-import', 'Import…', 'Load a library from a JSON file (or drop one on the page)');
  const doImport = (f: File): void => {
    importLibrary(lanterna, f).then((n) => { status(`Imported ${f.name} (${n} entries).`, true); }, onError);
  };
  exportButton.addEventListener('click', () => { exportLibrary(lanterna); });
  importButton.addEventListener('click', () => { file.click(); });
  file.addEventListener('change', () => {
    const chosen = file.files?.[0];
    if (chosen) {
      doImport(chosen);
    }
    file.value = '';
  });
  const stopDrop = acceptDroppedFiles(options.dropTarget ?? document.body, doImport);
  const files = document.createElement('div');
  files.className = 'lanterna-button-row';
  files.append(exportButton, importButton, file);
  const dataset = createDatasetSave(lanterna, options.manifestUrl, status);
  section.append(lists, saveForm(lanterna, onError, status), files, dataset.element, statusLine);

  let shown: PresetLibrary | null = null;
  const initial = lanterna.getPresetLibrary();
  const refresh = (): void => {
    const library = lanterna.getPresetLibrary();
    if (library === shown) {
      return;
    }
    shown = library;
    if (library !== initial) {
      dataset.probe(); // something to save: may the server take it?
    }
    const parts: HTMLElement[] = [];
    for (const target of ['base', 'lens'] as const) {
      const title = document.createElement('h3');
      title.textContent = TARGET_TITLES[target];
      parts.push(title, entryList(lanterna, library, target, onError));
    }
    lists.replaceChildren(...parts);
  };
  const mounted = mountSection(lanterna, parent, section, refresh);
  return {
    element: section,
    destroy: () => {
      stopDrop();
      mounted.destroy();
    },
  };
}
