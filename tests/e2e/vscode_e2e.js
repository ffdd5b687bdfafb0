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

const { spawn, spawnSync } = require('child_process');
const fs = require('fs');
const http = require('http');
const net = require('net');
const os = require('os');
const path = require('path');

const HERE = __dirname;
const CODE_SERVER = path.join(HERE, 'node_modules', '.bin', 'code-server');

function parseArgs(argv) {
  const args = {};
  for (let i = 0; i < argv.length; i++) {
    const m = /^--([a-z-]+)$/.exec(argv[i]);
    if (!m) throw new Error(`unexpected argument ${argv[i]}`);
    if (m[1] === 'no-sim' || m[1] === 'no-hover' || m[1] === 'no-python') {
      args[m[1]] = true;
      continue;
    }
    args[m[1]] = argv[++i];
  }
  for (const k of ['vsix', 'workspace', 'bad', 'sim', 'out']) {
    if (!args[k]) throw new Error(`missing --${k}`);
  }
  return args;
}

const t0 = Date.now();
const timings = {};
function log(msg) {
  process.stderr.write(`[${((Date.now() - t0) / 1000).toFixed(1)}s] ${msg}\n`);
}
async function timed(name, fn) {
  const start = Date.now();
  log(`${name}…`);
  try {
    return await fn();
  } finally {
    timings[name] = +((Date.now() - start) / 1000).toFixed(2);
  }
}

function freePort() {
  return new Promise((resolve, reject) => {
    const srv = net.createServer();
    srv.once('error', reject);
    srv.listen(0, '127.0.0.1', () => {
      const { port } = srv.address();
      srv.close(() => resolve(port));
    });
  });
}

function get(url) {
  return new Promise((resolve) => {
    const req = http.get(url, (res) => {
      res.resume();
      resolve(res.statusCode);
    });
    req.on('error', () => resolve(0));
    req.setTimeout(2000, () => {
      req.destroy();
      resolve(0);
    });
  });
}

