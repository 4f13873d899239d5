import { describe, expect, it } from 'vitest';
import { DEFAULT_IDLE_SECONDS, PageOptionsError, readPageOptions, RETRY_SECONDS } from '../../../plugin/src/simple/page-options';

const PAGE = 'http://host/viewer/simple.html';

describe('readPageOptions', () => {
  it('resolves the manifest and presets URLs against the page', () => {
    const o = readPageOptions('?manifest=../datasets/obj/manifest.json&presets=/libs/a.json', PAGE);
    expect(o.manifest).toBe('http://host/datasets/obj/manifest.json');
    expect(o.presets).toBe('http://host/libs/a.json');
    expect(o.kiosk).toBe(false);
    expect(o.idleSeconds).toBe(0); // no idle reset outside a kiosk unless asked
  });

  it('gives a kiosk the default idle time, or the one asked for', () => {
    expect(readPageOptions('?manifest=m.json&kiosk=1', PAGE)).toMatchObject({ kiosk: true, idleSeconds: DEFAULT_IDLE_SECONDS });
    expect(readPageOptions('?manifest=m.json&kiosk=1&idle=45', PAGE).idleSeconds).toBe(45);
    expect(readPageOptions('?manifest=m.json&kiosk=1&idle=0', PAGE).idleSeconds).toBe(0);
    expect(readPageOptions('?manifest=m.json&kiosk=true&idle=-3', PAGE).idleSeconds).toBe(DEFAULT_IDLE_SECONDS);
    expect(readPageOptions('?manifest=m.json&kiosk=0', PAGE).kiosk).toBe(false);
    expect(readPageOptions('?manifest=m.json&idle=10', PAGE)).toMatchObject({ kiosk: false, idleSeconds: 10 });
  });

  it('leaves the library to the manifest when no presets URL is given', () => {
    expect(readPageOptions('?manifest=m.json&presets=', PAGE).presets).toBeUndefined();
  });

  it('reads the test knobs of the advanced page', () => {
    const o = readPageOptions('?manifest=m.json&minPixelRatio=0.75&wholeLevelMaxSide=0', PAGE);
    expect(o.minPixelRatio).toBe(0.75);
    expect(o.wholeLevelMaxSide).toBe(0);
    expect(readPageOptions('?manifest=m.json', PAGE)).toMatchObject({
      minPixelRatio: null, wholeLevelMaxSide: undefined, retrySeconds: RETRY_SECONDS,
    });
    expect(readPageOptions('?manifest=m.json&retry=2', PAGE).retrySeconds).toBe(2);
  });

  it('says what is missing', () => {
    expect(() => readPageOptions('?kiosk=1', PAGE)).toThrow(PageOptionsError);
    expect(() => readPageOptions('', PAGE)).toThrow(/no manifest given/);
    expect(() => readPageOptions('?manifest=http://[bad', PAGE)).toThrow(/manifest parameter is not a URL/);
  });
});
