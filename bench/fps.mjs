#!/usr/bin/env node
// Benchmark (not a test): frames per second of each layer type while the light moves every frame,
// against a plain image layer drawn by the same drawer over the same view, in headless Chromium;
// plus the requests and bytes to the first complete frame of each layer.
//
//   .venv/bin/python bench/make_datasets.py /tmp/lbench          # 4096×3072, every layer type
//   .venv/bin/lanterna serve /tmp/lbench --port 8766 &
//   node bench/fps.mjs --server http://127.0.0.1:8766 [--seconds 4] [--rounds 3] [--json out.json]
//
// Options: --dataset NAME (bench), --layers a,b,… (ptm_lrgb,ptm_rgb,hsh9,hsh16,svbrdf,rbf27,bilinear18,image),
// --reference ID (plain), --width/--height (1920×1080).
// --modes color,unsharpNormals,… : instead, each layer in each mode against the same layer in the
// first mode (interleaved), e.g. the unsharp modes against colour.
import { cpus, totalmem } from 'node:os';
import { writeFileSync } from 'node:fs';
import process from 'node:process';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const CHROMIUM = process.env.LANTERNA_CHROMIUM ?? '/usr/bin/chromium';
const ARGS = [
  '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--no-first-run', '--disable-quic',
  // measure rendering throughput, not the 60 Hz display clock
  '--disable-gpu-vsync', '--disable-frame-rate-limit',
];

const { values: opt } = parseArgs({
  options: {
    server: { type: 'string', default: 'http://127.0.0.1:8766' },
    dataset: { type: 'string', default: 'bench' },
    layers: { type: 'string', default: 'ptm_lrgb,ptm_rgb,hsh9,hsh16,svbrdf,rbf27,bilinear18,image' },
    reference: { type: 'string', default: 'plain' },
    seconds: { type: 'string', default: '4' },
    rounds: { type: 'string', default: '3' },
    width: { type: 'string', default: '1920' },
    height: { type: 'string', default: '1080' },
    json: { type: 'string' },
    modes: { type: 'string' },
  },
});
const layers = opt.layers.split(',').filter(Boolean);
const seconds = Number(opt.seconds);
const rounds = Number(opt.rounds);
const viewport = { width: Number(opt.width), height: Number(opt.height) };
const manifest = `${opt.server}/datasets/${opt.dataset}/manifest.json`;
const pageUrl = (layer) => `${opt.server}/viewer/?manifest=${manifest}&layer=${layer}`;

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
};

/** Open a page that fails loudly on page errors. */
async function openPage(browser) {
  const context = await browser.newContext({ viewport, deviceScaleFactor: 1 });
  const page = await context.newPage();
  page.on('pageerror', (err) => { throw new Error(`page error: ${err.message}`); });
  page.on('console', (msg) => {
    if (msg.type() === 'error') {
      process.stderr.write(`console error: ${msg.text()}\n`);
    }
  });
  return { context, page };
}

/** Requests, bytes and time from navigation to the first complete frame (home view), cold cache. */
async function firstFrame(browser, layer) {
  const { context, page } = await openPage(browser);
  const all = [];
  page.on('requestfinished', (request) => { all.push(request); });
  const t0 = Date.now();
  await page.goto(pageUrl(layer), { waitUntil: 'load' });
  await page.waitForFunction(() => window.lanterna !== undefined);
  await page.evaluate(async () => {
    await window.lanterna.ready;
    await window.lanterna.whenFullyLoaded();
  });
  const ms = Date.now() - t0;
  let requests = 0;
  let bytes = 0;
  let dataRequests = 0;
  let dataBytes = 0;
  for (const r of all) {
    const size = (await r.sizes()).responseBodySize;
    requests++;
    bytes += size;
    if (r.url().includes('/datasets/')) {
      dataRequests++;
      dataBytes += size;
    }
  }
  await context.close();
  return { requests, bytes, dataRequests, dataBytes, ms };
}

/** Frames drawn per second while the light moves every frame (view already fully loaded). */
async function measureFps(page, layer, durationMs, mode = 'color') {
  await page.evaluate(async ({ id, m }) => {
    await window.lanterna.setActiveLayer(id);
    window.lanterna.setRenderMode(m);
    await window.lanterna.whenFullyLoaded();
  }, { id: layer, m: mode });
  return page.evaluate((ms) => new Promise((resolve) => {
    const l = window.lanterna;
    const drawer = l.viewer.drawer;
    // Frames rendered: the drawer's own count where it has one (it skips draws with nothing new),
    // else the draw calls (older builds render on every draw).
    const counted = typeof drawer.getFrameCount === 'function';
    const start = counted ? drawer.getFrameCount() : 0;
    let calls = 0;
    const draw = drawer.draw.bind(drawer);
    drawer.draw = (items) => { calls++; draw(items); };
    let frame = 0;
    const t0 = performance.now();
    const tick = (now) => {
      frame++;
      const a = frame * 0.05;
      l.setLight(0.7 * Math.cos(a), 0.7 * Math.sin(a));
      if (now - t0 < ms) {
        requestAnimationFrame(tick);
      } else {
        const elapsed = (performance.now() - t0) / 1000;
        drawer.draw = draw;
        const draws = counted ? drawer.getFrameCount() - start : calls;
        resolve({ fps: draws / elapsed, rafFps: frame / elapsed });
      }
    };
    requestAnimationFrame(tick);
  }), durationMs);
}

