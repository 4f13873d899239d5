/**
 * The Annotate toolbox's controls: brush or eraser, colours, sizes, opacity, undo / redo / clear,
 * the texts (short, long HTML, for the level or this patch, comment or tag), the author (kept in
 * localStorage), the token row, Download, Upload, Cancel/Done and a one-line status. DOM only: what
 * the buttons do is wired by `annotator.ts`.
 */
import { createTokenRow, type TokenRow } from '../panel/authoring-token';
import { button } from '../panel/panel-dom';
import type { Brush } from './draw-surface';
import type { StrokeTool } from './stroke-history';

/** The brush colours offered. */
export const COLORS: readonly (readonly [string, string])[] = [
  ['#ff3b30', 'Red'], ['#ffd60a', 'Yellow'], ['#34c759', 'Green'], ['#0a84ff', 'Blue'], ['#ffffff', 'White'],
  ['#000000', 'Black'],
];
/** The brush sizes offered (drawing pixels), and the default. */
export const SIZES: readonly number[] = [2, 4, 8, 16, 32];
const DEFAULT_SIZE = 4;
/** Where the author's name is kept. */
export const AUTHOR_KEY = 'lanterna.annotationAuthor';

/** Where the texts go. */
export type TextsFor = 'patch' | 'level';

/** The texts of the form. */
export interface ToolboxTexts {
  readonly short: string;
  readonly long: string;
  readonly textsFor: TextsFor;
  readonly motivation: 'commenting' | 'tagging';
  readonly author: string;
}

/** The toolbox's elements and what they say. */
export interface Toolbox {
  readonly element: HTMLElement;
  readonly buttons: Readonly<Record<'undo' | 'redo' | 'clear' | 'download' | 'upload' | 'close', HTMLButtonElement>>;
  readonly token: TokenRow;
  brush(): Brush;
  texts(): ToolboxTexts;
  /** Show the patch being drawn (its level, rectangle and size). */
  setTitle(text: string): void;
  /** Show one line of status; `ok` false for an error. */
  setStatus(text: string, ok?: boolean): void;
  /** Empty the short and long texts (the next patch gets its own). */
  clearTexts(): void;
}

function row(...children: HTMLElement[]): HTMLElement {
  const div = document.createElement('div');
  div.className = 'lanterna-button-row';
  div.append(...children);
  return div;
}

function labelled(text: string, control: HTMLElement): HTMLLabelElement {
  const label = document.createElement('label');
  const span = document.createElement('span');
  span.textContent = text;
  label.append(span, control);
  return label;
}

function select(name: string, options: readonly (readonly [string, string])[]): HTMLSelectElement {
  const s = document.createElement('select');
  s.name = name;
  for (const [value, text] of options) {
    s.append(new Option(text, value));
  }
  return s;
}

function readAuthor(): string {
  try {
    return localStorage.getItem(AUTHOR_KEY) ?? '';
  } catch {
    return '';
  }
}

function keepAuthor(name: string): void {
  try {
    localStorage.setItem(AUTHOR_KEY, name);
  } catch {
    // storage off: asked again next time
  }
}

