/**
 * Sliders for the render parameters a mode uses on a layer, shared by the base and the lens sections:
 * rebuilt when the layer or mode changes, kept in line with the parameters otherwise.
 */
import type { ShadingClass, RenderMode } from '../render/modes';
import { PARAM_SPECS, relevantParams, type RenderParamName, type RenderParams } from '../render/params';
import { slider, type Slider } from './panel-dom';

/** What the sliders show: the layer's shading class, its mode and the parameters. */
export interface ParamView {
  readonly key: string;
  readonly mode: RenderMode;
  readonly shading: ShadingClass;
  readonly params: RenderParams;
}

/** The sliders' container and how to bring them in line with a view. */
export interface ParamSliders {
  readonly element: HTMLDivElement;
  refresh(view: ParamView): void;
}

/** The text of a parameter's value. */
export function formatParam(name: RenderParamName, value: number): string {
  return value.toFixed(PARAM_SPECS[name].step < 1 ? 2 : 0);
}

/**
 * Build the sliders; `prefix` names their inputs (`lens-` for the lens), `set` changes parameters.
 * A double-click on a slider sets its default.
 */
export function createParamSliders(prefix: string, set: (params: Partial<RenderParams>) => void): ParamSliders {
  const element = document.createElement('div');
  element.className = 'lanterna-sliders';
  const inputs = new Map<RenderParamName, Slider>();
  let shownKey = '';
  const build = (names: readonly RenderParamName[]): void => {
    element.replaceChildren();
    inputs.clear();
    for (const name of names) {
      const spec = PARAM_SPECS[name];
      const s = slider(spec.label, { name: `${prefix}${name}`, min: spec.min, max: spec.max, step: spec.step });
      s.input.addEventListener('input', () => { set({ [name]: Number(s.input.value) }); });
      s.input.addEventListener('dblclick', () => { set({ [name]: spec.default }); });
      s.row.title = `${name}: ${spec.min}–${spec.max}, default ${spec.default} (double-click to reset)`;
      element.appendChild(s.row);
      inputs.set(name, s);
    }
  };
  return {
    element,
    refresh(view) {
      const key = `${view.key}|${view.mode}|${view.shading}`;
      if (key !== shownKey) {
        shownKey = key;
        build(relevantParams(view.mode, view.shading));
      }
      for (const [name, { input, value }] of inputs) {
        input.value = String(view.params[name]);
        value.textContent = formatParam(name, view.params[name]);
      }
    },
  };
}