async function main() {
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: ARGS, headless: true });
  try {
    if (opt.modes) {
      await modesRun(browser);
      return;
    }
    const all = [opt.reference, ...layers];
    const first = {};
    for (const layer of all) {
      first[layer] = await firstFrame(browser, layer);
      process.stderr.write(`first frame ${layer}: ${JSON.stringify(first[layer])}\n`);
    }
    const { page } = await openPage(browser);
    await page.goto(pageUrl(opt.reference), { waitUntil: 'load' });
    await page.waitForFunction(() => window.lanterna !== undefined);
    const renderer = await page.evaluate(async () => {
      await window.lanterna.ready;
      const gl = document.createElement('canvas').getContext('webgl2');
      const ext = gl.getExtension('WEBGL_debug_renderer_info');
      return ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    });
    // 1 image px = 1 screen px, centred: full-resolution tiles cover the whole canvas.
    await page.evaluate(({ w, h }) => {
      const l = window.lanterna;
      const layer = l.layer.layer;
      l.showImageRegion(Math.round((layer.width - w) / 2), Math.round((layer.height - h) / 2), w, h);
    }, { w: viewport.width, h: viewport.height });
    const fps = Object.fromEntries(all.map((l) => [l, []]));
    const ratios = Object.fromEntries(layers.map((l) => [l, []]));
    for (let round = 0; round < rounds; round++) {
      // interleave: reference, layer, reference, layer… (rotating the layer order each round)
      const order = layers.slice(round % layers.length).concat(layers.slice(0, round % layers.length));
      for (const layer of order) {
        const ref = await measureFps(page, opt.reference, seconds * 1000);
        const got = await measureFps(page, layer, seconds * 1000);
        fps[opt.reference].push(ref.fps);
        fps[layer].push(got.fps);
        ratios[layer].push(got.fps / ref.fps);
        process.stderr.write(`round ${round + 1} ${layer}: ${got.fps.toFixed(2)} fps vs ${opt.reference} `
          + `${ref.fps.toFixed(2)} fps → ${(got.fps / ref.fps).toFixed(3)}\n`);
      }
    }
    const result = {
      date: new Date().toISOString(),
      machine: { cpu: cpus()[0]?.model, cpus: cpus().length, memoryGiB: Math.round(totalmem() / 2 ** 30),
        browser: `Chromium ${browser.version()}`, renderer, viewport },
      settings: { dataset: opt.dataset, reference: opt.reference, seconds, rounds },
      layers: Object.fromEntries(all.map((l) => [l, {
        fpsMedian: median(fps[l]), fps: fps[l], ratioMedian: l === opt.reference ? 1 : median(ratios[l]),
        ratios: ratios[l] ?? [], firstFrame: first[l],
      }])),
    };
    process.stdout.write('| layer | fps (median) | relit / plain (median) | requests to first frame (data) | bytes (data) |\n');
    process.stdout.write('|---|---|---|---|---|\n');
    for (const l of all) {
      const r = result.layers[l];
      const f = r.firstFrame;
      process.stdout.write(`| ${l} | ${r.fpsMedian.toFixed(2)} | ${r.ratioMedian.toFixed(3)} | ${f.requests} (${f.dataRequests}) `
        + `| ${(f.bytes / 1e6).toFixed(2)} MB (${(f.dataBytes / 1e6).toFixed(2)} MB) |\n`);
    }
    process.stdout.write(`\n${JSON.stringify(result.machine)}\n`);
    if (opt.json) {
      writeFileSync(opt.json, `${JSON.stringify(result, null, 2)}\n`);
    }
  } finally {
    await browser.close();
  }
}

/** `--modes`: each layer in each mode against the same layer in the first mode, interleaved. */
async function modesRun(browser) {
  const [base, ...modes] = opt.modes.split(',').filter(Boolean);
  const { page } = await openPage(browser);
  await page.goto(pageUrl(layers[0]), { waitUntil: 'load' });
  await page.waitForFunction(() => window.lanterna !== undefined);
  await page.evaluate(async ({ w, h }) => {
    const l = window.lanterna;
    await l.ready;
    const layer = l.layer.layer;
    l.showImageRegion(Math.round((layer.width - w) / 2), Math.round((layer.height - h) / 2), w, h);
  }, { w: viewport.width, h: viewport.height });
  const rows = {};
  for (let round = 0; round < rounds; round++) {
    for (const layer of layers) {
      const order = modes.slice(round % modes.length).concat(modes.slice(0, round % modes.length));
      for (const mode of order) {
        const ref = await measureFps(page, layer, seconds * 1000, base);
        const got = await measureFps(page, layer, seconds * 1000, mode);
        const row = (rows[`${layer} ${mode}`] ??= { layer, mode, fps: [], baseFps: [], ratios: [] });
        row.fps.push(got.fps);
        row.baseFps.push(ref.fps);
        row.ratios.push(got.fps / ref.fps);
        process.stderr.write(`round ${round + 1} ${layer} ${mode}: ${got.fps.toFixed(2)} fps vs ${base} `
          + `${ref.fps.toFixed(2)} fps → ${(got.fps / ref.fps).toFixed(3)}\n`);
      }
    }
  }
  process.stdout.write(`| layer | mode | fps (median) | ${base} fps (median) | ratio (median) |\n|---|---|---|---|---|\n`);
  for (const r of Object.values(rows)) {
    process.stdout.write(`| ${r.layer} | ${r.mode} | ${median(r.fps).toFixed(2)} | ${median(r.baseFps).toFixed(2)} `
      + `| ${median(r.ratios).toFixed(3)} |\n`);
  }
  if (opt.json) {
    writeFileSync(opt.json, `${JSON.stringify({ date: new Date().toISOString(),
      settings: { dataset: opt.dataset, base, modes, seconds, rounds }, rows }, null, 2)}\n`);
  }
}

main().catch((error) => {
  process.stderr.write(`fps.mjs: ${error?.stack ?? String(error)}\n`);
  process.exitCode = 1;
});
