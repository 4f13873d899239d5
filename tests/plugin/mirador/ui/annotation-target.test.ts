import { describe, expect, it } from 'vitest';
import {
  annotationTarget, canvasSize, findAnnotation, parseXywh, targetRegion, toImageRegion,
} from '../../../../plugin/src/mirador/ui/annotation-target';

const CANVAS = 'http://h/ds/canvas/1';

/** An overlay level in the new encoding (contract §2): commenting, its drawing's bounding box. */
function overlayLevel(layer: string, level: number, xywh: string | null): Record<string, unknown> {
  return {
    id: `${CANVAS}/overlays/${layer}/level/${level}`, type: 'Annotation', motivation: 'commenting',
    target: xywh === null ? CANVAS
      : { type: 'SpecificResource', source: CANVAS, selector: { type: 'FragmentSelector', value: `xywh=${xywh}` } },
    body: [
      { id: `http://h/ds/iiif/ov_${layer}_${level}/full/max/0/default.png`, type: 'Image', width: 64, height: 32,
        service: [{ id: `http://h/ds/iiif/ov_${layer}_${level}`, type: 'ImageService3', profile: 'level0' },
          { type: 'LanternaOverlayLevel', layer, level }] },
      { type: 'TextualBody', value: 'Gilding', format: 'text/plain', purpose: 'commenting' },
    ],
  };
}

function patch(layer: string, xywh: string): Record<string, unknown> {
  return {
    id: `http://h/ds/annotations/${layer}/1_8_8_16_16_0_a.json`, type: 'Annotation',
    motivation: ['highlighting', 'commenting'],
    target: { type: 'SpecificResource', source: { id: CANVAS, type: 'Canvas' },
      selector: [{ type: 'FragmentSelector', conformsTo: 'http://www.w3.org/TR/media-frags/', value: `xywh=${xywh}` }] },
    body: [{ id: `http://h/ds/annotations/${layer}/1_8_8_16_16_0_a.png`, type: 'Image', width: 8, height: 8,
      service: [{ type: 'LanternaPatch', layer, level: 1, x: 8, y: 8, w: 16, h: 16, order: 0 }] }],
  };
}

describe('xywh media fragments', () => {
  it('reads pixel rectangles, with or without the pixel: prefix or a leading #', () => {
    expect(parseXywh('xywh=10,20,30,40')).toEqual([10, 20, 30, 40]);
    expect(parseXywh('#xywh=pixel:1,2,3,4')).toEqual([1, 2, 3, 4]);
  });

  it('scales percent: rectangles by the canvas, and needs it', () => {
    expect(parseXywh('xywh=percent:50,25,50,50', { width: 200, height: 400 })).toEqual([100, 100, 100, 200]);
    expect(parseXywh('xywh=percent:50,25,50,50')).toBeNull();
  });

  it('refuses malformed or empty rectangles', () => {
    for (const bad of ['xywh=1,2,3', 'xywh=1,2,3,x', 'xywh=1,2,0,4', 'xywh=,2,3,4', 't=10', '']) {
      expect(parseXywh(bad), bad).toBeNull();
    }
  });
});

describe('an annotation target region', () => {
  it('comes from a FragmentSelector, one or in a list', () => {
    expect(targetRegion(overlayLevel('vis', 0, '5,6,7,8'))).toEqual([5, 6, 7, 8]);
    expect(targetRegion(patch('vis', '8,8,16,16'))).toEqual([8, 8, 16, 16]);
  });

  it('comes from a canvas#xywh string target', () => {
    expect(targetRegion({ target: `${CANVAS}#xywh=1,1,2,2` })).toEqual([1, 1, 2, 2]);
  });

  it('is null for a whole-canvas target', () => {
    expect(targetRegion(overlayLevel('vis', 0, null))).toBeNull();
    expect(targetRegion({ target: { type: 'SpecificResource', source: CANVAS } })).toBeNull();
  });
});

describe('what an annotation is', () => {
  it('an overlay level: its layer and level from the LanternaOverlayLevel block', () => {
    expect(annotationTarget(overlayLevel('ir', 2, '0,0,10,10')))
      .toEqual({ kind: 'overlay', layer: 'ir', level: 2, region: [0, 0, 10, 10] });
  });

  it('a patch: its layer and image URL from the LanternaPatch body', () => {
    expect(annotationTarget(patch('vis', '8,8,16,16'))).toEqual({
      kind: 'patch', layer: 'vis', imageUrl: 'http://h/ds/annotations/vis/1_8_8_16_16_0_a.png', region: [8, 8, 16, 16],
    });
  });

  it('anything else with a region is a region; without one, nothing', () => {
    const note = { id: 'n', type: 'Annotation', motivation: 'commenting', target: `${CANVAS}#xywh=3,4,5,6`,
      body: { type: 'TextualBody', value: 'a note' } };
    expect(annotationTarget(note)).toEqual({ kind: 'region', region: [3, 4, 5, 6] });
    expect(annotationTarget({ ...note, target: CANVAS })).toBeNull();
    expect(annotationTarget('not an annotation')).toBeNull();
  });

  it('a block without a usable layer or level is not one of ours', () => {
    const bad = overlayLevel('vis', 0, '1,1,1,1');
    const [image] = bad.body as Record<string, unknown>[];
    (image?.service as Record<string, unknown>[])[1] = { type: 'LanternaOverlayLevel', layer: 'vis', level: -1 };
    expect(annotationTarget(bad)).toEqual({ kind: 'region', region: [1, 1, 1, 1] });
  });
});

describe('finding things in Mirador state', () => {
  it('finds an annotation by id across pages', () => {
    const pages = [{ type: 'AnnotationPage', items: [overlayLevel('vis', 0, null)] },
      { type: 'AnnotationPage', items: [patch('vis', '8,8,16,16')] }];
    expect(findAnnotation(pages, 'http://h/ds/annotations/vis/1_8_8_16_16_0_a.json')).toBe(pages[1]?.items[0]);
    expect(findAnnotation(pages, 'nope')).toBeNull();
    expect(findAnnotation([null, 'x'], 'nope')).toBeNull();
  });

  it('reads a canvas size from the manifest', () => {
    const manifest = { items: [{ id: 'c0', width: 5, height: 6 }, { id: CANVAS, width: 640, height: 480 }] };
    expect(canvasSize(manifest, CANVAS)).toEqual({ width: 640, height: 480 });
    expect(canvasSize(manifest, 'other')).toBeNull();
    expect(canvasSize({ items: [{ id: CANVAS, width: 0, height: 3 }] }, CANVAS)).toBeNull();
  });
});

describe('canvas regions in image pixels', () => {
  const image = { width: 200, height: 100 };

  it('scales by image / canvas and clips to the image', () => {
    expect(toImageRegion([10, 10, 20, 20], { width: 400, height: 200 }, image)).toEqual([5, 5, 10, 10]);
    expect(toImageRegion([-10, 90, 30, 30], null, image)).toEqual([0, 90, 20, 10]);
  });

  it('is the whole image for no region, and null off the image', () => {
    expect(toImageRegion(null, null, image)).toEqual([0, 0, 200, 100]);
    expect(toImageRegion([300, 0, 10, 10], null, image)).toBeNull();
  });
});
