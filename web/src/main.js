// The playground page: CodeMirror 6 for the program, textladder's language server in a Web Worker
// (worker.js) for diagnostics, hover, simulation and the files to download.
import { Annotation, EditorState, StateEffect, StateField } from '@codemirror/state';
import { Decoration, EditorView, highlightActiveLine, hoverTooltip, keymap, lineNumbers } from '@codemirror/view';
import { defaultKeymap, history, historyKeymap, indentWithTab } from '@codemirror/commands';
import { forEachDiagnostic, lintGutter, setDiagnostics } from '@codemirror/lint';
import example from '../../examples/conveyor.ladder';
import { Client } from './lsp.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
// what the tests and the curious read: when the first diagnostics came, how long each edit took
// (docs/browser.md, "Cold start and speed"), the worker's start-up by stage
const timings = { firstDiagnosticsMs: null, edits: [], start: null };
const PLOT_SPAN_MS = 10000;
const PLOT_ROWS = 12;

const client = new Client(window.ladderWorker); // started by index.html
const doc = { uri: 'inmemory://playground/conveyor.ladder', languageId: 'ladder', version: 1 };
// version -> when its keystroke came and when the change was sent to the server
const editStarted = new Map();
let keyAt = null; // the keystroke being typed: its event's time
let listed = null; // the Problems list shown (showDiagnostics)
const loading = Annotation.define();
let simulation = null; // the last state while one runs
let plotted = []; // the states of the running simulation: {t, values}

// --- the editor ------------------------------------------------------------------------

const setEnergized = StateEffect.define();
const energizedMark = Decoration.mark({ class: 'cm-energized' });
const energized = StateField.define({
  create: () => Decoration.none,
  update(marks, tr) {
    marks = marks.map(tr.changes);
    for (const effect of tr.effects) {
      if (effect.is(setEnergized)) marks = effect.value;
    }
    return marks;
  },
  provide: (field) => EditorView.decorations.from(field),
});

function offset(state, position) {
  const lines = state.doc.lines;
  if (position.line >= lines) return state.doc.length;
  const line = state.doc.line(position.line + 1);
  return Math.min(line.from + position.character, line.to);
}

function position(state, at) {
  const line = state.doc.lineAt(at);
  return { line: line.number - 1, character: at - line.from };
}

