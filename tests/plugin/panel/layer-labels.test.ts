import { describe, expect, it } from 'vitest';
import { layerLabels } from '../../../plugin/src/panel/layer-labels';

describe('layerLabels', () => {
  it('shows the label alone when labels are distinct, the type and id in the tooltip', () => {
    const out = layerLabels([
      { id: 'ptm', label: 'Relief tablet (PTM LRGB)', layerType: 'ptm' },
      { id: 'band_ir', label: 'IR band', layerType: 'image' },
    ]);
    expect(out.map((o) => o.text)).toEqual(['Relief tablet (PTM LRGB)', 'IR band']);
    expect(out[1]?.title).toContain('image');
    expect(out[1]?.title).toContain('band_ir');
  });

  it('adds the type only where labels collide, and the id where label and type both collide', () => {
    const out = layerLabels([
      { id: 'a', label: 'Tablet', layerType: 'ptm' },
      { id: 'b', label: 'Tablet', layerType: 'hsh' },
      { id: 'c', label: 'Tablet', layerType: 'hsh' },
      { id: 'd', label: 'Other', layerType: 'hsh' },
    ]);
    expect(out.map((o) => o.text)).toEqual(['Tablet · ptm', 'Tablet · hsh (b)', 'Tablet · hsh (c)', 'Other']);
    expect(new Set(out.map((o) => o.text)).size).toBe(4);
  });
});
