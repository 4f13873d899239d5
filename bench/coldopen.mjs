#!/usr/bin/env node
// Benchmark (not a test): opening an object cold. For each layer of each dataset (every layer type
// of one object and a plain JPEG image layer of the same object), in headless Chromium at 1920×1080
// with a fresh browser (new temporary profile: empty HTTP, code and GPU caches) per run:
// the time from navigation start to the first complete frame (the viewer API's whenFullyLoaded()
// resolved), the requests and bytes it took, and the time from the last response to that frame;
// plus a layer switch A→B→A and the requests of the switch back. Runs are interleaved (the order
// rotates every round) and medians are reported.
//
//   .venv/bin/python bench/make_coldopen.py /tmp/lcold            # sources, then lanterna import
//   .venv/bin/lanterna serve /tmp/lcold --port 8767 &
//   node bench/coldopen.mjs --server http://127.0.0.1:8767 [--rounds 3] [--json out.json]
//
// Options: --datasets a,b (every dataset of sources.json), --layers a,b (every layer),
// --switch A,B (ptm_lrgb,hsh16 of the first dataset; "" for none), --warmup N (1 unrecorded round),
// --timeout S (180 per open), --width/--height (1920×1080).
import { execFileSync } from 'node:child_process';
import { cpus, loadavg, totalmem } from 'node:os';
import { writeFileSync } from 'node:fs';
import { dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import process from 'node:process';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const CHROMIUM = process.env.LANTERNA_CHROMIUM ?? '/usr/bin/chromium';
const ARGS = [
  '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--no-first-run', '--disable-quic',
];
const HERE = dirname(fileURLToPath(import.meta.url));
const SETTLE_MS = 300; // after a step: let the network events of its last requests arrive

const { values: opt } = parseArgs({
  options: {
    server: { type: 'string', default: 'http://127.0.0.1:8767' },
    sources: { type: 'string', default: 'coldopen-sources' },
    datasets: { type: 'string', default: '' },
    layers: { type: 'string', default: '' },
    switch: { type: 'string', default: 'ptm_lrgb,hsh16' },
    rounds: { type: 'string', default: '3' },
    warmup: { type: 'string', default: '1' },
    timeout: { type: 'string', default: '180' },
    width: { type: 'string', default: '1920' },
    height: { type: 'string', default: '1080' },
    json: { type: 'string' },
  },
});
const rounds = Number(opt.rounds);
const warmup = Number(opt.warmup);
const timeoutMs = Number(opt.timeout) * 1000;
const viewport = { width: Number(opt.width), height: Number(opt.height) };
const server = opt.server.replace(/\/$/, '');
const manifestUrl = (dataset) => `${server}/datasets/${dataset}/manifest.json`;
const pageUrl = (dataset, layer) => `${server}/viewer/?manifest=${manifestUrl(dataset)}&layer=${layer}`;

const median = (xs) => {
  const s = xs.filter((x) => Number.isFinite(x)).sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length === 0 ? NaN : s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
};
const list = (text) => text.split(',').map((s) => s.trim()).filter(Boolean);

class BenchError extends Error {}

/** GET a URL of the server, or fail with a one-line message saying what to do. */
async function fetchOrExplain(url, missing) {
  let response;
  try {
    response = await fetch(url);
  } catch (error) {
    throw new BenchError(`no server at ${server} (${error.cause?.code ?? error.message}): start it with `
      + '`.venv/bin/lanterna serve ROOT --port PORT` and pass --server');
  }
  if (!response.ok) {
    throw new BenchError(`${url}: HTTP ${response.status}: ${missing}`);
  }
  return response;
}

/** The datasets, their layers and their source bytes (sources.json of make_coldopen.py), checked. */
async function loadPlan() {
  const url = `${server}/datasets/${opt.sources}/sources.json`;
  const table = await (await fetchOrExplain(url, 'make the datasets with '
    + '`.venv/bin/python bench/make_coldopen.py ROOT` (ROOT = the served folder)')).json();
  const names = opt.datasets ? list(opt.datasets) : Object.keys(table.datasets);
  const only = list(opt.layers);
  const plan = [];
  for (const name of names) {
    const ds = table.datasets[name];
    if (!ds) {
      throw new BenchError(`dataset ${name} is not in ${url} (it has ${Object.keys(table.datasets).join(', ')})`);
    }
    const manifest = await (await fetchOrExplain(manifestUrl(name), `dataset ${name} is missing: `
      + 'make it with bench/make_coldopen.py')).json();
    const served = JSON.stringify(manifest);
    const layers = Object.keys(ds.layers).filter((l) => only.length === 0 || only.includes(l) || l === ds.reference);
    for (const layer of layers) {
      if (!served.includes(`/layers/${layer}.json`)) {
        throw new BenchError(`${manifestUrl(name)}: no layer ${layer}; re-make the datasets`);
      }
    }
    plan.push({ dataset: name, reference: ds.reference, layers, sources: ds.layers, size: [ds.width, ds.height] });
  }
  await fetchOrExplain(`${server}/viewer/`, 'the viewer is not built (npm run build)');
  return { table, plan };
}

/** In the page, before any script: time whenFullyLoaded() from navigation start (the time origin). */
function timingHook() {
  performance.setResourceTimingBufferSize(1e6);
  let viewer;
  Object.defineProperty(window, 'lanterna', {
    configurable: true,
    get: () => viewer,
    set: (v) => {
      viewer = v;
      window.__coldopen = { state: 'opening' };
      v.ready.then(() => {
        window.__coldopen.readyMs = performance.now();
        return v.whenFullyLoaded();
      }).then(() => {
        window.__coldopen = { ...window.__coldopen, state: 'done', doneMs: performance.now() };
      }, (error) => {
        window.__coldopen = { state: 'error', error: String(error?.message ?? error) };
      });
    },
  });
}

/** A fresh browser (its own temporary profile) with one 1920×1080 page recording its network. */
async function launch() {
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: ARGS, headless: true });
  current = browser;
  const context = await browser.newContext({ viewport, deviceScaleFactor: 1 });
  await context.addInitScript(timingHook);
  const page = await context.newPage();
  const net = { requests: [], finished: new Set(), failed: [], errors: [] };
  page.on('request', (r) => { net.requests.push(r); });
  page.on('requestfinished', (r) => { net.finished.add(r); });
  page.on('requestfailed', (r) => { net.failed.push(`${r.url()}: ${r.failure()?.errorText}`); });
  page.on('pageerror', (err) => { net.errors.push(`page error: ${err.message}`); });
  page.on('console', (msg) => {
    if (msg.type() === 'error') {
      net.errors.push(`console error: ${msg.text()}`);
    }
  });
  return { browser, page, net };
}

