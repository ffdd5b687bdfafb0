// The language server's worker entry (lsp/worker.py, started by src/server.js as the Web Worker
// starts it) on Pyodide under Node, from the built web/dist: a program with an error gets its
// diagnostic, the fixed program none; a simulation starts and an input toggled drives its output;
// ladder.export gives the HEX; ladder.build says what the browser cannot do. Then, with TIMED, the
// server's own time for edits on Pyodide, without a page: from each change taken to its diagnostics
// posted (docs/browser.md, "The frame after a keystroke").
//
//   node node_worker.mjs BAD.ladder FIXED.ladder INPUT OUTPUT [TIMED.json]
//     TIMED.json: {"open": [messages], "uri": URI, "warmUpMs": N, "edits": [didChange messages]}
//
// Prints one JSON object on its last line of stdout: {"ok": true, "timings": {...}, "hex": "..."};
// timings.editsMs has the milliseconds of each timed edit.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { startServer } from '../src/server.js';

const DIST = path.join(path.dirname(fileURLToPath(import.meta.url)), '..', 'dist');
const [badFile, fixedFile, input, output, timedFile] = process.argv.slice(2);
const URI = 'untitled:Untitled-1';
const t0 = performance.now();
const timings = {};
const waiting = new Map();
const notifications = [];
const published = new Map(); // "uri version" -> when its diagnostics were posted
let nextId = 1;
let take = null;

function received(text) {
  const message = JSON.parse(text);
  if (message.id !== undefined && !message.method) {
    waiting.get(message.id)(message);
    waiting.delete(message.id);
  } else if (message.method) {
    notifications.push(message);
    if (message.method === 'textDocument/publishDiagnostics') published.set(`${message.params.uri} ${message.params.version}`, performance.now());
  }
}

function request(method, params) {
  const id = nextId++;
  const answer = new Promise((resolve) => waiting.set(id, resolve));
  take(JSON.stringify({ jsonrpc: '2.0', id, method, params }));
  return answer;
}

function notify(method, params) {
  take(JSON.stringify({ jsonrpc: '2.0', method, params }));
}

async function diagnostics(version, uri = URI) {
  for (let i = 0; i < 2000; i++) {
    const found = notifications.find((m) => m.method === 'textDocument/publishDiagnostics' && m.params.uri === uri && m.params.version === version);
    if (found) return found.params.diagnostics;
    await new Promise((resolve) => setTimeout(resolve, 5));
  }
  throw new Error(`no diagnostics for version ${version}`);
}

function check(condition, what) {
  if (!condition) throw new Error(what);
}

// each edit from its message taken to its diagnostics posted, one after the other's diagnostics
async function timeEdits({ open, uri, warmUpMs, edits }) {
  for (const message of open) take(JSON.stringify(message));
  await diagnostics(1, uri);
  await new Promise((resolve) => setTimeout(resolve, warmUpMs));
  const times = [];
  for (const edit of edits) {
    const version = edit.params.textDocument.version;
    const start = performance.now();
    take(JSON.stringify(edit));
    await diagnostics(version, uri);
    times.push(+(published.get(`${uri} ${version}`) - start).toFixed(2));
  }
  return times;
}

async function main() {
  const { loadPyodide } = await import(path.join(DIST, 'pyodide', 'pyodide.mjs'));
  take = await startServer({
    loadPyodide, indexURL: path.join(DIST, 'pyodide') + path.sep, timings,
    site: new Uint8Array(fs.readFileSync(path.join(DIST, 'site.zip'))), post: received,
  });
  timings.startMs = performance.now() - t0;
  const init = await request('initialize', { processId: null, rootUri: null, capabilities: {} });
  check(init.result && init.result.capabilities.hoverProvider, `initialize: ${JSON.stringify(init)}`);
  notify('initialized', {});
  notify('textDocument/didOpen', { textDocument: { uri: URI, languageId: 'ladder', version: 1, text: fs.readFileSync(badFile, 'utf8') } });
  const bad = await diagnostics(1);
  timings.firstDiagnosticsMs = performance.now() - t0;
  check(bad.length === 1 && bad[0].code === 'LD102', `diagnostics of the bad program: ${JSON.stringify(bad)}`);
  notify('textDocument/didChange', { textDocument: { uri: URI, version: 2 }, contentChanges: [{ text: fs.readFileSync(fixedFile, 'utf8') }] });
  check((await diagnostics(2)).length === 0, 'the fixed program has diagnostics');
  const command = (name, ...args) => request('workspace/executeCommand', { command: name, arguments: [URI, ...args] });
  const started = await command('ladder.sim.start');
  check(started.result && started.result.values[output] === 0, `sim.start: ${JSON.stringify(started)}`);
  await command('ladder.sim.toggle', input);
  const stepped = (await command('ladder.sim.step', 1)).result;
  check(stepped.values[output] === 1 && stepped.energized.length > 0, `after toggling ${input}: ${JSON.stringify(stepped)}`);
  const exported = await command('ladder.export', 'hex');
  check(exported.result && exported.result.files.length === 1, `ladder.export: ${JSON.stringify(exported)}`);
  const build = await command('ladder.build');
  check(build.error && /in the browser/.test(build.error.message), `ladder.build: ${JSON.stringify(build)}`);
  if (timedFile) timings.editsMs = await timeEdits(JSON.parse(fs.readFileSync(timedFile, 'utf8')));
  const hex = Buffer.from(exported.result.files[0].data, 'base64').toString('ascii');
  console.log(JSON.stringify({ ok: true, timings, hex, buildMessage: build.error.message }));
  process.exit(0); // the server's timers (the idle collector) would keep Node running
}

main().catch((error) => {
  console.log(JSON.stringify({ ok: false, error: String(error.stack || error), timings }));
  process.exit(1);
});
