import { describe, expect, it } from 'vitest';
import { authoringUrls, layerUrls, saveErrorText, serverError } from '../../../plugin/src/panel/authoring-url';

describe('authoringUrls', () => {
  it('finds the API beside a served dataset manifest', () => {
    expect(authoringUrls('http://h:8000/datasets/demo/manifest.json')).toEqual({
      name: 'demo', api: 'http://h:8000/api/', presets: 'http://h:8000/api/datasets/demo/presets',
      dataset: 'http://h:8000/api/datasets/demo',
    });
    expect(authoringUrls('https://h/lanterna/datasets/a%20b/manifest.json?x=1')?.presets)
      .toBe('https://h/lanterna/api/datasets/a%20b/presets');
  });

  it('gives null for another manifest URL', () => {
    expect(authoringUrls('http://h/objects/demo/manifest.json')).toBeNull();
    expect(authoringUrls('http://h/datasets/demo/other.json')).toBeNull();
  });
});

describe('saveErrorText', () => {
  it('shows the server\'s one-line error, else what the status means', () => {
    expect(saveErrorText(400, '{"error": "presets.json: base[0].layer: no layer \'x\'"}'))
      .toBe('Not saved (400): presets.json: base[0].layer: no layer \'x\'');
    expect(saveErrorText(401, '')).toBe('Not saved (401): the token was not accepted');
    expect(saveErrorText(500, 'oops\nmore')).toBe('Not saved (500): HTTP 500');
  });
});

describe('layerUrls', () => {
  it('gives the annotation endpoints of a layer', () => {
    const urls = authoringUrls('http://h:8000/datasets/demo/manifest.json');
    expect(urls?.dataset).toBe('http://h:8000/api/datasets/demo');
    if (!urls) {
      return;
    }
    const layer = layerUrls(urls, 'ptm 1');
    expect(layer.patches).toBe('http://h:8000/api/datasets/demo/layers/ptm%201/patches');
    expect(layer.status).toBe('http://h:8000/api/datasets/demo/layers/ptm%201/status');
    expect(layer.level(2)).toBe('http://h:8000/api/datasets/demo/layers/ptm%201/levels/2');
    expect(layer.patch('2_0_0_8_8_0_patch')).toBe('http://h:8000/api/datasets/demo/layers/ptm%201/patches/2_0_0_8_8_0_patch');
  });
});

describe('serverError', () => {
  it('is the first line of the server\'s error, else empty', () => {
    expect(serverError('{"error": "image: not a PNG\\nmore"}')).toBe('image: not a PNG');
    expect(serverError('<html>')).toBe('');
    expect(serverError('{"ok": true}')).toBe('');
  });
});