/** Requests issued since `from` (an index into net.requests): count, bytes, data, info.json, end. */
async function account(net, from, untilEpoch = Infinity) {
  const out = { requests: 0, bytes: 0, dataRequests: 0, dataBytes: 0, infoJson: 0, tiles: 0, lastEnd: 0,
    after: 0 };
  for (const r of net.requests.slice(from)) {
    const t = r.timing();
    const end = net.finished.has(r) && t.responseEnd >= 0 ? t.startTime + t.responseEnd : Infinity;
    if (end > untilEpoch || end === Infinity) {
      out.after++; // finished after the complete frame, or not yet: not part of it
      continue;
    }
    const size = (await r.sizes()).responseBodySize;
    const url = new URL(r.url());
    out.requests++;
    out.bytes += size;
    out.lastEnd = Math.max(out.lastEnd, end);
    if (url.pathname.startsWith('/datasets/')) {
      out.dataRequests++;
      out.dataBytes += size;
      out.infoJson += url.pathname.endsWith('/info.json') ? 1 : 0;
      out.tiles += /\/iiif\/.*\/default\.\w+$/.test(url.pathname) ? 1 : 0;
    }
  }
  return out;
}

/** Wait for the page's timing hook to report; throw with the page's own message on failure. */
async function waitOpened(page, net, what) {
  try {
    await page.waitForFunction(() => ['done', 'error'].includes(window.__coldopen?.state)
      || document.getElementById('error')?.hidden === false, null, { timeout: timeoutMs, polling: 100 });
  } catch (error) {
    if (error?.name !== 'TimeoutError') {
      throw error; // e.g. the browser closed by a signal
    }
    throw new BenchError(`${what}: not fully loaded after ${timeoutMs / 1000} s (${net.errors.join('; ')})`);
  }
  const state = await page.evaluate(() => ({ ...window.__coldopen, timeOrigin: performance.timeOrigin,
    // the page's own view of its last response (Resource Timing; fetches of workers not included)
    lastResourceEnd: Math.max(0, ...performance.getEntriesByType('resource').map((e) => e.responseEnd)
      .filter((t) => t <= (window.__coldopen?.doneMs ?? 0))),
    box: document.getElementById('error')?.hidden === false ? document.getElementById('error').textContent : null }));
  if (state.state !== 'done') {
    throw new BenchError(`${what}: the viewer failed: ${state.error ?? state.box} ${net.errors.join('; ')}`);
  }
  return state;
}