/** Build the toolbox (hidden); `sendToken(token)` is called when a token is entered. */
export function createToolbox(sendToken: (token: string) => void): Toolbox {
  const element = document.createElement('section');
  element.className = 'lanterna-annotate';
  element.setAttribute('aria-label', 'Annotate');
  element.hidden = true;
  const title = document.createElement('h2');
  title.className = 'lanterna-section-title';
  let tool: StrokeTool = 'brush';
  let color = COLORS[0]?.[0] ?? '#ff3b30';
  const brushButton = button('annotate-brush', 'Brush', 'Paint');
  const eraserButton = button('annotate-eraser', 'Eraser', 'Erase what is drawn');
  const swatches = COLORS.map(([value, name]) => {
    const b = button('annotate-color', '', name);
    b.value = value;
    b.className = 'lanterna-swatch';
    b.style.background = value;
    b.setAttribute('aria-label', name);
    return b;
  });
  const sync = (): void => {
    brushButton.setAttribute('aria-pressed', String(tool === 'brush'));
    eraserButton.setAttribute('aria-pressed', String(tool === 'eraser'));
    for (const s of swatches) {
      s.setAttribute('aria-pressed', String(tool === 'brush' && s.value === color));
    }
  };
  brushButton.addEventListener('click', () => { tool = 'brush'; sync(); });
  eraserButton.addEventListener('click', () => { tool = 'eraser'; sync(); });
  for (const s of swatches) {
    s.addEventListener('click', () => { color = s.value; tool = 'brush'; sync(); });
  }
  sync();
  const size = select('annotate-size', SIZES.map((n) => [String(n), `${n} px`]));
  size.value = String(DEFAULT_SIZE);
  const opacity = Object.assign(document.createElement('input'), {
    type: 'range', name: 'annotate-opacity', min: '5', max: '100', step: '5', value: '100',
  });
  const opacityOut = document.createElement('output');
  const showOpacity = (): void => { opacityOut.value = `${opacity.value} %`; };
  opacity.addEventListener('input', showOpacity);
  showOpacity();
  const buttons = {
    undo: button('annotate-undo', 'Undo', 'Undo (Ctrl+Z)'),
    redo: button('annotate-redo', 'Redo', 'Redo (Ctrl+Shift+Z or Ctrl+Y)'),
    clear: button('annotate-clear', 'Clear', 'Erase the whole drawing (Undo brings it back)'),
    download: button('annotate-download', 'Download', 'Save the patch as L_X_Y_W_H_O_INFO.png'),
    upload: button('annotate-upload', 'Upload', 'Send the patch to the server: the overlay is rebuilt with it'),
    close: button('annotate-close', 'Cancel', 'Stop annotating'),
  };
  const short = Object.assign(document.createElement('input'), {
    type: 'text', name: 'annotate-short', maxLength: 1000, placeholder: 'Short text',
  });
  const long = Object.assign(document.createElement('textarea'), {
    name: 'annotate-long', rows: 3, maxLength: 100000, placeholder: 'Long text (HTML: <p>, <b>, <a href>…)',
  });
  const textsFor = select('annotate-texts-for', [['patch', "This patch's note"], ['level', "The level's text"]]);
  const motivation = select('annotate-motivation', [['commenting', 'Comment'], ['tagging', 'Tag']]);
  const author = Object.assign(document.createElement('input'), {
    type: 'text', name: 'annotate-author', maxLength: 200, placeholder: 'Your name', value: readAuthor(),
  });
  author.addEventListener('input', () => { keepAuthor(author.value.trim()); });
  const texts = document.createElement('details');
  texts.className = 'lanterna-annotate-texts';
  const summary = document.createElement('summary');
  summary.textContent = 'Texts and author';
  texts.append(summary, labelled('Short text', short), labelled('Long text', long), labelled('For', textsFor),
    labelled('Kind', motivation), labelled('Author', author));
  const status = document.createElement('p');
  status.className = 'lanterna-annotate-status';
  status.setAttribute('role', 'status');
  const token = createTokenRow('annotate-send-token', 'Upload', sendToken);
  // The title and the status in a head that stays in sight when the toolbox scrolls (page CSS: sticky).
  const head = document.createElement('header');
  head.className = 'lanterna-annotate-head';
  head.append(title, status);
  element.append(head, row(brushButton, eraserButton), row(...swatches),
    row(labelled('Size', size), labelled('Opacity', opacity), opacityOut),
    row(buttons.undo, buttons.redo, buttons.clear), texts, token.element,
    row(buttons.download, buttons.upload, buttons.close));
  return {
    element, buttons, token,
    brush: () => ({ tool, color, size: Number(size.value), opacity: Number(opacity.value) / 100 }),
    texts: () => ({
      short: short.value.trim(), long: long.value.trim(), textsFor: textsFor.value === 'level' ? 'level' : 'patch',
      motivation: motivation.value === 'tagging' ? 'tagging' : 'commenting', author: author.value.trim(),
    }),
    setTitle: (text) => { title.textContent = text; },
    clearTexts() {
      short.value = '';
      long.value = '';
    },
    setStatus(text, ok = true) {
      status.textContent = text;
      status.dataset.ok = String(ok);
    },
  };
}