async function waitFor(what, fn, timeoutMs = 30000, intervalMs = 250) {
  const end = Date.now() + timeoutMs;
  let last;
  while (Date.now() < end) {
    try {
      last = await fn();
      if (last) return last;
    } catch (e) {
      last = e;
    }
    await new Promise((r) => setTimeout(r, intervalMs));
  }
  throw new Error(`timed out waiting for ${what}${last instanceof Error ? `: ${last.message}` : ''}`);
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  fs.mkdirSync(args.out, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'ladder-vscode-e2e-'));
  const userDir = path.join(tmp, 'user');
  const extDir = path.join(tmp, 'extensions');
  fs.mkdirSync(path.join(userDir, 'User'), { recursive: true });
  fs.writeFileSync(
    path.join(userDir, 'User', 'settings.json'),
    JSON.stringify(
      {
        'security.workspace.trust.enabled': false,
        'workbench.startupEditor': 'none',
        'workbench.tips.enabled': false,
        'workbench.colorTheme': 'Default Dark Modern',
        'workbench.enableExperiments': false,
        'telemetry.telemetryLevel': 'off',
        'update.mode': 'none',
        'extensions.autoCheckUpdates': false,
        'extensions.autoUpdate': false,
        'extensions.ignoreRecommendations': true,
        'git.enabled': false,
        'editor.minimap.enabled': false,
        'window.commandCenter': false,
        'chat.commandCenter.enabled': false,
        ...(args.python ? { 'ladder.server.pythonPath': args.python } : {}),
        'ladder.compileOnSave': false,
      },
      null,
      2,
    ),
  );

  const env = { ...process.env, HOME: tmp, XDG_CONFIG_HOME: path.join(tmp, 'config'), XDG_DATA_HOME: path.join(tmp, 'data') };
  delete env.VSCODE_IPC_HOOK_CLI;

  await timed('install extension', async () => {
    const r = spawnSync(CODE_SERVER, ['--install-extension', args.vsix, '--extensions-dir', extDir, '--user-data-dir', userDir], {
      env,
      encoding: 'utf8',
      timeout: 120000,
    });
    if (r.status !== 0) throw new Error(`--install-extension failed (${r.status}): ${r.stdout}\n${r.stderr}`);
    const installed = fs.readdirSync(extDir).filter((d) => d.startsWith('textladder.'));
    if (installed.length === 0) throw new Error(`extension not installed in ${extDir}: ${r.stdout}`);
    log(`installed ${installed.join(', ')}`);
  });

  const port = await freePort();
  const serverLog = fs.openSync(path.join(args.out, 'code-server.log'), 'w');
  const server = spawn(
    CODE_SERVER,
    [
      '--auth', 'none',
      '--bind-addr', `127.0.0.1:${port}`,
      '--disable-telemetry',
      '--disable-update-check',
      '--disable-workspace-trust',
      '--disable-getting-started-override',
      '--extensions-dir', extDir,
      '--user-data-dir', userDir,
      args.workspace,
    ],
    { env, detached: true, stdio: ['ignore', serverLog, serverLog] },
  );
  const killServer = () => {
    try {
      process.kill(-server.pid, 'SIGTERM');
    } catch {}
  };
  process.on('exit', () => {
    try {
      process.kill(-server.pid, 'SIGKILL');
    } catch {}
  });

  let browser;
  let page;
  const result = { ok: false, timings };
  try {
    await timed('start code-server', () =>
      waitFor('code-server to answer', async () => (await get(`http://127.0.0.1:${port}/healthz`)) === 200, 60000),
    );

    const { chromium } = require(path.join(HERE, 'node_modules', 'playwright-core'));
    browser = await timed('start chromium', () =>
      chromium.launch({
        executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
        headless: true,
        args: [
          '--headless',
          '--no-sandbox',
          '--disable-gpu',
          '--disable-dev-shm-usage',
          '--disable-background-networking',
          '--disable-component-update',
          '--no-first-run',
        ],
      }),
    );
    const context = await browser.newContext({ viewport: { width: 1400, height: 900 } });
    page = await context.newPage();
    page.on('pageerror', (e) => log(`page error: ${e.message}`));

    await timed('load workbench', async () => {
      await page.goto(`http://127.0.0.1:${port}/?folder=${encodeURIComponent(args.workspace)}`, { waitUntil: 'domcontentloaded' });
      await page.waitForSelector('.monaco-workbench', { timeout: 60000 });
      await page.waitForSelector('.explorer-folders-view, .explorer-viewlet', { timeout: 60000 });
    });

    const openFile = async (name) => {
      await page.locator('.monaco-workbench').click({ position: { x: 700, y: 400 } }).catch(() => undefined);
      await page.keyboard.press('Control+P');
      const input = page.locator('.quick-input-widget input');
      await input.waitFor({ state: 'visible', timeout: 15000 });
      await input.fill(name);
      const row = page.locator('.quick-input-widget .monaco-list-row', { hasText: name }).first();
      await row.waitFor({ state: 'visible', timeout: 15000 });
      await row.click();
      await page.locator(`.tab.active[aria-label^="${name}"], .tab.active:has-text("${name}")`).first().waitFor({ timeout: 15000 });
      await page.locator('.monaco-editor .view-lines').first().waitFor({ timeout: 15000 });
    };

    const runCommand = async (title) => {
      await page.keyboard.press('F1');
      const input = page.locator('.quick-input-widget input');
      await input.waitFor({ state: 'visible', timeout: 15000 });
      await input.fill(`>${title}`);
      const row = page.locator('.quick-input-widget .monaco-list-row', { hasText: title }).first();
      await row.waitFor({ state: 'visible', timeout: 15000 });
      await row.click();
    };

    const hoverName = async (word) => {
      const name = page.locator('.monaco-editor .view-lines span span', { hasText: new RegExp(`^${word}$`) }).first();
      await name.waitFor({ timeout: 5000 });
      const box = await name.boundingBox();
      await page.mouse.move(box.x + 2, box.y + box.height / 2);
      await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2, { steps: 5 });
    };
    const hoverText = () =>
      waitFor('the hover', async () => {
        const h = page.locator('.monaco-hover:not(.hidden) .monaco-hover-content').first();
        return (await h.isVisible().catch(() => false)) ? (await h.innerText()).trim() : false;
      }, 15000);

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
      const box = page.locator('.quick-input-widget input');
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

    result.languageId = await timed('language mode', () =>
      waitFor('the ladder language mode', async () => {
        const text = (await page.locator('.statusbar [id="status.editor.mode"]').innerText().catch(() => '')) || '';
        return /ladder/i.test(text) ? text.trim() : false;
      }, 30000),
    );

    if (args['no-python']) {
      // no Python on PATH: the notification says what to install
      result.notification = await timed('the notification that no Python fits', () =>
        waitFor('the notification', async () => {
          const toasts = await page.locator('.notifications-toasts .notification-toast').allInnerTexts();
          const hit = toasts.find((t) => /language server needs Python/.test(t));
          return hit ? hit.replace(/\s+/g, ' ').trim() : false;
        }, 30000),
      );
      const shot = path.join(args.out, 'vscode-no-python.png');
      await page.screenshot({ path: shot });
      result.screenshot = shot;
    } else {
      result.problems = await timed('diagnostic in the Problems panel', async () => {
        await page.keyboard.press('Control+Shift+M');
        return waitFor(
          'the diagnostic in the Problems panel',
          async () => {
            const rows = await page.locator('.markers-panel .monaco-list-row').allInnerTexts();
            const hit = rows.find((r) => /LD102/.test(r));
            return hit ? rows : false;
          },
          60000,
        );
      });
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
        result.hover = await timed('hover a name', async () => {
          await hoverName('Xstop');
          return hoverText();
        });
        await page.mouse.move(5, 5);
        await page.keyboard.press('Escape');
      }

      if (!args['no-sim']) {
        await timed('start the simulation (command palette)', async () => {
          await runCommand('Ladder: Start Simulation');
          await waitFor('the status bar to show the simulation', async () => {
            const text = await page.locator('.statusbar').innerText();
            return /scan\s+\d+/.test(text);
          }, 30000);
        });

        await timed('toggle Xstart with its code lens', async () => {
          const lens = page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Xstart = 0' }).first();
          await lens.waitFor({ state: 'visible', timeout: 20000 });
          await lens.click();
          await page.locator('.contentWidgets .codelens-decoration a', { hasText: 'Xstart = 1' }).first().waitFor({ timeout: 20000 });
        });

        await timed('one scan with F10', async () => {
          const before = await page.locator('.statusbar').innerText();
          const scanBefore = Number((/scan\s+(\d+)/.exec(before) || [])[1]);
          await page.locator('.monaco-editor .view-lines').first().click({ position: { x: 5, y: 5 } });
          await page.keyboard.press('F10');
          result.statusBar = await waitFor('the scan count to advance', async () => {
            const text = await page.locator('.statusbar').innerText();
            const m = /Sim[^\n]*scan\s+(\d+)/.exec(text);
            return m && Number(m[1]) > scanBefore ? m[0] : false;
          }, 20000);
        });

        result.energized = await timed('energized elements painted red', () =>
          waitFor('red (energized) text in the editor', async () => {
            const texts = await page.evaluate(() => {
              const out = [];
              const spans = document.querySelectorAll('.monaco-editor .view-lines .view-line span span');
              for (const s of spans) {
                // textladder.energizedForeground in a dark theme: #ff4040
                if (getComputedStyle(s).color === 'rgb(255, 64, 64)' && s.textContent.trim()) out.push(s.textContent);
              }
              return out;
            });
            return texts.length > 0 ? texts : false;
          }, 20000),
        );
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

        await timed('stop the simulation', async () => {
          await page.locator('.monaco-editor .view-lines').first().click({ position: { x: 5, y: 5 } });
          await page.keyboard.press('Shift+F5');
          await waitFor('the red elements to go', async () => {
            const n = await page.evaluate(() => {
              let k = 0;
              for (const s of document.querySelectorAll('.monaco-editor .view-lines .view-line span span')) {
                if (getComputedStyle(s).color === 'rgb(255, 64, 64)' && s.textContent.trim()) k++;
              }
              return k;
            });
            return n === 0;
          }, 15000);
        });

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
    result.ok = true;
  } catch (err) {
    result.error = String(err && err.stack ? err.stack : err);
    log(`FAILED: ${result.error}`);
    if (page) {
      const shot = path.join(args.out, 'vscode-failure.png');
      await page.screenshot({ path: shot }).catch(() => undefined);
      result.screenshot = shot;
    }
  } finally {
    if (browser) await browser.close().catch(() => undefined);
    killServer();
    await new Promise((r) => setTimeout(r, 500));
    try {
      process.kill(-server.pid, 'SIGKILL');
    } catch {}
    // the extension host logs are the first place to look when a step fails
    try {
      const logs = path.join(userDir, 'logs');
      fs.cpSync(logs, path.join(args.out, 'code-server-logs'), { recursive: true });
    } catch {}
    fs.rmSync(tmp, { recursive: true, force: true });
  }
  timings.total = +((Date.now() - t0) / 1000).toFixed(2);
  process.stdout.write(JSON.stringify(result) + '\n');
  process.exit(result.ok ? 0 : 1);
}

main().catch((err) => {
  process.stderr.write(`${err && err.stack ? err.stack : err}\n`);
  process.stdout.write(JSON.stringify({ ok: false, error: String(err), timings }) + '\n');
  process.exit(1);
});