/** Open one layer cold and measure it. */
async function coldOpen(dataset, layer) {
  const { browser, page, net } = await launch();
  try {
    await page.goto(pageUrl(dataset, layer), { waitUntil: 'commit' });
    const state = await waitOpened(page, net, `${dataset}/${layer}`);
    await page.waitForTimeout(SETTLE_MS);
    const doneEpoch = state.timeOrigin + state.doneMs;
    const got = await account(net, 0, doneEpoch);
    return { ms: state.doneMs, readyMs: state.readyMs, afterLastByteMs: doneEpoch - got.lastEnd,
      afterLastResourceMs: state.doneMs - state.lastResourceEnd, ...got, lastEnd: undefined,
      failed: net.failed.length };
  } finally {
    await browser.close();
  }
}

/** Open A, switch to B, then back to A: the requests, bytes and time of each switch. */
async function layerSwitch(dataset, a, b) {
  const { browser, page, net } = await launch();
  try {
    await page.goto(pageUrl(dataset, a), { waitUntil: 'commit' });
    await waitOpened(page, net, `${dataset}/${a}`);
    const renderer = await page.evaluate(() => {
      const gl = document.createElement('canvas').getContext('webgl2');
      const ext = gl.getExtension('WEBGL_debug_renderer_info');
      return ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    });
    const steps = {};
    for (const [name, id] of [['toB', b], ['backToA', a]]) {
      await page.waitForTimeout(SETTLE_MS);
      const from = net.requests.length;
      const ms = await page.evaluate(async (layer) => {
        const t0 = performance.now();
        await window.lanterna.setActiveLayer(layer);
        await window.lanterna.whenFullyLoaded();
        return performance.now() - t0;
      }, id);
      await page.waitForTimeout(SETTLE_MS);
      const got = await account(net, from);
      steps[name] = { ms, requests: got.requests, bytes: got.bytes, tiles: got.tiles };
    }
    return { renderer, ...steps };
  } finally {
    await browser.close();
  }
}

const rotate = (xs, k) => xs.slice(k % xs.length).concat(xs.slice(0, k % xs.length));
const mb = (bytes) => (bytes / 1e6).toFixed(2);

function summarise(plan, runs, switches) {
  const out = {};
  for (const { dataset, reference, layers, sources } of plan) {
    out[dataset] = {};
    for (const layer of layers) {
      const mine = runs.filter((r) => r.dataset === dataset && r.layer === layer);
      const ratios = mine.map((r) => r.ms / runs.find((x) => x.dataset === dataset && x.round === r.round
        && x.layer === reference)?.ms);
      const pick = (key) => median(mine.map((r) => r[key]));
      const src = sources[layer];
      out[dataset][layer] = {
        msMedian: pick('ms'), ms: mine.map((r) => r.ms), ratioToReferenceMedian: layer === reference ? 1 : median(ratios),
        requests: pick('requests'), dataRequests: pick('dataRequests'), infoJson: pick('infoJson'), tiles: pick('tiles'),
        bytes: pick('bytes'), dataBytes: pick('dataBytes'), afterLastByteMsMedian: pick('afterLastByteMs'),
        readyMsMedian: pick('readyMs'), requestsAfterFrame: pick('after'),
        sourceBytes: src.bytes, jpegSourced: src.jpegSourced, bytesPerSourceByte: pick('dataBytes') / src.bytes,
      };
    }
  }
  const sw = switches.length === 0 ? null : Object.fromEntries(['toB', 'backToA'].map((k) => [k, {
    msMedian: median(switches.map((s) => s[k].ms)), requests: median(switches.map((s) => s[k].requests)),
    bytes: median(switches.map((s) => s[k].bytes)), runs: switches.map((s) => s[k]),
  }]));
  return { layers: out, switch: sw };
}

