/**
 * The panel's light section: the light's azimuth and elevation, and buttons for the overhead light
 * (the reset) and raking light from the four sides. One light for base and lens (seed paper §6.2.1).
 */
import type { LanternaViewer } from '../api/viewer-api';
import { formatLight, LIGHT_PRESETS } from './light-angles';
import { mountSection, type PanelSection, titledSection } from './panel-dom';

/** Build the light section into `parent`. */
export function createLightTools(lanterna: LanternaViewer, parent: HTMLElement): PanelSection {
  const section = titledSection('lanterna-light-tools', 'Light');
  const readout = document.createElement('output');
  readout.className = 'lanterna-light-readout';
  readout.setAttribute('aria-live', 'off');
  const buttons = document.createElement('div');
  buttons.className = 'lanterna-button-row';
  for (const preset of LIGHT_PRESETS) {
    const button = document.createElement('button');
    button.type = 'button';
    button.name = `light-${preset.id}`;
    button.textContent = preset.label;
    button.title = preset.title;
    button.setAttribute('aria-label', preset.title);
    button.addEventListener('click', () => { lanterna.setLight(preset.light[0], preset.light[1]); });
    buttons.appendChild(button);
  }
  section.append(readout, buttons);
  const refresh = (): void => {
    const { lu, lv } = lanterna.getLight();
    readout.textContent = formatLight(lu, lv);
  };
  return mountSection(lanterna, parent, section, refresh);
}
