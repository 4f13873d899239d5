/**
 * The view tools' CSS (scale bar, help overlay, visible focus), added once to the document so that
 * every page that mounts the tools gets it.
 */

const CSS = `
.lanterna-tool:focus-visible, .lanterna-help-dialog:focus-visible { outline: 2px solid #ffd75e; outline-offset: 2px; }
.lanterna-scale-bar { position: absolute; bottom: 12px; z-index: 10; pointer-events: none;
  font: 12px system-ui, sans-serif; color: #fff; text-shadow: 0 0 3px #000, 0 0 2px #000; }
.lanterna-scale-bar[hidden] { display: none; }
.lanterna-scale-bar-label { display: block; margin-bottom: 2px; }
.lanterna-scale-bar-line { box-sizing: border-box; height: 8px; border: 2px solid #fff; border-top: 0;
  box-shadow: 0 1px 2px rgba(0, 0, 0, 0.8); }
.lanterna-help { position: fixed; inset: 0; z-index: 1000; display: flex; align-items: center;
  justify-content: center; background: rgba(0, 0, 0, 0.55); }
.lanterna-help[hidden] { display: none; }
.lanterna-help-dialog { box-sizing: border-box; width: min(560px, calc(100% - 24px)); max-height: calc(100% - 24px);
  overflow: auto; padding: 14px 18px; border-radius: 8px; border: 1px solid #555; background: #1c1c1c; color: #eee;
  font: 14px/1.4 system-ui, sans-serif; }
.lanterna-help-dialog h2 { margin: 0 0 8px; font-size: 17px; }
.lanterna-help-dialog h3 { margin: 12px 0 4px; font-size: 14px; color: #ffd75e; }
.lanterna-help-dialog dl { display: grid; grid-template-columns: minmax(9em, auto) 1fr; gap: 2px 12px; margin: 0; }
.lanterna-help-dialog dt { font-weight: 600; }
.lanterna-help-dialog dd { margin: 0; }
.lanterna-help-close { margin-top: 12px; font: inherit; padding: 6px 14px; border-radius: 4px; border: 1px solid #777;
  background: #222; color: #eee; cursor: pointer; }
`;

/** Add the stylesheet to `doc` once. */
export function addToolStyles(doc: Document = document): void {
  if (doc.getElementById('lanterna-tool-styles')) {
    return;
  }
  const style = doc.createElement('style');
  style.id = 'lanterna-tool-styles';
  style.textContent = CSS;
  doc.head.append(style);
}