function printTable(summary, plan, switchPair) {
  const w = (s) => process.stdout.write(`${s}\n`);
  w('| dataset | layer | cold open, ms | / plain image | requests (data, info.json, tiles) | MB (data) '
    + '| source MB | data / source | after last byte, ms |');
  w('|---|---|---|---|---|---|---|---|---|');
  for (const { dataset, reference } of plan) {
    for (const [layer, r] of Object.entries(summary.layers[dataset])) {
      const ratio = layer === reference ? '(reference)' : `${r.ratioToReferenceMedian.toFixed(2)}×`;
      const perSource = `${r.bytesPerSourceByte.toFixed(2)}×${r.jpegSourced ? '' : ' (not JPEG)'}`;
      w(`| ${dataset} | ${layer} | ${r.msMedian.toFixed(0)} | ${ratio} | ${r.requests} (${r.dataRequests}, `
        + `${r.infoJson}, ${r.tiles}) | ${mb(r.bytes)} (${mb(r.dataBytes)}) | ${mb(r.sourceBytes)} | ${perSource} `
        + `| ${r.afterLastByteMsMedian.toFixed(0)} |`);
    }
  }
  if (summary.switch) {
    const { toB, backToA } = summary.switch;
    w(`\nlayer switch ${switchPair.join('→')}→${switchPair[0]} (${plan[0].dataset}): `
      + `to ${switchPair[1]} ${toB.requests} requests, ${mb(toB.bytes)} MB, ${toB.msMedian.toFixed(0)} ms; `
      + `back to ${switchPair[0]} ${backToA.requests} requests, ${mb(backToA.bytes)} MB, ${backToA.msMedian.toFixed(0)} ms`);
  }
}

let current = null; // the run's browser, closed on a signal

/** The commit measured (and whether the worktree had changes), or null outside a git checkout. */
function commit() {
  try {
    const git = (...args) => execFileSync('git', args, { encoding: 'utf8', cwd: HERE }).trim();
    const head = git('rev-parse', 'HEAD');
    const dirty = git('status', '--porcelain', '--', '../plugin', '../tiler');
    return dirty ? `${head} (with changes in plugin/ or tiler/)` : head;
  } catch {
    return null;
  }
}

async function main() {
  const { table, plan } = await loadPlan();
  const loadBefore = loadavg();
  const switchPair = list(opt.switch);
  if (switchPair.length !== 0 && (switchPair.length !== 2 || !switchPair.every((l) => l in plan[0].sources))) {
    throw new BenchError(`--switch ${opt.switch}: expected two layers of ${plan[0].dataset}`);
  }
  const cases = plan.flatMap(({ dataset, layers }) => layers.map((layer) => ({ dataset, layer })));
  const runs = [];
  const switches = [];
  for (let round = -warmup; round < rounds; round++) {
    const tag = round < 0 ? 'warm-up' : `round ${round + 1}/${rounds}`;
    for (const { dataset, layer } of rotate(cases, round + warmup)) {
      const r = await coldOpen(dataset, layer);
      process.stderr.write(`${tag} ${dataset}/${layer}: ${r.ms.toFixed(0)} ms, ${r.requests} requests, `
        + `${mb(r.bytes)} MB, ${r.afterLastByteMs.toFixed(0)} ms after the last byte\n`);
      if (round >= 0) {
        runs.push({ round, dataset, layer, ...r });
      }
    }
    if (switchPair.length === 2 && round >= 0) {
      const s = await layerSwitch(plan[0].dataset, ...switchPair);
      process.stderr.write(`${tag} switch: ${JSON.stringify(s)}\n`);
      switches.push(s);
    }
  }
  const summary = summarise(plan, runs, switches);
  printTable(summary, plan, switchPair);
  const result = {
    date: new Date().toISOString(),
    machine: { cpu: cpus()[0]?.model, cpus: cpus().length, memoryGiB: Math.round(totalmem() / 2 ** 30),
      chromium: CHROMIUM, renderer: switches[0]?.renderer, viewport,
      loadAverage: { before: loadBefore, after: loadavg() } },
    commit: commit(),
    settings: { server, rounds, warmup, switch: switchPair, freshBrowserPerRun: true },
    datasets: Object.fromEntries(plan.map((p) => [p.dataset, { size: p.size, reference: p.reference,
      sourceQuality: table.datasets[p.dataset].quality ?? table.quality,
      importArgs: table.datasets[p.dataset].importArgs ?? table.importArgs }])),
    ...summary,
    runs,
  };
  if (opt.json) {
    writeFileSync(opt.json, `${JSON.stringify(result, null, 2)}\n`);
  }
}

let interrupted = false;
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    interrupted = true;
    process.stderr.write(`coldopen.mjs: ${signal}, closing Chromium\n`);
    Promise.resolve(current?.close()).finally(() => process.exit(130));
  });
}

main().catch((error) => {
  if (interrupted) {
    return; // the browser was closed under the run: no error of its own
  }
  process.stderr.write(`coldopen.mjs: ${error instanceof BenchError ? error.message : error?.stack ?? String(error)}\n`);
  process.exitCode = 1;
});
