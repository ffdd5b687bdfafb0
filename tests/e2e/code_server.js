// A VS Code session in code-server (VS Code 1.100.3 on Node 20), driven by Debian's Chromium
// through playwright-core: what the real-editor tests of the extension share (vscode_e2e.js, the
// desktop extension; vscode_web_e2e.js, its browser entry in the web worker extension host;
// vscode_testweb_e2e.js, the same entry in @vscode/test-web, which uses the browser and the
// workbench steps only).
'use strict';

const { spawn, spawnSync } = require('child_process');
const fs = require('fs');
const http = require('http');
const net = require('net');
const os = require('os');
const path = require('path');

const HERE = __dirname;
const CODE_SERVER = path.join(HERE, 'node_modules', '.bin', 'code-server');

/** log(msg) to stderr with the seconds since the start; timed(name, fn) also records fn's seconds in timings. */
function stopwatch() {
  const t0 = Date.now();
  const timings = {};
  const log = (msg) => process.stderr.write(`[${((Date.now() - t0) / 1000).toFixed(1)}s] ${msg}\n`);
  const timed = async (name, fn) => {
    const start = Date.now();
    log(`${name}…`);
    try {
      return await fn();
    } finally {
      timings[name] = +((Date.now() - start) / 1000).toFixed(2);
    }
  };
  const total = () => +((Date.now() - t0) / 1000).toFixed(2);
  return { log, timed, timings, total };
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

/** Debian's Chromium (or $CHROMIUM) through playwright-core, headless: { browser, page }, the page 1400×900. */
async function openBrowser({ timed, log }) {
  const { chromium } = require(path.join(HERE, 'node_modules', 'playwright-core'));
  const browser = await timed('start chromium', () =>
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
  // the clipboard, for reading an editor's whole text (workbench().editorText)
  const context = await browser.newContext({ viewport: { width: 1400, height: 900 }, permissions: ['clipboard-read', 'clipboard-write'] });
  const page = await context.newPage();
  page.on('pageerror', (e) => log(`page error: ${e.message}`));
  return { browser, page };
}

/** Opens the workbench at url and waits for it and its Explorer. */
async function loadWorkbench(page, url, timed) {
  await timed('load workbench', async () => {
    await page.goto(url, { waitUntil: 'domcontentloaded' });
    await page.waitForSelector('.monaco-workbench', { timeout: 60000 });
    await page.waitForSelector('.explorer-folders-view, .explorer-viewlet', { timeout: 60000 });
  });
}

/**
 * Installs the .vsix into a fresh code-server with these user settings (added to the quiet ones
 * below), starts it on `workspace` and opens the workbench in Chromium. Returns { page, userDir,
 * close() }; close() ends Chromium and code-server's whole process group and copies code-server's
 * logs to out/code-server-logs.
 */
async function openCodeServer({ vsix, workspace, out, settings, timed, log }) {
  fs.mkdirSync(out, { recursive: true });
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
        ...settings,
      },
      null,
      2,
    ),
  );

  const env = { ...process.env, HOME: tmp, XDG_CONFIG_HOME: path.join(tmp, 'config'), XDG_DATA_HOME: path.join(tmp, 'data') };
  delete env.VSCODE_IPC_HOOK_CLI;

  await timed('install extension', async () => {
    const r = spawnSync(CODE_SERVER, ['--install-extension', vsix, '--extensions-dir', extDir, '--user-data-dir', userDir], {
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
  const serverLog = fs.openSync(path.join(out, 'code-server.log'), 'w');
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
      workspace,
    ],
    { env, detached: true, stdio: ['ignore', serverLog, serverLog] },
  );
  process.on('exit', () => {
    try {
      process.kill(-server.pid, 'SIGKILL');
    } catch {}
  });

  let browser;
  const close = async () => {
    if (browser) await browser.close().catch(() => undefined);
    try {
      process.kill(-server.pid, 'SIGTERM');
    } catch {}
    await new Promise((r) => setTimeout(r, 500));
    try {
      process.kill(-server.pid, 'SIGKILL');
    } catch {}
    // the extension host logs are the first place to look when a step fails
    try {
      fs.cpSync(path.join(userDir, 'logs'), path.join(out, 'code-server-logs'), { recursive: true });
    } catch {}
    fs.rmSync(tmp, { recursive: true, force: true });
  };

  try {
    await timed('start code-server', () =>
      waitFor('code-server to answer', async () => (await get(`http://127.0.0.1:${port}/healthz`)) === 200, 60000),
    );
    let page;
    ({ browser, page } = await openBrowser({ timed, log }));
    await loadWorkbench(page, `http://127.0.0.1:${port}/?folder=${encodeURIComponent(workspace)}`, timed);
    return { page, userDir, close };
  } catch (err) {
    await close();
    throw err;
  }
}

/** What a person does in the workbench: open a file, run a command by its title, hover a word, fix, simulate, read. */
function workbench(page) {
  // the text box of Quick Open and the command palette (its list rows may hold checkboxes too)
  const quickInput = page.locator('.quick-input-widget .quick-input-box input');

  // the editor of the file `name` is the active one
  const shown = async (name) => {
    await page.locator(`.tab.active[aria-label^="${name}"], .tab.active:has-text("${name}")`).first().waitFor({ timeout: 15000 });
    await page.locator('.monaco-editor .view-lines').first().waitFor({ timeout: 15000 });
  };

  const openFile = async (name) => {
    await page.locator('.monaco-workbench').click({ position: { x: 700, y: 400 } }).catch(() => undefined);
    await page.keyboard.press('Control+P');
    await quickInput.waitFor({ state: 'visible', timeout: 15000 });
    await quickInput.fill(name);
    const row = page.locator('.quick-input-widget .monaco-list-row', { hasText: name }).first();
    await row.waitFor({ state: 'visible', timeout: 15000 });
    await row.click();
    await shown(name);
  };

  // a file of the workspace's top folder, by a double click on its row in the Explorer
  const openFromExplorer = async (name) => {
    const row = page.locator('.explorer-folders-view .monaco-list-row', { hasText: name }).first();
    await row.waitFor({ state: 'visible', timeout: 15000 });
    await row.dblclick();
    await shown(name);
  };

  const runCommand = async (title) => {
    await page.keyboard.press('F1');
    await quickInput.waitFor({ state: 'visible', timeout: 15000 });
    await quickInput.fill(`>${title}`);
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

  // the Problems panel's rows once one of them matches
  const problems = async (pattern, timeoutMs) => {
    await page.keyboard.press('Control+Shift+M');
    return waitFor('the diagnostic in the Problems panel', async () => {
      const rows = await page.locator('.markers-panel .monaco-list-row').allInnerTexts();
      return rows.some((r) => pattern.test(r)) ? rows : false;
    }, timeoutMs);
  };

  // the Problems panel once it is empty
  const noProblems = () =>
    waitFor('an empty Problems panel', async () => {
      const text = await page.locator('.markers-panel').innerText().catch(() => '');
      const rows = await page.locator('.markers-panel .monaco-list-row').allInnerTexts();
      return rows.length === 0 && /No problems/i.test(text) ? text.trim() : false;
    }, 30000);

  // Find and Replace in the active editor, Replace All
  const replaceAll = async (find, replacement) => {
    await page.locator('.monaco-editor .view-lines').first().click({ position: { x: 5, y: 5 } });
    await page.keyboard.press('Control+H');
    const box = page.locator('.find-widget .find-part textarea').first();
    await box.waitFor({ state: 'visible', timeout: 15000 });
    await box.fill(find);
    await page.locator('.find-widget .replace-part textarea').first().fill(replacement);
    await page.keyboard.press('Control+Alt+Enter');
    await page.keyboard.press('Escape');
  };

  const languageMode = () =>
    waitFor('the ladder language mode', async () => {
      const text = (await page.locator('.statusbar [id="status.editor.mode"]').innerText().catch(() => '')) || '';
      return /ladder/i.test(text) ? text.trim() : false;
    }, 30000);

  const statusBar = () => page.locator('.statusbar').innerText();

  const startSimulation = async () => {
    await runCommand('Ladder: Start Simulation');
    await waitFor('the status bar to show the simulation', async () => /scan\s+\d+/.test(await statusBar()), 30000);
  };

  // an input's code lens ("Xstart = 0") clicked, until it reads the other value
  const toggleWithLens = async (name) => {
    const lens = page.locator('.contentWidgets .codelens-decoration a', { hasText: `${name} = 0` }).first();
    await lens.waitFor({ state: 'visible', timeout: 20000 });
    await lens.click();
    await page.locator('.contentWidgets .codelens-decoration a', { hasText: `${name} = 1` }).first().waitFor({ timeout: 20000 });
  };

  // F10 in the editor: the status bar's "Sim … scan N" once N has advanced
  const scanWithF10 = async () => {
    const scanBefore = Number((/scan\s+(\d+)/.exec(await statusBar()) || [])[1]);
    await page.locator('.monaco-editor .view-lines').first().click({ position: { x: 5, y: 5 } });
    await page.keyboard.press('F10');
    return waitFor('the scan count to advance', async () => {
      const m = /Sim[^\n]*scan\s+(\d+)/.exec(await statusBar());
      return m && Number(m[1]) > scanBefore ? m[0] : false;
    }, 20000);
  };

  // the texts painted in the theme's textladder.energizedForeground (Default Dark Modern: #ff4040)
  const energized = () =>
    page.evaluate(() => {
      const probe = document.createElement('span');
      probe.style.color = 'var(--vscode-textladder-energizedForeground)';
      document.querySelector('.monaco-workbench').appendChild(probe);
      const red = getComputedStyle(probe).color;
      probe.remove();
      const out = [];
      for (const s of document.querySelectorAll('.monaco-editor .view-lines .view-line span span')) {
        const text = s.textContent.replace(/\u00a0/g, ' ');
        if (getComputedStyle(s).color === red && text.trim()) out.push(text);
      }
      return out;
    });

  // energized() once it has a text that passes `has`
  const energizedUntil = (has) =>
    waitFor('red (energized) text in the editor', async () => {
      const texts = await energized();
      return texts.some(has) ? texts : false;
    }, 20000);

  // Shift+F5 in the editor, until no element is painted red
  const stopSimulation = async () => {
    await page.locator('.monaco-editor .view-lines').first().click({ position: { x: 5, y: 5 } });
    await page.keyboard.press('Shift+F5');
    await waitFor('the red elements to go', async () => (await energized()).length === 0, 15000);
  };

  // a hover's text on `word`, then the hover dismissed
  const hover = async (word) => {
    await hoverName(word);
    const text = await hoverText();
    await page.mouse.move(5, 5);
    await page.keyboard.press('Escape');
    return text;
  };

  // Ctrl+Space with the cursor inside `word` (clicked): the suggestions' rows, the list left open
  const suggestions = async (word) => {
    await page.locator('.monaco-editor .view-lines span span', { hasText: new RegExp(`^${word}$`) }).first().click();
    await page.keyboard.press('Control+Space');
    return waitFor('the suggestions', async () => {
      const texts = await page.locator('.suggest-widget .monaco-list-row').allInnerTexts();
      return texts.length > 0 ? texts.map((t) => t.replace(/\s+/g, ' ').trim()) : false;
    }, 15000);
  };

  // the suggestion whose label is `label`, clicked: its edits applied
  const acceptSuggestion = async (label) => {
    const name = page.locator('.label-name', { hasText: new RegExp(`^${label}$`) });
    const row = page.locator('.suggest-widget .monaco-list-row', { has: name }).first();
    await row.click();
    await page.locator('.suggest-widget .monaco-list-row').first().waitFor({ state: 'hidden', timeout: 15000 });
  };

  // a notification's text once one matches pattern
  const toast = (pattern) =>
    waitFor(`a notification matching ${pattern}`, async () => {
      const toasts = await page.locator('.notifications-toasts .notification-toast').allInnerTexts();
      const hit = toasts.find((t) => pattern.test(t));
      return hit ? hit.replace(/\s+/g, ' ').trim() : false;
    }, 60000);

  // the button `label` of the notification that matches pattern, clicked
  const toastButton = async (pattern, label) => {
    const t = page.locator('.notifications-toasts .notification-toast', { hasText: pattern }).first();
    await t.locator('.monaco-button', { hasText: label }).first().click();
  };

  // the notification's text that says the extension wrote the file `name`
  const wroteName = (name) => new RegExp(`Ladder: .*wrote ${name.replace(/\./g, '\\.')}`);
  const wrote = (name) => toast(wroteName(name));

  // the file `name` the extension wrote, opened with its notification's Open: the editor's text
  const openWritten = async (name) => {
    await toastButton(wroteName(name), 'Open');
    await shown(name);
    return editorText();
  };

  // Ladder: Convert on the active editor, to the format whose row says `kind`: the notification that it wrote `name`
  const convert = async (kind, name) => {
    await runCommand('Ladder: Convert');
    const row = page.locator('.quick-input-widget .monaco-list-row', { hasText: kind }).first();
    await row.waitFor({ state: 'visible', timeout: 15000 });
    await row.click();
    return wrote(name);
  };

  // Ladder: Build HEX on the active editor: the notification that it wrote the image `name`
  const buildHex = async (name) => {
    await runCommand('Ladder: Build HEX');
    return wrote(name);
  };

  // the active editor focused from the keyboard (Ctrl+1: no notification or widget can be in the
  // way of a key), so that the commands that need an editor's focus are offered
  const focusEditor = async () => {
    await page.keyboard.press('Control+1');
    await page.locator('.part.editor .monaco-editor.focused').first().waitFor({ timeout: 5000 });
  };

  // Format Document on the active editor (the command palette offers it only while an editor has
  // the focus), until the lines shown change. Nothing touches the editor meanwhile: VS Code drops
  // formatting edits that arrive after the cursor moved. (Not the tab's modified mark: VS Code for
  // the Web saves after a delay by default.)
  const formatDocument = async () => {
    const lines = page.locator('.part.editor .monaco-editor .view-lines').first();
    const before = await lines.innerText();
    await focusEditor();
    await runCommand('Format Document');
    await waitFor('the formatted lines', async () => (await lines.innerText()) !== before, 15000);
  };

  // the active editor's whole text (Select All, Copy, the clipboard read), its cursor left at the start
  const editorText = async () => {
    await focusEditor();
    await page.keyboard.press('Control+A');
    await page.keyboard.press('Control+C');
    await page.keyboard.press('Control+Home');
    return page.evaluate(() => navigator.clipboard.readText());
  };

  // the text of an output channel once it matches pattern
  const output = async (channel, pattern) => {
    await runCommand('Output: Show Output Channels');
    const row = page.locator('.quick-input-widget .monaco-list-row', { hasText: new RegExp(`^${channel}$`) }).first();
    await row.waitFor({ state: 'visible', timeout: 15000 });
    await row.click();
    return waitFor(`the output of ${channel} to match ${pattern}`, async () => {
      const text = (await page.locator('.panel .monaco-editor .view-lines').first().innerText().catch(() => '')).replace(/\u00a0/g, ' ');
      return pattern.test(text) ? text : false;
    }, 15000);
  };

  // a program whose Xlamp should be Ylamp, opened by `open`: LD102 in Problems (after the server's
  // cold start), then Replace All fixes it and Problems empties; the screenshot shows the diagnostic
  const diagnoseAndFix = async (timed, result, open, shot) => {
    await timed('open the program with an error', open);
    result.languageId = await languageMode();
    result.problems = await timed('the diagnostic in the Problems panel', () => problems(/LD102/, 120000));
    await page.screenshot({ path: shot });
    result.fixed = await timed('fix it (Replace All Xlamp by Ylamp): the diagnostic goes', async () => {
      await replaceAll('Xlamp', 'Ylamp');
      return noProblems();
    });
  };

  return {
    quickInput, openFile, diagnoseAndFix, openFromExplorer, runCommand, hoverName, hoverText, problems, noProblems, replaceAll, languageMode, statusBar,
    startSimulation, toggleWithLens, scanWithF10, energized, energizedUntil, stopSimulation, hover, suggestions, acceptSuggestion,
    toast, convert, buildHex, openWritten, formatDocument, editorText, output,
  };
}

/** Runs a driver's steps, given an object they put their session in ({ page, close() }), and prints the
 * result as the one JSON line the pytest side reads: on a failure its error and a screenshot named
 * `shot` in `out`. The session is closed either way; the exit status is the outcome. */
async function report(result, steps, { out, shot, log, total }) {
  const opened = {};
  try {
    await steps(opened);
    result.ok = true;
  } catch (err) {
    result.error = String(err && err.stack ? err.stack : err);
    log(`FAILED: ${result.error}`);
    if (opened.session && opened.session.page) {
      const file = path.join(out, shot);
      await opened.session.page.screenshot({ path: file }).catch(() => undefined);
      result.screenshot = file;
    }
  } finally {
    if (opened.session) await opened.session.close();
  }
  result.timings.total = total();
  process.stdout.write(JSON.stringify(result) + '\n');
  process.exit(result.ok ? 0 : 1);
}

/** A driver's `--name value` arguments (and the bare `--flag`s named in `flags`, true when given);
 * each name of `required` must be given. */
function parseArgs(argv, required, flags = []) {
  const args = {};
  for (let i = 0; i < argv.length; i++) {
    const m = /^--([a-z-]+)$/.exec(argv[i]);
    if (!m) throw new Error(`unexpected argument ${argv[i]}`);
    if (flags.includes(m[1])) {
      args[m[1]] = true;
    } else if (argv[i + 1] === undefined) {
      throw new Error(`--${m[1]} needs a value`);
    } else {
      args[m[1]] = argv[++i];
    }
  }
  for (const k of required) {
    if (!args[k]) throw new Error(`missing --${k}`);
  }
  return args;
}

/** Runs a driver's `main`: an error thrown outside `report` (before the session opened) is printed
 * as the same JSON line, with `extra()`'s fields, and the exit status 1. */
function runDriver(main, extra = () => ({})) {
  main().catch((err) => {
    process.stderr.write(`${err && err.stack ? err.stack : err}\n`);
    process.stdout.write(JSON.stringify({ ok: false, error: String(err), ...extra() }) + '\n');
    process.exit(1);
  });
}

module.exports = { stopwatch, waitFor, freePort, openBrowser, loadWorkbench, openCodeServer, workbench, report, runDriver, parseArgs };
