#!/usr/bin/env node
// Real-editor test of the extension's browser entry: the .vsix installed into code-server (VS Code
// 1.100.3), the extension forced into the web worker extension host, where VS Code for the Web
// and vscode.dev run it (the user setting "remote.extensionKind": web), so its language server is
// the one on Pyodide in a Web Worker. In Chromium through playwright-core, as a person would:
// a diagnostic in the Problems panel, the program fixed with Replace All and the diagnostic gone,
// its HEX built (Build HEX), a program formatted (Format Document) and saved, the hover of a
// name, completion on a name, a simulation started with an input toggled by its code lens and a
// scan run (F10), the coil painted red; the program converted to .ld; the "Ladder" output, which
// names the server started. The HEX and the .ld are written through the workspace's file system,
// beside their programs. Saves screenshots.
//
//   node vscode_web_e2e.js --vsix X.vsix --workspace DIR --bad NAME --fmt NAME --sim NAME --out DIR
//
// --bad: a program whose only diagnostic is LD102 on Xlamp, fixed by renaming it Ylamp everywhere;
// --fmt: a program that formatting changes; --sim: a program with the inputs Xstart and Xstop.
// Prints one JSON object on its last line of stdout ({"ok": true, ...}); exits 1 on failure.
'use strict';

const fs = require('fs');
const path = require('path');
const { stopwatch, waitFor, openCodeServer, workbench, report, runDriver, parseArgs } = require('./code_server');

async function main() {
  const args = parseArgs(process.argv.slice(2), ['vsix', 'workspace', 'bad', 'fmt', 'sim', 'out']);
  const { log, timed, timings, total } = stopwatch();
  const result = { ok: false, timings };
  await report(result, async (opened) => {
    const session = opened.session = await openCodeServer({
      ...args,
      settings: { 'remote.extensionKind': { 'textladder.textladder': ['web'] }, 'ladder.compileOnSave': false },
      timed,
      log,
    });
    const page = session.page;
    const ui = workbench(page);

    await ui.diagnoseAndFix(timed, result, () => ui.openFile(args.bad), path.join(args.out, 'vscode-web-problems.png'));

    result.built = await timed('build the HEX of the fixed program', () => ui.buildHex('lamp.hex'));

    await timed('format a program and save it', async () => {
      const file = path.join(args.workspace, args.fmt);
      const before = fs.readFileSync(file, 'utf8');
      await ui.openFile(args.fmt);
      await ui.formatDocument();
      await page.keyboard.press('Control+S');
      await waitFor('the formatted program saved', () => fs.readFileSync(file, 'utf8') !== before, 15000);
    });

    await timed('open the program to simulate', () => ui.openFile(args.sim));
    result.hover = await timed('hover a name', () => ui.hover('Xstop'));
    result.completion = await timed('completion on a name', async () => {
      const rows = await ui.suggestions('Xstop');
      await page.keyboard.press('Escape');
      return rows;
    });

    await timed('start the simulation (command palette)', ui.startSimulation);
    await timed('toggle Xstart with its code lens', () => ui.toggleWithLens('Xstart'));
    result.statusBar = await timed('one scan with F10', ui.scanWithF10);
    result.energized = await timed('energized elements painted red', () => ui.energizedUntil((t) => t.includes('(')));
    await page.screenshot({ path: path.join(args.out, 'vscode-web-simulation.png') });
    await timed('stop the simulation', ui.stopSimulation);

    result.converted = await timed('convert to .ld', () => ui.convert("LDmicro's own format", 'conveyor.ld'));

    result.output = await timed('the "Ladder" output', () => ui.output('Ladder', /starting the language server/));
  }, { out: args.out, shot: 'vscode-web-failure.png', log, total });
}

runDriver(main);
