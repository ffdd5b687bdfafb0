#!/usr/bin/env node
// Real-editor test of the VS Code extension: installs the .vsix into code-server (VS Code 1.100.3
// on Node 20), opens it in Debian's Chromium through playwright-core, and checks what a person
// would see: the diagnostic in the Problems panel, a simulation started from the command palette,
// an input toggled with its code lens, a scan run with F10, energized elements painted red, the
// status bar and the watch view; with --uart, a program that sends run for a second and what it
// sent read from the watch view. Saves screenshots.
//
//   node vscode_e2e.js --vsix X.vsix --workspace DIR --bad FILE --sim FILE --out DIR [--python PY]
//                      [--uart FILE]
//                      [--detect a.ld,b.txt] [--no-sim] [--no-hover]   (to narrow a run down while debugging)
//                      [--no-python]
//
// Without --python the extension finds a Python itself (ladder.server.pythonPath unset), on the
// PATH this script is started with, which code-server and its extension host inherit. With
// --no-python that PATH has none: the run opens --bad and reads the notification that says what
// to install, and checks nothing else.
//
// Prints one JSON object on its last line of stdout ({"ok": true, ...}); exits 1 on failure.
'use strict';

const path = require('path');
const { stopwatch, waitFor, openCodeServer, workbench, report, runDriver, parseArgs } = require('./code_server');

const { log, timed, timings, total } = stopwatch();

