import { describe, expect, it } from 'vitest';
import { hoverPatch, selectionPlan, type ViewerFacts } from '../../../../plugin/src/mirador/ui/selection-plan';

const CANVAS = 'http://h/ds/canvas/1';
const PNG = 'http://h/ds/annotations/vis/1_8_8_16_16_0_a.png';

function fragment(xywh: string): Record<string, unknown> {
  return { type: 'SpecificResource', source: CANVAS, selector: { type: 'FragmentSelector', value: `xywh=${xywh}` } };
}

function overlayLevel(layer: string, xywh: string | null): Record<string, unknown> {
  return {
    id: `${CANVAS}/overlays/${layer}/level/0`, type: 'Annotation', motivation: 'commenting',
    target: xywh === null ? CANVAS : fragment(xywh),
    body: [{ id: 'ov.png', type: 'Image', service: [{ type: 'LanternaOverlayLevel', layer, level: 0 }] }],
  };
}

const PATCH = {
  id: 'http://h/ds/annotations/vis/1_8_8_16_16_0_a.json', type: 'Annotation', target: fragment('8,8,16,16'),
  body: [{ id: PNG, type: 'Image', service: [{ type: 'LanternaPatch', layer: 'vis', level: 1 }] }],
};

const FACTS: ViewerFacts = {
  layers: ['vis', 'ir'], activeLayer: 'vis', patches: [{ id: '1_8_8_16_16_0_a', imageUrl: PNG, layer: 'vis' }],
  image: { width: 256, height: 128 }, canvas: { width: 256, height: 128 },
};

describe('selecting an annotation in Mirador', () => {
  it('focuses a patch the viewer knows (its own rectangle and render state), overlays on', () => {
    expect(selectionPlan(PATCH, FACTS)).toEqual([{ step: 'focus', patch: '1_8_8_16_16_0_a' }, { step: 'overlays' }]);
  });

  it('fits the view to a patch the viewer does not know', () => {
    expect(selectionPlan(PATCH, { ...FACTS, patches: [] })).toEqual([{ step: 'region', region: [8, 8, 16, 16] }]);
  });

  it('shows an overlay level of the active layer at its region', () => {
    expect(selectionPlan(overlayLevel('vis', '10,20,30,40'), FACTS))
      .toEqual([{ step: 'overlays' }, { step: 'region', region: [10, 20, 30, 40] }]);
  });

  it('switches to the overlay level\'s layer first, and fits the whole image when it names no region', () => {
    expect(selectionPlan(overlayLevel('ir', null), FACTS))
      .toEqual([{ step: 'layer', layer: 'ir' }, { step: 'overlays' }, { step: 'region', region: [0, 0, 256, 128] }]);
  });

  it('only fits the region of an overlay level of a layer the viewer does not have', () => {
    expect(selectionPlan(overlayLevel('uv', '1,2,3,4'), FACTS)).toEqual([{ step: 'region', region: [1, 2, 3, 4] }]);
  });

  it('maps canvas pixels to image pixels when the canvas is another size', () => {
    expect(selectionPlan(overlayLevel('vis', '100,50,200,100'), { ...FACTS, canvas: { width: 512, height: 256 } }))
      .toEqual([{ step: 'overlays' }, { step: 'region', region: [50, 25, 100, 50] }]);
  });

  it('does nothing for a whole-canvas note, or a region off the image', () => {
    const note = { id: 'n', type: 'Annotation', target: CANVAS, body: { type: 'TextualBody', value: 'x' } };
    expect(selectionPlan(note, FACTS)).toEqual([]);
    expect(selectionPlan({ ...note, target: `${CANVAS}#xywh=999,999,5,5` }, FACTS)).toEqual([]);
  });

  it('outlines a known patch on hover, nothing else', () => {
    expect(hoverPatch(PATCH, FACTS)).toBe('1_8_8_16_16_0_a');
    expect(hoverPatch(overlayLevel('vis', '1,1,1,1'), FACTS)).toBeNull();
    expect(hoverPatch(PATCH, { patches: [] })).toBeNull();
  });
});