const hover = hoverTooltip(async (view, pos) => {
  const result = await client.request('textDocument/hover', { textDocument: { uri: doc.uri }, position: position(view.state, pos) })
    .catch(() => null);
  if (!result) return null;
  const contents = result.contents;
  const text = typeof contents === 'string' ? contents : contents.value ?? contents.map((c) => c.value ?? c).join('\n\n');
  const from = result.range ? offset(view.state, result.range.start) : pos;
  const to = result.range ? offset(view.state, result.range.end) : pos;
  return {
    pos: from, end: to, above: true,
    create: () => {
      const dom = document.createElement('div');
      dom.className = 'hover';
      dom.textContent = text.replace(/```\w*\n?/g, '');
      return { dom };
    },
  };
});

// Sent before CodeMirror updates its view (dispatchTransactions), so the server starts on the
// change while the page draws it: the two threads work at the same time.
function sendChanges(transactions) {
  const changes = [];
  for (const tr of transactions) {
    if (tr.docChanged && !tr.annotation(loading)) changes.push(...changesOf(tr));
  }
  if (!changes.length) return;
  doc.version += 1;
  const sent = performance.now();
  const edit = { key: keyAt, sent, firstTask: null };
  editStarted.set(doc.version, edit);
  firstTaskProbe(edit);
  keyAt = null;
  client.notify('textDocument/didChange', { textDocument: { uri: doc.uri, version: doc.version }, contentChanges: changes });
}

// When the page can first run a task after the keystroke. After a key press Chromium runs none of
// the page's tasks (the worker's reply is one) before the frame that draws the typed letter
// (DeferRendererTasksAfterInput, docs/browser.md "The frame after a keystroke"): a message the
// page posts to itself with the change arrives then, the earliest any reply could be handled.
const probe = new MessageChannel();
const probed = [];
probe.port1.onmessage = () => {
  const edit = probed.shift();
  if (edit) edit.firstTask = performance.now();
};

function firstTaskProbe(edit) {
  probed.push(edit);
  probe.port2.postMessage(null);
}

function changesOf(tr) {
  const changes = [];
  // from the last to the first: each range is then still where it was in the document before
  tr.changes.iterChanges((fromA, toA, _fromB, _toB, inserted) => {
    changes.unshift({
      range: { start: position(tr.startState, fromA), end: position(tr.startState, toA) },
      text: inserted.toString(),
    });
  });
  return changes;
}

const view = new EditorView({
  parent: $('editor'),
  state: EditorState.create({
    doc: example,
    extensions: [lineNumbers(), history(), highlightActiveLine(), lintGutter(), hover, energized,
      keymap.of([...defaultKeymap, ...historyKeymap, indentWithTab]),
      EditorView.domEventHandlers({ keydown: (event) => { keyAt = event.timeStamp; }, keyup: () => { keyAt = null; } })],
  }),
  dispatchTransactions: (transactions, editor) => {
    sendChanges(transactions);
    editor.update(transactions);
  },
});

// --- diagnostics -------------------------------------------------------------------------

client.on('textDocument/publishDiagnostics', (published) => {
  if (published.uri !== doc.uri || (published.version != null && published.version !== doc.version)) return;
  const now = performance.now();
  if (timings.firstDiagnosticsMs === null) {
    timings.firstDiagnosticsMs = now;
    setStatus(`ready: first diagnostics ${(now / 1000).toFixed(1)} s after the page began to load`);
  }
  const edit = editStarted.get(published.version);
  editStarted.clear();
  showDiagnostics(published.diagnostics);
  if (edit) {
    // the diagnostics are in the page (the next frame paints them); from the keystroke, as the
    // person typing sees it, and from the change sent, which is what the native figure's wire measures
    const shown = performance.now();
    timings.edits.push({
      keyToShownMs: edit.key === null ? null : shown - edit.key, sentToReceivedMs: now - edit.sent,
      keyToFirstTaskMs: edit.key === null || edit.firstTask === null ? null : edit.firstTask - edit.key,
    });
  }
});

// An edit rarely changes the diagnostics: the underlines CodeMirror has moved with the text and
// the Problems list are redrawn only when the new ones differ, so that a reply costs the page
// almost nothing while the person types.
function showDiagnostics(diagnostics) {
  const state = view.state;
  const found = diagnostics.map((d) => ({
    from: offset(state, d.range.start), to: Math.max(offset(state, d.range.end), offset(state, d.range.start)),
    severity: d.severity === 1 ? 'error' : 'warning', message: d.message, source: d.code,
  }));
  if (!underlined(state, found)) view.dispatch(setDiagnostics(state, found));
  const lines = diagnostics.map((d) => `${d.range.start.line + 1}:${d.range.start.character + 1} ${d.code} ${d.message}`);
  const severities = diagnostics.map((d) => d.severity);
  const list = JSON.stringify([lines, severities]);
  if (list === listed) return;
  listed = list;
  $('problems').replaceChildren(...diagnostics.map((d, i) => {
    const item = document.createElement('li');
    item.textContent = lines[i];
    item.className = d.severity === 1 ? 'error' : 'warning';
    item.onclick = () => {
      view.dispatch({ selection: { anchor: offset(view.state, d.range.start) }, scrollIntoView: true });
      view.focus();
    };
    return item;
  }));
}

// whether the editor already shows exactly these diagnostics, where they are
function underlined(state, found) {
  const key = (d, from, to) => JSON.stringify([from, to, d.severity, d.message, d.source]);
  const shown = [];
  forEachDiagnostic(state, (d, from, to) => shown.push(key(d, from, to)));
  const wanted = found.map((d) => key(d, d.from, d.to));
  return shown.length === wanted.length && shown.sort().join('\n') === wanted.sort().join('\n');
}

client.on('window/showMessage', (p) => showMessage(p.message));
client.on('window/logMessage', (p) => {
  const started = /^ladder: started (\{.*\})$/.exec(p.message);
  if (started) timings.start = JSON.parse(started[1]);
  if (p.type === 1) console.error(p.message);
});

function setStatus(text) {
  $('status').textContent = text;
}

function showMessage(text) {
  $('message').textContent = text || '';
}

// --- simulation --------------------------------------------------------------------------

client.on('ladder/simulationState', (state) => {
  if (state.uri === doc.uri) showState(state);
});

function showState(state) {
  simulation = state.running ? state : null;
  const running = simulation !== null;
  $('sim-start').disabled = running;
  for (const id of ['sim-stop', 'sim-step', 'sim-run', 'sim-reset']) $(id).disabled = !running;
  $('sim-run').textContent = running && state.realtime ? 'Pause' : 'Run';
  const marks = running ? state.energized.map((r) => energizedMark.range(offset(view.state, r.start), offset(view.state, r.end)))
    .filter((m) => m.from < m.to) : [];
  view.dispatch({ effects: setEnergized.of(Decoration.set(marks, true)) });
  if (state.error) showMessage(`simulation stopped: ${state.error}`);
  const names = Object.keys(state.values || {}).sort();
  $('inputs').replaceChildren(...names.filter((n) => n.startsWith('X')).map((name) => {
    const button = document.createElement('button');
    button.textContent = name;
    button.dataset.name = name;
    button.className = state.values[name] ? 'on' : '';
    button.onclick = () => toggle(name);
    return button;
  }));
  $('values').replaceChildren(...names.map((name) => {
    const row = document.createElement('tr');
    row.dataset.name = name;
    const value = state.values[name];
    row.innerHTML = '<td></td><td></td>';
    row.cells[0].textContent = name;
    row.cells[1].textContent = String(value);
    if (value && /^[XYR]/.test(name)) row.cells[1].className = 'on';
    return row;
  }));
  $('sim-time').textContent = running ? `${(state.timeMs / 1000).toFixed(2)} s, scan ${state.scan}` : '';
  if (running) {
    plotted.push({ t: state.timeMs, values: state.values });
    while (plotted.length > 2 && plotted[0].t < state.timeMs - PLOT_SPAN_MS) plotted.shift();
  }
  plot();
}

function plot() {
  const svg = $('plot');
  const width = svg.clientWidth || 300;
  const height = svg.clientHeight || 150;
  const names = simulation ? Object.keys(simulation.values).filter((n) => /^[XYR]/.test(n)).sort().slice(0, PLOT_ROWS) : [];
  if (!names.length || !plotted.length) {
    svg.replaceChildren();
    return;
  }
  const label = 60;
  const end = plotted[plotted.length - 1].t;
  // the last ten seconds, or what there is of them (one second at least)
  const span = Math.min(PLOT_SPAN_MS, Math.max(end - plotted[0].t, 1000));
  const x = (t) => label + (width - label - 4) * (1 - (end - t) / span);
  const row = height / names.length;
  const parts = [];
  names.forEach((name, i) => {
    const y = (v) => i * row + (v ? 3 : row - 3);
    let d = '';
    let last = null;
    for (const { t, values } of plotted) {
      const v = values[name] ? 1 : 0;
      d += d ? ` H${x(t).toFixed(1)}` : `M${x(t).toFixed(1)} ${y(v)}`;
      if (last !== null && v !== last) d += ` V${y(v)}`;
      last = v;
    }
    parts.push(`<text x="2" y="${(i + 0.7) * row}">${name}</text><path d="${d}"/>`);
  });
  svg.innerHTML = parts.join('');
}

async function simCommand(name, ...args) {
  try {
    const state = await client.command(name, doc.uri, ...args);
    if (state && state.uri) showState(state);
    showMessage(simulation && simulation.error ? `simulation stopped: ${simulation.error}` : '');
  } catch (error) {
    showMessage(error.message);
  }
}

async function toggle(name) {
  await simCommand('ladder.sim.toggle', name);
  if (simulation && !simulation.realtime) await simCommand('ladder.sim.step', 1);
}

$('sim-start').onclick = async () => {
  plotted = [];
  await simCommand('ladder.sim.start');
  if (simulation) await simCommand('ladder.sim.runRealtime', true);
};
$('sim-stop').onclick = () => simCommand('ladder.sim.stop');
$('sim-step').onclick = () => simCommand('ladder.sim.step', 1);
$('sim-run').onclick = () => simCommand('ladder.sim.runRealtime', !(simulation && simulation.realtime));
$('sim-reset').onclick = () => {
  plotted = [];
  return simCommand('ladder.sim.reset');
};

// --- files -------------------------------------------------------------------------------

function open(name, text, languageId) {
  if (simulation) client.command('ladder.sim.stop', doc.uri).catch(() => {});
  client.notify('textDocument/didClose', { textDocument: { uri: doc.uri } });
  doc.uri = `inmemory://playground/${encodeURIComponent(name)}`;
  doc.languageId = languageId;
  doc.version = 1;
  plotted = [];
  showState({ running: false, energized: [], values: {} });
  view.dispatch({ changes: { from: 0, to: view.state.doc.length, insert: text }, annotations: loading.of(true) });
  client.notify('textDocument/didOpen', { textDocument: { uri: doc.uri, languageId, version: 1, text } });
}

$('open').onchange = async (event) => {
  const file = event.target.files[0];
  if (!file) return;
  const bytes = await file.arrayBuffer();
  const ld = /\.ld$/i.test(file.name);
  // an .ld file is in LDmicro's code page (ladder.encoding, cp1252 by default)
  open(file.name, new TextDecoder(ld ? 'windows-1252' : 'utf-8').decode(bytes), ld ? 'ldmicro' : 'ladder');
  event.target.value = '';
};

for (const button of document.querySelectorAll('[data-export]')) {
  button.onclick = async () => {
    try {
      const done = await client.command('ladder.export', doc.uri, button.dataset.export);
      for (const file of done.files) download(file.name, Uint8Array.from(atob(file.data), (c) => c.charCodeAt(0)));
      showMessage([done.summary, ...done.warnings].filter(Boolean).join('\n'));
    } catch (error) {
      showMessage(error.message);
    }
  };
}

function download(name, bytes) {
  const link = document.createElement('a');
  link.href = URL.createObjectURL(new Blob([bytes], { type: 'application/octet-stream' }));
  link.download = name;
  link.click();
  setTimeout(() => URL.revokeObjectURL(link.href), 10000);
}

// --- start -------------------------------------------------------------------------------

async function start() {
  client.listen();
  setStatus('loading Python and the language server…');
  await client.request('initialize', {
    processId: null, rootUri: null, clientInfo: { name: 'textladder playground' },
    capabilities: { textDocument: { hover: { contentFormat: ['plaintext', 'markdown'] },
      publishDiagnostics: { relatedInformation: false } } },
  });
  client.notify('initialized', {});
  if (params.has('delay')) {
    client.notify('workspace/didChangeConfiguration', { settings: { ladder: { diagnosticsDelayMs: Number(params.get('delay')) } } });
  }
  client.notify('textDocument/didOpen', { textDocument: { uri: doc.uri, languageId: doc.languageId, version: doc.version, text: view.state.doc.toString() } });
}

window.ladder = { view, client, timings, doc, open };
start().catch((error) => setStatus(`the language server did not start: ${error.message}`));
