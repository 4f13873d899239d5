/**
 * The stylesheet of the Lanterna companion window: our panel sections (plain DOM, `panel/`) laid out
 * for Mirador's light theme, scoped to `.lanterna-mirador-panel`. Added to the document once.
 */

const STYLE_ID = 'lanterna-mirador-panel-style';

const CSS = `
.lanterna-mirador-panel { display: flex; flex-direction: column; gap: 4px; padding: 8px 12px 12px;
  font: 13px/1.35 Roboto, Helvetica, Arial, sans-serif; color: rgba(0, 0, 0, 0.87); }
.lanterna-mirador-panel .lanterna-controls { display: flex; flex-direction: column; gap: 6px; margin: 0; min-width: 0; }
.lanterna-mirador-panel fieldset.lanterna-controls { border: 0; border-top: 1px solid rgba(0, 0, 0, 0.12);
  padding: 8px 0 0; margin: 8px 0 0; }
.lanterna-mirador-panel fieldset.lanterna-controls legend, .lanterna-mirador-panel .lanterna-section-title {
  font-size: 12px; font-weight: 500; text-transform: uppercase; letter-spacing: 0.04em; margin: 0 0 4px;
  padding: 0; color: rgba(0, 0, 0, 0.6); }
.lanterna-mirador-panel label { display: grid; grid-template-columns: 1fr auto; gap: 2px 8px; align-items: center; }
.lanterna-mirador-panel label > span { grid-column: 1 / -1; color: rgba(0, 0, 0, 0.6); font-size: 12px; }
.lanterna-mirador-panel select { grid-column: 1 / -1; width: 100%; }
.lanterna-mirador-panel input[type="range"] { width: 100%; margin: 0; }
.lanterna-mirador-panel output { font-variant-numeric: tabular-nums; min-width: 3.2em; text-align: right; }
.lanterna-mirador-panel .lanterna-sliders { display: flex; flex-direction: column; gap: 6px; }
.lanterna-mirador-panel .lanterna-sliders:empty { display: none; }
.lanterna-mirador-panel .lanterna-controls > button { align-self: flex-end; }
.lanterna-mirador-panel .lanterna-lens-controls:disabled { opacity: 0.5; }
.lanterna-mirador-panel .lanterna-button-row { display: flex; flex-wrap: wrap; gap: 4px; }
.lanterna-mirador-panel label.lanterna-check { display: flex; gap: 6px; align-items: center; }
.lanterna-mirador-panel .lanterna-preset-list { list-style: none; margin: 0; padding: 0; display: flex;
  flex-direction: column; gap: 4px; }
.lanterna-mirador-panel .lanterna-preset-list li { display: flex; gap: 4px; }
.lanterna-mirador-panel .lanterna-preset-apply { flex: 1; text-align: left; overflow: hidden; text-overflow: ellipsis;
  white-space: nowrap; }
.lanterna-mirador-panel .lanterna-preset-empty { color: rgba(0, 0, 0, 0.5); font-style: italic; }
.lanterna-mirador-panel .lanterna-preset-save { display: flex; flex-direction: column; gap: 6px; }
.lanterna-mirador-panel .lanterna-presets-status[data-ok="false"] { color: #b00020; }
.lanterna-mirador-panel [hidden] { display: none !important; }
.lanterna-mirador-panel .lanterna-section-title { border-top: 1px solid rgba(0, 0, 0, 0.12); padding-top: 8px;
  margin-top: 8px; }
`;

/** Add the stylesheet to `doc` unless it is there. */
export function ensurePanelStyle(doc: Document): void {
  if (doc.getElementById(STYLE_ID)) {
    return;
  }
  const style = doc.createElement('style');
  style.id = STYLE_ID;
  style.textContent = CSS;
  doc.head.appendChild(style);
}