async function main() {
  const args = parseArgs(process.argv.slice(2), ['vsix', 'workspace', 'bad', 'sim', 'out'], ['no-sim', 'no-hover', 'no-python']);
  const result = { ok: false, timings };
  await report(result, async (opened) => {
    const session = opened.session = await openCodeServer({
      ...args,
      settings: { ...(args.python ? { 'ladder.server.pythonPath': args.python } : {}), 'ladder.compileOnSave': false },
      timed,
      log,
    });
    const page = session.page;
    const { quickInput, openFile, runCommand, hoverName, hoverText, problems, languageMode, startSimulation, toggleWithLens, scanWithF10,
      energizedUntil, stopSimulation, hover, toast } = workbench(page);

    // the rows of the watch view as drawn: label (its spaces kept), description, depth in the tree
    const watchRows = (pane) =>
      pane.locator('.monaco-list-row').evaluateAll((rows) =>
        rows.map((r) => ({
          label: (r.querySelector('.label-name') || r).textContent,
          description: ((r.querySelector('.label-description') || {}).textContent || '').trim(),
          level: Number(r.getAttribute('aria-level')),
        })),
      );

    // a program that sends, simulated for a second ("Run Simulation For…"): the watch view's UART group
    const uartInWatchView = async (name) => {
      await openFile(name);
      await runCommand('Ladder: Start Simulation');
      await waitFor('the status bar to show scan 1', async () => /scan 1\b/.test(await page.locator('.statusbar').innerText()), 30000);
      await runCommand('Ladder: Run Simulation For');
      const box = quickInput;
      await box.waitFor({ state: 'visible', timeout: 15000 });
      await box.fill('1 s');
      await box.press('Enter');
      const statusBar = await waitFor('a second simulated', async () => {
        const m = /Sim[^\n]*scan\s+(\d+)/.exec(await page.locator('.statusbar').innerText());
        return m && Number(m[1]) > 1 ? m[0] : false;
      }, 30000);
      // the Explorer's folder section gives its height to the watch view, whose rows are drawn only when in sight
      const folders = page.locator('.pane', { has: page.locator('.explorer-folders-view') }).locator('.pane-header').first();
      if ((await folders.getAttribute('aria-expanded')) === 'true') await folders.click();
      const pane = page.locator('.pane', { has: page.locator('.pane-header', { hasText: 'Ladder Simulation' }) });
      let before = '';
      const rows = await waitFor('the UART group in the watch view, its rows settled', async () => {
        const now = await watchRows(pane);
        const group = now.findIndex((r) => /^UART sent/.test(r.label));
        const seen = JSON.stringify(now);
        const settled = group >= 0 && group + 1 < now.length && seen === before;
        before = seen;
        return settled ? now : false;
      }, 20000);
      return { statusBar, rows };
    };

    const badName = path.basename(args.bad);
    const simName = path.basename(args.sim);

    await timed('open file with an error', () => openFile(badName));

    result.languageId = await timed('language mode', languageMode);

    if (args['no-python']) {
      // no Python on PATH: the notification says what to install
      result.notification = await timed('the notification that no Python fits', () => toast(/language server needs Python/));
      const shot = path.join(args.out, 'vscode-no-python.png');
      await page.screenshot({ path: shot });
      result.screenshot = shot;
    } else {
      result.problems = await timed('diagnostic in the Problems panel', () => problems(/LD102/, 60000));
      log(`problems: ${JSON.stringify(result.problems)}`);
      await page.screenshot({ path: path.join(args.out, 'vscode-problems.png') });

      // languages by first line: LDmicro .ld files are `ldmicro`, linker scripts are not; exported .txt is `ladder`
      if (args.detect) {
        result.languages = await timed('languages of .ld and .txt files', async () => {
          const out = {};
          for (const name of args.detect.split(',')) {
            await openFile(name);
            out[name] = await waitFor(`the language mode of ${name}`, async () => {
              const t = (await page.locator('.statusbar [id="status.editor.mode"]').innerText().catch(() => '')).trim();
              return t || false;
            }, 15000);
            // the language is chosen when the file opens; give a late change a moment to show
            await page.waitForTimeout(300);
            out[name] = (await page.locator('.statusbar [id="status.editor.mode"]').innerText()).trim();
          }
          return out;
        });
      }

      await timed('open the program to simulate', () => openFile(simName));
      // the hover of a name: the server's text
      if (!args['no-hover']) {
        result.hover = await timed('hover a name', () => hover('Xstop'));
      }

      if (!args['no-sim']) {
        await timed('start the simulation (command palette)', startSimulation);
        await timed('toggle Xstart with its code lens', () => toggleWithLens('Xstart'));
        result.statusBar = await timed('one scan with F10', scanWithF10);
        result.energized = await timed('energized elements painted red', () => energizedUntil(() => true));
        log(`energized: ${JSON.stringify(result.energized)}`);

        // live values come as inlay hints after the end of their line: the drawing must not move
        result.liveValues = await timed('live values after the line, rails aligned', () =>
          waitFor('Xstart=1 after its line with every right rail in one column', async () => {
            const seen = await page.evaluate(() => {
              const rails = new Set();
              let hint = '';
              for (const line of document.querySelectorAll('.monaco-editor .view-lines .view-line')) {
                const text = line.textContent || '';
                if (/Xstart=1/.test(text)) hint = text.replace(/\u00a0/g, ' ');
                // the right rail: the last "||" of the drawing, measured where the browser draws it
                const walker = document.createTreeWalker(line, NodeFilter.SHOW_TEXT);
                let last = null;
                for (let node = walker.nextNode(); node; node = walker.nextNode()) {
                  const at = node.textContent.lastIndexOf('||');
                  if (at >= 0) last = [node, at];
                }
                if (!last || !/^\s*\d*\|\|/.test(text.replace(/\u00a0/g, ' '))) continue;
                const range = document.createRange();
                range.setStart(last[0], last[1]);
                range.setEnd(last[0], last[1] + 2);
                rails.add(Math.round(range.getBoundingClientRect().left));
              }
              return { rails: [...rails], hint };
            });
            return seen.rails.length === 1 && /\|\|\s+Xstart=1/.test(seen.hint) ? seen : false;
          }, 20000),
        );
        log(`live values: ${JSON.stringify(result.liveValues)}`);

        result.watch = await timed('watch view', async () => {
          const header = page.locator('.pane-header', { hasText: 'Ladder Simulation' }).first();
          await header.waitFor({ timeout: 15000 });
          if ((await header.getAttribute('aria-expanded')) !== 'true') await header.click();
          return waitFor('Xstart in the watch view', async () => {
            const rows = await page.locator('.pane', { has: header }).locator('.monaco-list-row').allInnerTexts();
            return rows.some((r) => /Xstart/.test(r)) ? rows.map((r) => r.replace(/\s+/g, ' ').trim()) : false;
          }, 15000);
        });

        const shot = path.join(args.out, 'vscode-simulation.png');
        await page.screenshot({ path: shot });
        result.screenshot = shot;

        // while simulating, the hover adds a link that toggles the input
        if (!args['no-hover']) {
          result.hoverSim = await timed('toggle Xstop from its hover', async () => {
            await hoverName('Xstop');
            const text = await waitFor('the toggle link in the hover', async () => {
              const t = await hoverText();
              return /Toggle Xstop/.test(t) ? t : false;
            }, 15000);
            await page.locator('.monaco-hover:not(.hidden) a', { hasText: 'Toggle Xstop' }).first().click();
            await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Xstop = 1' }).first().waitFor({ timeout: 15000 });
            return text;
          });
          await page.mouse.move(5, 5);
        }

        await timed('stop the simulation', stopSimulation);

        if (args.uart) {
          result.uart = await timed('what the UART sent, in the watch view', () => uartInWatchView(path.basename(args.uart)));
          log(`uart: ${JSON.stringify(result.uart)}`);
          await page.screenshot({ path: path.join(args.out, 'vscode-uart.png') });
        }
      } else {
        const shot = path.join(args.out, 'vscode-editor.png');
        await page.screenshot({ path: shot });
        result.screenshot = shot;
      }
    }
  }, { out: args.out, shot: 'vscode-failure.png', log, total });
}

runDriver(main, () => ({ timings }));
