#!/usr/bin/env node
// Drive the Lanterna viewer page through a scripted session in headless Chromium: pages opened one
// after another in one browser context, each a list of steps. For the view-tools tests (links,
// snapshots, scale bar, keys, help).
//
//   node tests/browser/session.mjs SPEC.json
//
// SPEC = {"pages": [{"url": "…/viewer/?manifest=…#v=1…", "viewport": {"width": 640, "height": 480},
//                    "steps": [STEP, …]}], "out": "/abs/dir", "timeoutMs": 60000}
// A page's url may hold `{name}`: the value an earlier step saved as `name` (e.g. a hash).
// Each page waits for `window.lanterna.ready` before its steps. Steps:
//   {"eval": "JS function body", "save": "name"}  run `async () => { body }` in the page, keep its
//       (JSON) result as `name`; `window.lanterna` is the viewer
//   {"waitFor": "JS expression"}  wait until it is truthy
//   {"frame": "name"}  wait until fully loaded, read the pixels to OUT/name.rgba (+ .json: width, height)
//   {"press": "KeyName"}  a key press (playwright names: "l", "Shift+ArrowUp", "?", "Escape", "Tab")
//   {"click": "CSS selector"}
//   {"download": "name", "press" | "click": …}  do the press or click, save the download as OUT/name
//       and its suggested file name as `name`
// Page keys: "routes": [{"match": "regex", "status": 404}] answer matching requests with that status;
// "allowConsoleErrors": ["regex", …] console errors that do not fail the run.
// The results (every saved value) go to OUT/result.json. Exits non-zero on a page error, a console
// error or a step taking longer than timeoutMs.
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import process from 'node:process';
import { chromium } from 'playwright-core';
import { CHROMIUM, CHROMIUM_ARGS, readFrame, withTimeout } from './page-actions.mjs';


async function runStep(page, step, saved, out) {
  if (step.download !== undefined) {
    const [download] = await Promise.all([
      page.waitForEvent('download'),
      step.press !== undefined ? page.keyboard.press(step.press) : page.click(step.click),
    ]);
    await download.saveAs(join(out, step.download));
    saved[step.download] = download.suggestedFilename();
  } else if (step.eval !== undefined) {
    const value = await page.evaluate(`(async () => { ${step.eval} })()`);
    if (step.save !== undefined) {
      saved[step.save] = value ?? null;
    }
  } else if (step.waitFor !== undefined) {
    await page.waitForFunction(step.waitFor);
  } else if (step.frame !== undefined) {
    const frame = await readFrame(page);
    writeFileSync(join(out, `${step.frame}.rgba`), Buffer.from(frame.base64, 'base64'));
    writeFileSync(join(out, `${step.frame}.rgba.json`), JSON.stringify({ width: frame.width, height: frame.height }));
  } else if (step.press !== undefined) {
    await page.keyboard.press(step.press);
  } else if (step.click !== undefined) {
    await page.click(step.click);
  } else {
    throw new Error(`unknown step ${JSON.stringify(step)}`);
  }
}

async function main() {
  const spec = JSON.parse((await import('node:fs')).readFileSync(process.argv[2], 'utf8'));
  const timeoutMs = spec.timeoutMs ?? 60000;
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, headless: true });
  const saved = {};
  const errors = [];
  try {
    const context = await browser.newContext({ deviceScaleFactor: 1, acceptDownloads: true });
    for (const [index, p] of spec.pages.entries()) {
      const page = await context.newPage();
      await page.setViewportSize({ width: p.viewport?.width ?? 640, height: p.viewport?.height ?? 480 });
      page.on('pageerror', (err) => errors.push(`page ${index}: page error: ${err.message}`));
      const allowed = (p.allowConsoleErrors ?? []).map((re) => new RegExp(re));
      for (const r of p.routes ?? []) {
        await page.route((u) => new RegExp(r.match).test(u.href), (route) => route.fulfill({ status: r.status }));
      }
      page.on('console', (msg) => {
        if (msg.type() === 'error' && !allowed.some((re) => re.test(msg.text()))) {
          errors.push(`page ${index}: console error: ${msg.text()}`);
        }
      });
      const url = p.url.replace(/\{(\w+)\}/g, (_, name) => String(saved[name] ?? ''));
      await withTimeout(page.goto(url, { waitUntil: 'load' }), timeoutMs, `loading ${url}`);
      await withTimeout(page.waitForFunction(() => window.lanterna !== undefined), timeoutMs, 'window.lanterna');
      await withTimeout(page.evaluate(() => window.lanterna.ready), timeoutMs, 'lanterna.ready');
      for (const step of p.steps ?? []) {
        await withTimeout(runStep(page, step, saved, spec.out), timeoutMs, `page ${index}: ${JSON.stringify(step)}`);
        if (errors.length > 0) {
          throw new Error(errors.join('\n'));
        }
      }
      await page.close();
    }
  } finally {
    writeFileSync(join(spec.out, 'result.json'), JSON.stringify(saved));
    await browser.close();
  }
}

main().catch((error) => {
  process.stderr.write(`session.mjs: ${error?.stack ?? String(error)}\n`);
  process.exitCode = 1;
});
