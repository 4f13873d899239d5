/** Shared test fixtures: a manifest and info.json shaped like the contract's examples. */
import { pcaChannelNames } from '../../plugin/src/iiif/pca-block';

const BASE = 'http://127.0.0.1:8000/datasets/ushabti';

export function relightBlock(): Record<string, unknown> {
  return {
    id: `${BASE}/layers/ptm.json`,
    type: 'LanternaRelight',
    profile: 'urn:lanterna:relight:1',
    layerType: 'ptm',
    colorspace: 'lrgb',
    basis: ['lu2', 'lv2', 'lulv', 'lu', 'lv', '1'],
    width: 512,
    height: 1024,
    planes: [
      { service: { id: `${BASE}/iiif/ptm_c0`, type: 'ImageService3', profile: 'level0' }, format: 'png',
        channels: ['L0', 'L1', 'L2'], scale: [2, 2, 2], bias: [0.627, 0.627, 0.627] },
      { service: { id: `${BASE}/iiif/ptm_c1`, type: 'ImageService3', profile: 'level0' }, format: 'png',
        channels: ['L3', 'L4', 'L5'], scale: [2, 2, 0], bias: [0.498, 0.498, 0] },
      { service: { id: `${BASE}/iiif/ptm_color`, type: 'ImageService3', profile: 'level0' }, format: 'png',
        channels: ['R', 'G', 'B'], scale: [1, 1, 1], bias: [0, 0, 0] },
    ],
  };
}

export function manifest(body?: unknown): Record<string, unknown> {
  const image = body ?? {
    id: `${BASE}/iiif/ptm_color/full/max/0/default.jpg`,
    type: 'Image',
    format: 'image/jpeg',
    service: [
      { id: `${BASE}/iiif/ptm_color`, type: 'ImageService3', profile: 'level0' },
      relightBlock(),
    ],
  };
  return {
    '@context': 'http://iiif.io/api/presentation/3/context.json',
    id: `${BASE}/manifest.json`,
    type: 'Manifest',
    label: { en: ['Ushabti'] },
    items: [{
      id: `${BASE}/canvas/1`,
      type: 'Canvas',
      width: 512,
      height: 1024,
      items: [{
        id: `${BASE}/canvas/1/page`,
        type: 'AnnotationPage',
        items: [{
          id: `${BASE}/canvas/1/page/anno`,
          type: 'Annotation',
          motivation: 'painting',
          target: `${BASE}/canvas/1`,
          body: image,
        }],
      }],
    }],
  };
}

export function info(overrides: Record<string, unknown> = {}): Record<string, unknown> {
  return {
    '@context': 'http://iiif.io/api/image/3/context.json',
    id: `${BASE}/iiif/ptm_c0`,
    type: 'ImageService3',
    protocol: 'http://iiif.io/api/image',
    profile: 'level0',
    width: 512,
    height: 1024,
    tiles: [{ width: 256, height: 256, scaleFactors: [1, 2, 4] }],
    preferredFormats: ['png'],
    ...overrides,
  };
}

/** One overlay level annotation shaped like docs/annotations.md ("Storage and manifest"). */
export function overlayAnnotation(layer: string, level: number, short: string, long: string): Record<string, unknown> {
  const w = Math.ceil(512 / 2 ** level);
  const h = Math.ceil(1024 / 2 ** level);
  return {
    id: `${BASE}/canvas/1/overlays/${layer}/${level}`,
    type: 'Annotation',
    motivation: 'supplementing',
    label: { en: [short] },
    target: {
      type: 'SpecificResource',
      source: `${BASE}/canvas/1`,
      selector: { type: 'FragmentSelector', conformsTo: 'http://www.w3.org/TR/media-frags/', value: 'xywh=0,0,512,1024' },
    },
    body: [
      {
        id: `${BASE}/iiif/${layer}_ov${level}/full/max/0/default.png`,
        type: 'Image',
        format: 'image/png',
        width: w,
        height: h,
        service: [
          { id: `${BASE}/iiif/${layer}_ov${level}`, type: 'ImageService3', profile: 'level0' },
          { id: `${BASE}/layers/${layer}.json#overlay-${level}`, type: 'LanternaOverlayLevel',
            profile: 'urn:lanterna:overlay:1', layer, level, short, long },
        ],
      },
      { type: 'TextualBody', format: 'text/html', purpose: 'describing', value: long },
    ],
  };
}

/** The fixture manifest with `canvas.annotations` set to `pages`. */
export function manifestWithAnnotations(pages: unknown[]): Record<string, unknown> {
  const m = manifest();
  const canvas = (m.items as Record<string, unknown>[])[0];
  if (canvas) {
    canvas.annotations = pages;
  }
  return m;
}

/** An overlay annotation page of `layer`. */
export function overlayPage(layer: string, items: unknown[]): Record<string, unknown> {
  return { id: `${BASE}/canvas/1/overlays/${layer}`, type: 'AnnotationPage', label: { en: [`Annotations: ${layer}`] }, items };
}

/** A valid PCA block: N planes, rbf over `d` lights or bilinear at resolution `res`. */
export function pcaBlock(layerType: 'rbf' | 'bilinear', n: number, extra: Record<string, unknown> = {},
  res = 3, d = 5): Record<string, unknown> {
  const dims = layerType === 'rbf' ? d : res * res;
  const lights = Array.from({ length: d }, (_, i) => {
    const phi = (2 * Math.PI * i) / d;
    return [0.5 * Math.cos(phi), 0.5 * Math.sin(phi), Math.sqrt(0.75)];
  }).flat();
  return {
    type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', id: 'http://h/layers/coin.json', layerType,
    colorspace: 'mrgb', nplanes: n, width: 8, height: 8,
    basis: Array.from({ length: (n + 1) * dims * 3 }, (_, i) => (i * 37) % 256),
    range: Array.from({ length: n }, (_, q) => 1 + q),
    ...(layerType === 'rbf' ? { lights, sigma: 0.125 } : { resolution: res }),
    planes: pcaChannelNames(n).map((channels, i) => ({
      service: { id: `http://h/p${i}` }, channels, scale: channels.map((c) => (c.startsWith('X') ? 0 : 2)),
      bias: channels.map(() => 0),
    })),
    ...extra,
  };
}
