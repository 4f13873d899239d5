import { describe, expect, it } from 'vitest';
import { checkLayers, decodeHash, encodeHash } from '../../../plugin/src/state/hash-codec';
import { DEFAULT_LENS_VIEW, roundState, sameState, type ViewState } from '../../../plugin/src/state/view-state';
import { DEFAULT_RENDER_PARAMS } from '../../../plugin/src/render/params';

const STATE: ViewState = {
  layer: 'ptm', mode: 'specular',
  params: { ...DEFAULT_RENDER_PARAMS, specKs: 0.8123456, gamma: 1.2 },
  light: [0.5123456, -0.3000004],
  overlays: false,
  view: [120.123456, 80.98765, 640.5, 480.375],
  rotation: 0,
  lens: {
    enabled: true, center: [400.55555, 300.44444], radius: 60.123456, layer: 'ir', mode: 'normals',
    params: { ...DEFAULT_RENDER_PARAMS, umGain: 2.5 }, opacity: 0.75, annotations: 'inside',
  },
};

describe('encodeHash', () => {
  it('writes a short readable hash, defaults left out', () => {
    expect(encodeHash(STATE)).toBe('#v=1&layer=ptm&mode=specular&light=0.512,-0.3&p=gamma:1.2,specKs:0.812'
      + '&view=120.12346,80.98765,640.5,480.375&ov=0&lens=400.55555,300.44444,60.12346&lensLayer=ir&lensMode=normals'
      + '&lensP=umGain:2.5&lensOpacity=0.75&lensAnn=inside');
    const plain: ViewState = { ...STATE, params: DEFAULT_RENDER_PARAMS, overlays: true, lens: DEFAULT_LENS_VIEW };
    expect(encodeHash(plain)).toBe('#v=1&layer=ptm&mode=specular&light=0.512,-0.3&view=120.12346,80.98765,640.5,480.375');
    // geometry keeps a step of 1/10⁷ of the view's width
    expect(encodeHash({ ...plain, view: [1 / 3, 2 / 3, 12.3456789123, 9] })).toContain('view=0.333333,0.666667,12.345679,9');
  });

  it('escapes layer ids', () => {
    const hash = encodeHash({ ...STATE, layer: 'a&b=c d' });
    expect(hash).toContain('layer=a%26b%3Dc%20d&');
    expect(decodeHash(hash).state?.layer).toBe('a&b=c d');
  });
});

describe('decodeHash', () => {
  it('reads back the rounded state exactly', () => {
    const rounded = roundState(STATE);
    const { state, problems } = decodeHash(encodeHash(STATE));
    expect(problems).toEqual([]);
    expect(state).toEqual(rounded);
    expect(sameState(state as ViewState, rounded, 0)).toBe(true);
  });

  it('round-trips many random states (rounding is idempotent)', () => {
    let seed = 7;
    const rand = (): number => ((seed = (seed * 16807) % 2147483647) / 2147483647);
    for (let i = 0; i < 200; i++) {
      const angle = rand() * 2 * Math.PI;
      const r = rand() ** 0.2; // many near the rim of the disk
      const w = 10 ** (1 + 3 * rand());
      const s: ViewState = {
        ...STATE,
        light: [r * Math.cos(angle), r * Math.sin(angle)],
        params: { ...DEFAULT_RENDER_PARAMS, specExponent: 1 + 149 * rand(), brightness: rand() - 0.5 },
        view: [rand() * 1000, rand() * 1000, w, w * 0.75],
        lens: { ...STATE.lens, center: [rand() * 1000, rand() * 1000], radius: rand() * w, opacity: rand() },
      };
      const once = roundState(s);
      expect(roundState(once)).toEqual(once);
      expect(once.light[0] ** 2 + once.light[1] ** 2).toBeLessThanOrEqual(1);
      expect(decodeHash(encodeHash(s)).state).toEqual(once);
      expect(encodeHash(once)).toBe(encodeHash(s));
    }
  });

  it('is not a view link without v, and rejects another version', () => {
    expect(decodeHash('')).toEqual({ state: null, problems: [] });
    expect(decodeHash('#section-2')).toEqual({ state: null, problems: [] });
    const other = decodeHash('#v=2&layer=ptm');
    expect(other.state).toBeNull();
    expect(other.problems).toEqual(['v: unknown link version "2" (this viewer reads 1)']);
  });

  it('skips garbage, naming each key, and keeps the rest', () => {
    const { state, problems } = decodeHash('#v=1&layer=ptm&mode=shiny&light=1,x&p=specKs:0.5,nope:1,gamma:&'
      + 'view=0,0,-5,10&lens=1,2&lensOpacity=3&lensAnn=below&zoom=4&ov=yes&rot=a&lensMode=normals');
    expect(problems).toEqual([
      'mode: no render mode "shiny"',
      'light: needs lu,lv, got "1,x"',
      'p: no render parameter "nope"',
      'p: gamma must be a number, got "gamma:"',
      'view: needs x,y,w,h with w and h > 0, got "0,0,-5,10"',
      'lens: needs x,y,radius with radius > 0, got "1,2"',
      'lensOpacity: needs a number 0–1, got "3"',
      'lensAnn: needs one of everywhere, inside, outside, got "below"',
      'zoom: unknown key',
      'ov: needs 0 or 1, got "yes"',
      'rot: needs degrees, got "a"',
    ]);
    expect(state).toMatchObject({ layer: 'ptm', params: { ...DEFAULT_RENDER_PARAMS, specKs: 0.5 }, overlays: true });
    expect(state?.mode).toBeUndefined();
    expect(state?.light).toBeUndefined();
    expect(state?.view).toBeUndefined();
    expect(state?.lens).toEqual({ ...DEFAULT_LENS_VIEW, mode: 'normals' });
  });

  it('never throws on arbitrary text', () => {
    for (const junk of ['#v=1&&&', '#v=1&=&=', '#v=1&p=', '#v=1&light=,', '#v=1&%zz', '#v=1&view=1e999,0,1,1',
      '#v=1&lens=NaN,1,1', '#v=1&p=:::', '#\u0000v=1']) {
      expect(() => decodeHash(junk)).not.toThrow();
    }
    expect(decodeHash('#v=1&view=1e999,0,1,1').state?.view).toBeUndefined();
  });

  it('clamps parameters to their ranges', () => {
    expect(decodeHash('#v=1&p=gamma:99').state?.params?.gamma).toBe(5);
  });
});

describe('checkLayers', () => {
  const layers = [{ id: 'ptm', modes: ['color', 'specular'] as const }, { id: 'img', modes: ['color'] as const }];
  it('drops a layer or mode the dataset cannot show', () => {
    const out = checkLayers({ layer: 'gone', mode: 'specular', lens: { layer: 'img', mode: 'specular' } }, layers, 'img');
    expect(out.problems).toEqual([
      'layer: no layer "gone" (layers: ptm, img)',
      'mode: specular does not apply to layer img (color)',
      'lensMode: specular does not apply to layer img (color)',
    ]);
    expect(out.state).toEqual({ lens: { layer: 'img' } });
  });
  it('keeps what applies', () => {
    const update = { layer: 'ptm', mode: 'specular' as const, lens: { layer: '', mode: 'specular' as const } };
    expect(checkLayers(update, layers, 'img')).toEqual({ state: update, problems: [] });
  });
});
