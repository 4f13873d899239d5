import { describe, expect, it } from 'vitest';
import { drawPlan, levelKey, levelRect, outlineRect, patchRect } from '../../../plugin/src/annotations/draw-plan';
import type { PatchAnnotation } from '../../../plugin/src/iiif/annotation-page';
import type { OverlayLevel } from '../../../plugin/src/iiif/overlays';

const W = 1000; // canvas width: 1 viewport unit
const H = 600;

function level(l: number, serviceId = `https://x/iiif/vis_ov${l}`): OverlayLevel {
  return { layer: 'vis', level: l, short: '', long: '', serviceId, width: Math.ceil(W / 2 ** l),
    height: Math.ceil(H / 2 ** l), embedded: null };
}

function patch(id: string, layer = 'vis'): PatchAnnotation {
  const [l, x, y, w, h, order] = id.split('_').map(Number) as [number, number, number, number, number, number];
  return { id, layer, level: l, x, y, w, h, order, short: '', long: '', motivation: 'commenting', author: '',
    created: '', modified: '2026-01-01T00:00:00Z', state: null, imageUrl: `https://x/annotations/${layer}/${id}.png`,
    width: w, height: h };
}

const LEVELS = [level(0), level(2)];
const PATCHES = ['0_10_10_50_50_1_b', '0_10_10_50_50_0_a', '0_30_30_50_50_1_c', '2_0_0_1000_600_0_all']
  .map((id) => patch(id));

describe('the draw plan', () => {
  it('draws the level pyramid while none of its patches is hidden', () => {
    const plan = drawPlan({ levels: LEVELS, patches: PATCHES, hidden: new Set(['2_0_0_1000_600_0_all']), level: 0,
      canvasWidth: W });
    expect(plan).toEqual([{ kind: 'level', key: levelKey(level(0)), level: level(0), order: 0,
      rect: { x: 0, y: 0, width: 1, height: 0.6 } }]);
  });

  it('draws nothing at a level without an overlay image, whatever is hidden', () => {
    expect(drawPlan({ levels: LEVELS, patches: PATCHES, hidden: new Set(), level: 1, canvasWidth: W })).toEqual([]);
    expect(drawPlan({ levels: [], patches: PATCHES, hidden: new Set(['0_10_10_50_50_0_a']), level: 0, canvasWidth: W }))
      .toEqual([]);
  });

  it('draws the visible patches of the level, in application order, once one is hidden', () => {
    const plan = drawPlan({ levels: LEVELS, patches: PATCHES, hidden: new Set(['0_10_10_50_50_1_b']), level: 0,
      canvasWidth: W });
    expect(plan.map((p) => (p.kind === 'patch' ? p.patch.id : p.kind))).toEqual(['0_10_10_50_50_0_a', '0_30_30_50_50_1_c']);
    // orders are the places in the level's whole application order: a hidden patch keeps its gap
    expect(plan.map((p) => p.order)).toEqual([1, 3]);
    expect(new Set(plan.map((p) => p.key)).size).toBe(2);
    expect(plan.map((p) => (p.kind === 'patch' ? p.size : null))).toEqual([{ width: 50, height: 50 },
      { width: 50, height: 50 }]);
    const level2 = drawPlan({ levels: LEVELS, patches: [patch('2_13_7_50_30_0_x'), patch('2_0_0_4_4_1_y')],
      hidden: new Set(['2_0_0_4_4_1_y']), level: 2, canvasWidth: W });
    expect(level2.map((p) => (p.kind === 'patch' ? p.size : null))).toEqual([{ width: 13, height: 9 }]);
    const all = drawPlan({ levels: LEVELS, patches: PATCHES, hidden: new Set(PATCHES.slice(0, 3).map((p) => p.id)),
      level: 0, canvasWidth: W });
    expect(all).toEqual([]);
  });

  it('clips a patch hanging over the level image to it, as the tiler does', () => {
    // level 2 of 1000 × 600 is 250 × 150 px; the patch covers level px [-2, 6) × [147, 152)
    const edge = patch('2_-8_588_32_20_0_edge');
    const [planned] = drawPlan({ levels: LEVELS, patches: [edge, patch('2_0_0_4_4_1_y')],
      hidden: new Set(['2_0_0_4_4_1_y']), level: 2, canvasWidth: W });
    expect(planned?.kind === 'patch' && planned.size).toEqual({ width: 8, height: 5 });
    expect(planned?.kind === 'patch' && planned.crop).toEqual({ x: 2, y: 0, width: 6, height: 3 });
    expect(planned?.rect).toEqual({ x: 0, y: 588 / W, width: 24 / W, height: 12 / W });
  });

  it('keeps a patch item key across hide sets, and changes it when the patch image changes', () => {
    const plan = (hidden: string[], patches = PATCHES) => drawPlan({ levels: LEVELS, patches, hidden: new Set(hidden),
      level: 0, canvasWidth: W });
    const [a1] = plan(['0_10_10_50_50_1_b']);
    const [a2] = plan(['0_30_30_50_50_1_c']);
    expect(a1?.key).toBe(a2?.key);
    const replaced = PATCHES.map((p) => (p.id === '0_10_10_50_50_0_a' ? { ...p, modified: '2026-02-02T00:00:00Z' } : p));
    expect(plan(['0_10_10_50_50_1_b'], replaced)[0]?.key).not.toBe(a1?.key);
  });

  it('gives a rebuilt level (a new image service) a new key', () => {
    expect(levelKey(level(0, 'https://x/iiif/vis_ov0_b2'))).not.toBe(levelKey(level(0)));
  });
});

describe('placements in viewport units', () => {
  it('puts a patch on its destination rectangle at its level, rounded outwards', () => {
    // level 2: x0 = floor(13/4) = 3, x1 = ceil(13+50)/4) = 16 → 4·[3, 16) canvas px
    expect(patchRect(patch('2_13_7_50_30_0'), W)).toEqual({ x: 12 / W, y: 4 / W, width: 52 / W, height: 36 / W });
    expect(patchRect(patch('0_13_7_50_30_0'), W)).toEqual({ x: 13 / W, y: 7 / W, width: 50 / W, height: 30 / W });
    // a patch over the top-left edge
    expect(patchRect(patch('1_-3_-1_10_4_0'), W)).toEqual({ x: -4 / W, y: -2 / W, width: 12 / W, height: 6 / W });
  });

  it('outlines the patch rectangle itself', () => {
    expect(outlineRect(patch('2_13_7_50_30_0'), W)).toEqual({ x: 13 / W, y: 7 / W, width: 50 / W, height: 30 / W });
  });

  it('makes level pixels 2^L canvas pixels wide, overhanging the canvas at odd sizes', () => {
    const l3 = level(3); // 125 × 75 px: 1000 × 600 canvas px
    expect(levelRect(l3, W)).toEqual({ x: 0, y: 0, width: 1, height: 0.6 });
    const odd = { ...level(3), width: Math.ceil(1001 / 8), height: Math.ceil(601 / 8) };
    expect(levelRect(odd, 1001)).toEqual({ x: 0, y: 0, width: 1008 / 1001, height: 608 / 1001 });
  });
});
