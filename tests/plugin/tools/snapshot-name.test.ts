import { describe, expect, it } from 'vitest';
import type { LanternaViewer } from '../../../plugin/src/api/viewer-api';
import { HELP_SECTIONS } from '../../../plugin/src/tools/help-content';
import { fileNamePart, snapshotFileName } from '../../../plugin/src/tools/snapshot-download';

/** Just what the file name reads of a viewer. */
function viewer(label: string, layer: string, mode: string): LanternaViewer {
  return {
    manifest: { label }, getActiveLayer: () => layer, getRenderMode: () => mode,
  } as unknown as LanternaViewer;
}

describe('snapshot file names', () => {
  it('are NAME_layer_mode.png with safe characters', () => {
    expect(snapshotFileName(viewer('Lens and overlays', 'base', 'specular'))).toBe('Lens_and_overlays_base_specular.png');
    expect(snapshotFileName(viewer('Tablette / n° 3: "Ur"', 'ir-1.5', 'color'))).toBe('Tablette_n_3_Ur_ir-1.5_color.png');
    expect(snapshotFileName(viewer('', 'ptm', 'normals'))).toBe('lanterna_ptm_normals.png');
    expect(snapshotFileName(viewer('ignored', 'ptm', 'color'), 'ushabti')).toBe('ushabti_ptm_color.png');
  });
  it('keep accented letters as their base letters and cut long names', () => {
    expect(fileNamePart('Égypte ancienne')).toBe('Egypte_ancienne');
    expect(fileNamePart('x'.repeat(100))).toHaveLength(60);
  });
});

describe('the help overlay', () => {
  it('lists every shortcut key and the OpenSeadragon keys', () => {
    const keys = HELP_SECTIONS.flatMap((s) => s.rows.map(([what]) => what));
    for (const key of ['L', 'A', 'H', 'S', '?', 'Esc', '← ↑ → ↓', 'Shift + ← ↑ → ↓', '0', 'F', 'W / D']) {
      expect(keys).toContain(key);
    }
    expect(HELP_SECTIONS.map((s) => s.title)).toEqual(expect.arrayContaining(['Mouse', 'Touch', 'Pen']));
  });
});
