// The playground in Debian's Chromium, headless, through playwright-core: what a person does and
// sees. Types a program with an error and sees its diagnostic, fixes it by typing, starts a
// simulation, clicks an input and sees the output energized in the drawing and 1 in the values;
// downloads the HEX; opens an .ld file and downloads it as a .ladder file; then opens bigger
// programs and times one-character edits: from the keystroke to its diagnostics in the page.
//
//   node playground_e2e.mjs --url URL --bad FILE --fixes JSON --input NAME --output NAME --ld FILE
//                           --timed JSON --out DIR
//     --fixes: [[line, column, length, typed]...] turning --bad into a program without problems
//     --input, --output: the input to click once the simulation runs, the output it drives
//     --ld: an LDmicro file to open and download as a .ladder file
//     --timed: [[FILE, [[line, column]...], warmUpMs]...] programs to open, each with the characters
//              to type over (one edit each) once warmUpMs have passed (lsp/warmup.py is then over)
//
// Prints one JSON object on its last line of stdout ({"ok": true, "timings": {...}, "hex": PATH});
// timings.timed has, for each --timed program, keyToShownMs, sentToReceivedMs and keyToFirstTaskMs
// (main.js: when the page could first run a task after the keystroke) of every edit.
// exits 1 on failure, with a screenshot in --out.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const t0 = Date.now();
const log = (message) => process.stderr.write(`[${((Date.now() - t0) / 1000).toFixed(1)}s] ${message}\n`);
const timings = {};

async function select(page, line, column, length) {
  await page.evaluate(([l, c, n]) => {
    const { view } = window.ladder;
    const from = view.state.doc.line(l + 1).from + c;
    view.dispatch({ selection: { anchor: from, head: from + n }, scrollIntoView: true });
    view.focus();
  }, [line, column, length]);
}

async function problems(page) {
  return page.locator('#problems li').allTextContents();
}

// opens `text` and types a letter over each of `edits` ([line, column]), one edit after the other's diagnostics
async function timeEdits(page, text, edits, warmUpMs) {
  await page.evaluate((t) => window.ladder.open('big.ladder', t, 'ladder'), text);
  await page.waitForFunction(() => window.ladder.timings.firstDiagnosticsMs !== null);
  await page.waitForTimeout(warmUpMs);
  const typed = 'abcdefghijklmnopqrstuvwxyz';
  await page.evaluate(() => { window.ladder.timings.edits.length = 0; });
  for (let i = 0; i < edits.length; i++) {
    const [line, column] = edits[i];
    const count = await page.evaluate(() => window.ladder.timings.edits.length);
    await select(page, line, column, 1);
    await page.keyboard.type(typed[i % typed.length]);
    await page.waitForFunction((n) => window.ladder.timings.edits.length > n, count);
  }
  const timed = await page.evaluate(() => window.ladder.timings.edits);
  if (timed.some((edit) => edit.keyToShownMs === null)) throw new Error(`an edit not timed from its keystroke: ${JSON.stringify(timed)}`);
  return {
    keyToShownMs: timed.map((edit) => +edit.keyToShownMs.toFixed(1)),
    sentToReceivedMs: timed.map((edit) => +edit.sentToReceivedMs.toFixed(1)),
    keyToFirstTaskMs: timed.map((edit) => (edit.keyToFirstTaskMs === null ? null : +edit.keyToFirstTaskMs.toFixed(1))),
  };
}

async function main() {
  fs.mkdirSync(args.out, { recursive: true });
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'ladder-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    acceptDownloads: true,
    viewport: { width: 1400, height: 900 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync', '--disable-dev-shm-usage'],
  });
  const page = context.pages()[0] || await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => m.type() === 'error' && log(`console: ${m.text()}`));
  try {
    log('load the page');
    await page.goto(args.url, { waitUntil: 'domcontentloaded' });
    await page.waitForFunction(() => window.ladder && window.ladder.timings.firstDiagnosticsMs !== null, null, { timeout: 90000 });
    timings.firstDiagnosticsMs = Math.round(await page.evaluate(() => window.ladder.timings.firstDiagnosticsMs));
    timings.workerStart = await page.evaluate(() => window.ladder.timings.start);
    log(`first diagnostics after ${timings.firstDiagnosticsMs} ms`);

    log('type a program with an error');
    await page.locator('.cm-content').click();
    await page.keyboard.press('Control+A');
    await page.keyboard.insertText(fs.readFileSync(args.bad, 'utf8'));
    await page.waitForFunction(() => [...document.querySelectorAll('#problems li')].some((li) => li.textContent.includes('LD102')));
    const bad = await problems(page);
    await page.locator('.cm-lintRange-error').first().waitFor();
    await page.screenshot({ path: path.join(args.out, 'playground-error.png') });

    log('fix it');
    for (const [line, column, length, typed] of JSON.parse(args.fixes)) {
      await select(page, line, column, length);
      await page.keyboard.type(typed);
    }
    await page.waitForFunction(() => document.querySelectorAll('#problems li').length === 0);
    await page.waitForFunction(() => document.querySelectorAll('.cm-lintRange-error').length === 0);

    log('simulate');
    await page.click('#sim-start');
    const input = page.locator('#inputs button', { hasText: args.input });
    await input.waitFor();
    const before = await page.locator(`#values tr[data-name="${args.output}"] td`).nth(1).textContent();
    await input.click();
    await page.waitForFunction((name) => {
      const row = document.querySelector(`#values tr[data-name="${name}"]`);
      return row && row.cells[1].textContent === '1';
    }, args.output);
    const energized = await page.locator('.cm-energized').allTextContents();
    await page.waitForFunction(() => document.querySelectorAll('#plot path').length > 0);
    await page.screenshot({ path: path.join(args.out, 'playground-simulation.png') });
    await page.click('#sim-stop');

    log('download the HEX');
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('[data-export="hex"]')]);
    const hex = path.join(args.out, download.suggestedFilename());
    await download.saveAs(hex);

    log('open an .ld file and download it as a .ladder file');
    await page.setInputFiles('#open', args.ld);
    await page.waitForFunction(() => window.ladder.doc.uri.endsWith('.ld') && window.ladder.timings.firstDiagnosticsMs !== null);
    await page.waitForTimeout(500); // its diagnostics, if it had any
    const ldProblems = await problems(page);
    const [converted] = await Promise.all([page.waitForEvent('download'), page.click('[data-export="ladder"]')]);
    const ladder = path.join(args.out, converted.suggestedFilename());
    await converted.saveAs(ladder);

    timings.timed = [];
    for (const [file, edits, warmUpMs] of JSON.parse(args.timed)) {
      log(`time edits on ${path.basename(file)}`);
      timings.timed.push(await timeEdits(page, fs.readFileSync(file, 'utf8'), edits, warmUpMs));
    }
    console.log(JSON.stringify({ ok: errors.length === 0, errors, timings, bad, before, energized, hex, ldProblems, ladder }));
  } catch (error) {
    await page.screenshot({ path: path.join(args.out, 'playground-failure.png') }).catch(() => {});
    console.log(JSON.stringify({ ok: false, error: String(error.stack || error), errors, timings }));
    process.exitCode = 1;
  } finally {
    await context.close();
    fs.rmSync(profile, { recursive: true, force: true });
  }
}

main();
