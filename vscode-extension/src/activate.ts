// textladder for VS Code, on the desktop (extension.ts: `ladder lsp` as a process) and in the browser
// (web/extension.ts: the server on Pyodide in a Web Worker): the client, the simulation UI and the
// commands, the same in both. Each entry says how its server starts (Host).
import * as vscode from 'vscode';
import { BaseLanguageClient, ExecuteCommandRequest, LanguageClientOptions, State } from 'vscode-languageclient';
import {
  SimulationState,
  SimulationStore,
  formatTime,
  isLadderDocument,
  isSimulationState,
  parseDurationMs,
  uriKey,
} from './state';
import { EnergizedDecorations, InputLenses, SimulationStatusBar, WatchItem, WatchView, isInput } from './views';

/** A server the host can start: its name for messages, and the client that runs it. */
export interface Server {
  /** e.g. the command line, for "starting the language server: NAME (SOURCE)" */
  name: string;
  source: string;
  /** what to check when it does not start */
  hint: string;
  create(options: LanguageClientOptions): BaseLanguageClient;
}

/** Why no server can be started, for the notification. */
export interface NoServer {
  message: string;
  /** a page that offers what is missing (python.org's download page) */
  download?: string;
}

export interface Host {
  /** the documents the client serves */
  selector: vscode.DocumentSelector;
  findServer(log: (line: string) => void): Promise<Server | NoServer>;
  /**
   * true: the server writes converted and built files beside the document (ladder.convert,
   * ladder.build); false: it cannot (in a browser), and the client writes what ladder.export gives
   */
  serverWritesFiles: boolean;
}

let client: BaseLanguageClient | undefined;
let store: SimulationStore;
let statusBar: SimulationStatusBar;
let output: vscode.OutputChannel;
let host: Host;

export async function activateWith(context: vscode.ExtensionContext, given: Host): Promise<void> {
  host = given;
  output = vscode.window.createOutputChannel('Ladder');
  store = new SimulationStore();
  statusBar = new SimulationStatusBar(store);
  const lenses = new InputLenses(store);
  context.subscriptions.push(
    output,
    store,
    statusBar,
    new EnergizedDecorations(store),
    lenses,
    new WatchView(store),
    vscode.languages.registerCodeLensProvider(host.selector, lenses),
    vscode.languages.registerHoverProvider(host.selector, lenses),
  );
  void vscode.commands.executeCommand('setContext', 'textladder.active', true);

  const updateContext = () => {
    const doc = vscode.window.activeTextEditor?.document;
    const state = isLadderDocument(doc) ? store.get(doc.uri) : undefined;
    void vscode.commands.executeCommand('setContext', 'textladder.simRunning', state !== undefined);
    void vscode.commands.executeCommand('setContext', 'textladder.simRealtime', state?.realtime === true);
  };
  context.subscriptions.push(store.onDidChange(updateContext), vscode.window.onDidChangeActiveTextEditor(updateContext));
  updateContext();

  registerCommands(context);

  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration(async (e) => {
      // also after a start that found no Python: the new setting may name one
      if (e.affectsConfiguration('ladder.server') && starting) {
        output.appendLine('server settings changed: restarting the language server');
        await restartClient();
      }
    }),
    // a closed document's simulation ends on the server; its decorations go with it
    vscode.workspace.onDidCloseTextDocument((doc) => store.clear(doc.uri.toString())),
    vscode.workspace.onDidOpenTextDocument((doc) => onOpen(doc)),
  );
  vscode.workspace.textDocuments.forEach(onOpen);
}

/**
 * VS Code reads a file's first line only when no extension claims the file: `.txt` is plain
 * text, and a linker-script extension may claim `.ld`. LDmicro's files say what they are on their
 * first line, so their language is set here. The server starts with the first ladder document.
 */
function onOpen(doc: vscode.TextDocument): void {
  if (isLadderDocument(doc)) {
    void ensureClient();
    return;
  }
  const language = languageByFirstLine(doc);
  if (language) {
    void vscode.languages.setTextDocumentLanguage(doc, language);
  }
}

function languageByFirstLine(doc: vscode.TextDocument): string | undefined {
  const ext = doc.uri.path.toLowerCase().replace(/^.*(\.[^./]*)$/, '$1');
  if ((ext !== '.txt' && ext !== '.ld') || doc.lineCount === 0) {
    return undefined;
  }
  const first = doc.lineAt(0).text;
  if (/^LDmicro export text/.test(first)) {
    return 'ladder';
  }
  if (ext === '.ld' && /^LDmicro/.test(first)) {
    return 'ldmicro';
  }
  return undefined;
}

export async function deactivate(): Promise<void> {
  if (client) {
    await client.stop().catch(() => undefined);
    client = undefined;
  }
}

// ---------------------------------------------------------------- the client

let starting: Promise<void> | undefined;

/** Starts the client once (the first ladder document, or the first command, asks for it). */
function ensureClient(): Promise<void> {
  if (!starting) {
    starting = startClient();
  }
  return starting;
}

async function startClient(): Promise<void> {
  const server = await host.findServer((line) => output.appendLine(line));
  if ('message' in server) {
    output.appendLine(`no language server: ${server.message}`);
    // not awaited: a command waiting for the server must not wait for the notification's answer
    void reportServerProblem(server.message, server.message, server.download);
    return;
  }
  output.appendLine(`starting the language server: ${server.name} (${server.source})`);
  const clientOptions: LanguageClientOptions = {
    documentSelector: host.selector as LanguageClientOptions['documentSelector'],
    synchronize: { configurationSection: 'ladder' },
    outputChannel: output,
    initializationFailedHandler: (error) => {
      output.appendLine(`initialization failed: ${error instanceof Error ? error.message : String(error)}`);
      return false;
    },
  };
  const c = server.create(clientOptions);
  c.onNotification('ladder/simulationState', (state: SimulationState) => {
    if (isSimulationState(state)) {
      store.update(state);
      if (state.error) {
        void vscode.window.showWarningMessage(`Simulation: ${state.error}`);
      }
    }
  });
  c.onDidChangeState((e) => {
    if (e.newState === State.Stopped) {
      store.clearAll();
    }
  });
  client = c;
  try {
    await c.start();
    statusBar.setServerProblem(undefined);
  } catch (err) {
    const message = err instanceof Error ? err.message : String(err);
    output.appendLine(`could not start ${server.name}: ${message}`);
    void reportServerProblem(
      `The ladder language server did not start (${server.name}): ${message}`,
      `could not start the language server "${server.name}": ${message}. ${server.hint}`,
      undefined,
    );
  }
}

/** The status bar keeps the problem; the notification offers what fixes it. */
async function reportServerProblem(status: string, message: string, download: string | undefined): Promise<void> {
  statusBar.setServerProblem(status);
  const actions = [...(download ? ['Download Python'] : []), 'Open Settings', 'Show Log'];
  const choice = await vscode.window.showErrorMessage(`Ladder: ${message}`, ...actions);
  if (choice === 'Download Python') {
    void vscode.env.openExternal(vscode.Uri.parse(download!));
  } else if (choice === 'Open Settings') {
    void vscode.commands.executeCommand('workbench.action.openSettings', 'ladder.server');
  } else if (choice === 'Show Log') {
    output.show();
  }
}

async function restartClient(): Promise<void> {
  const old = client;
  client = undefined;
  store.clearAll();
  if (old) {
    await old.stop().catch(() => undefined);
  }
  starting = startClient();
  await starting;
}

// ---------------------------------------------------------------- commands

/** The document a simulation command is for: the active ladder editor, else the last simulated one. */
function targetUri(explicit?: unknown): string | undefined {
  if (typeof explicit === 'string' && explicit !== '') {
    return explicit;
  }
  if (explicit instanceof vscode.Uri) {
    return explicit.toString();
  }
  const doc = vscode.window.activeTextEditor?.document;
  if (isLadderDocument(doc)) {
    return doc.uri.toString();
  }
  const visible = vscode.window.visibleTextEditors.map((e) => e.document).find(isLadderDocument);
  return visible?.uri.toString() ?? store.lastUri;
}

async function execute(command: string, uri: string | undefined, ...args: unknown[]): Promise<unknown> {
  if (!uri) {
    void vscode.window.showWarningMessage('Ladder: open a ladder program (.ladder, or an LDmicro .ld/.txt) first.');
    return undefined;
  }
  await ensureClient();
  if (!client || !client.isRunning()) {
    void vscode.window.showErrorMessage('Ladder: the language server is not running (see the "Ladder" output).');
    return undefined;
  }
  try {
    const result = await client.sendRequest(ExecuteCommandRequest.type, { command, arguments: [uri, ...args] });
    if (isSimulationState(result)) {
      store.update(result);
    }
    return result;
  } catch (err) {
    const message = err instanceof Error ? err.message : String(err);
    void vscode.window.showErrorMessage(`Ladder: ${message}`);
    return undefined;
  }
}

/** Name and document from a command's arguments: a lens or hover passes (name, uri), the watch view a WatchItem. */
function nameArgs(args: unknown[]): { name?: string; uri?: string } {
  const [first, second] = args;
  if (first instanceof WatchItem) {
    return { name: first.key, uri: first.uri };
  }
  return {
    name: typeof first === 'string' ? first : undefined,
    uri: typeof second === 'string' ? second : undefined,
  };
}

function nameAtCursor(state: SimulationState | undefined): string | undefined {
  const editor = vscode.window.activeTextEditor;
  if (!editor || !state) {
    return undefined;
  }
  const range = editor.document.getWordRangeAtPosition(editor.selection.active, /[A-Za-z_$][A-Za-z0-9_]*/);
  const word = range ? editor.document.getText(range) : undefined;
  return word !== undefined && word in state.values ? word : undefined;
}

async function pickName(state: SimulationState | undefined, filter: (n: string) => boolean, title: string) {
  const names = Object.keys(state?.values ?? {}).filter(filter).sort();
  if (names.length === 0) {
    void vscode.window.showWarningMessage('Ladder: no simulation is running, or the program has no such names.');
    return undefined;
  }
  const picked = await vscode.window.showQuickPick(
    names.map((n) => ({ label: n, description: String(state!.values[n]) })),
    { title, placeHolder: 'name' },
  );
  return picked?.label;
}

function showReached(result: unknown, condition: string) {
  if (isSimulationState(result) && result.reached !== undefined) {
    if (result.reached) {
      void vscode.window.showInformationMessage(`Ladder: "${condition}" reached at ${formatTime(result.timeMs)} (scan ${result.scan}).`);
    } else {
      void vscode.window.showWarningMessage(`Ladder: "${condition}" not reached (stopped at ${formatTime(result.timeMs)}).`);
    }
  }
}

function registerCommands(context: vscode.ExtensionContext): void {
  const reg = (id: string, fn: (...args: unknown[]) => unknown) =>
    context.subscriptions.push(vscode.commands.registerCommand(id, fn));

  reg('textladder.sim.start', async (uri?: unknown) => {
    const target = targetUri(uri);
    const doc = vscode.workspace.textDocuments.find((d) => uriKey(d.uri) === uriKey(target ?? ''));
    if (doc?.isDirty && doc.uri.scheme === 'file') {
      // the server simulates the text it has, saved or not; saving keeps the HEX in step
      await doc.save();
    }
    await execute('ladder.sim.start', target);
  });
  reg('textladder.sim.stop', async (uri?: unknown) => {
    const target = targetUri(uri);
    await execute('ladder.sim.stop', target);
    if (target) {
      store.clear(target);
    }
  });
  reg('textladder.sim.step', async (uri?: unknown) => execute('ladder.sim.step', targetUri(uri), 1));
  reg('textladder.sim.stepN', async () => {
    const text = await vscode.window.showInputBox({
      title: 'Simulate N scans',
      prompt: 'Number of scans',
      value: '10',
      validateInput: (v) => (/^\s*[1-9][0-9]*\s*$/.test(v) ? undefined : 'a whole number of scans, 1 or more'),
    });
    if (text !== undefined) {
      await execute('ladder.sim.step', targetUri(), parseInt(text, 10));
    }
  });
  reg('textladder.sim.runFor', async () => {
    const text = await vscode.window.showInputBox({
      title: 'Run the simulation for…',
      prompt: 'Simulated time: 500 (ms), 500ms, 2.5 s, 1 min',
      value: '1 s',
      validateInput: (v) => (parseDurationMs(v) !== undefined ? undefined : 'a duration such as 250 ms or 2 s'),
    });
    const ms = text !== undefined ? parseDurationMs(text) : undefined;
    if (ms !== undefined) {
      await execute('ladder.sim.runFor', targetUri(), ms);
    }
  });
  reg('textladder.sim.runRealtime', async (on?: unknown) => {
    const target = targetUri();
    const state = store.get(target);
    const turnOn = typeof on === 'boolean' ? on : !(state?.realtime ?? false);
    await execute('ladder.sim.runRealtime', target, turnOn);
  });
  reg('textladder.sim.runUntil', async () => {
    const condition = await vscode.window.showInputBox({
      title: 'Run the simulation until…',
      prompt: 'Condition, e.g. Yred = 1 or Ccount >= 3',
      placeHolder: 'Ymotor = 1',
    });
    if (condition) {
      const result = await execute('ladder.sim.runUntil', targetUri(), condition, 60000);
      showReached(result, condition);
    }
  });
  reg('textladder.sim.reset', async () => execute('ladder.sim.reset', targetUri()));
  reg('textladder.sim.toggle', async (...args: unknown[]) => {
    const given = nameArgs(args);
    const target = targetUri(given.uri);
    const state = store.get(target);
    const name = given.name ?? nameAtCursor(state) ?? (await pickName(state, isInput, 'Toggle an input'));
    if (name) {
      await execute('ladder.sim.toggle', target, name);
    }
  });
  reg('textladder.sim.set', async (...args: unknown[]) => {
    const given = nameArgs(args);
    const target = targetUri(given.uri);
    const state = store.get(target);
    const name = given.name ?? nameAtCursor(state) ?? (await pickName(state, () => true, 'Set an input or variable'));
    if (!name) {
      return;
    }
    const text = await vscode.window.showInputBox({
      title: `Set ${name}`,
      prompt: 'Integer value',
      value: String(state?.values[name] ?? 0),
      validateInput: (v) => (/^\s*[-+]?(0x[0-9a-f]+|[0-9]+)\s*$/i.test(v) ? undefined : 'an integer'),
    });
    if (text !== undefined) {
      await execute('ladder.sim.set', target, name, Number(text.trim()));
    }
  });
  reg('textladder.sim.actions', async () => {
    const state = store.get(targetUri());
    const items: (vscode.QuickPickItem & { command: string })[] = state
      ? [
          { label: '$(debug-step-over) One scan', description: 'F10', command: 'textladder.sim.step' },
          { label: '$(debug-step-over) N scans…', command: 'textladder.sim.stepN' },
          { label: '$(watch) Run for…', command: 'textladder.sim.runFor' },
          { label: '$(debug-continue) Run until…', command: 'textladder.sim.runUntil' },
          {
            label: state.realtime ? '$(debug-pause) Pause real time' : '$(play) Run in real time',
            description: 'F8',
            command: 'textladder.sim.runRealtime',
          },
          { label: '$(arrow-swap) Toggle an input…', description: 'F9', command: 'textladder.sim.toggle' },
          { label: '$(edit) Set a value…', command: 'textladder.sim.set' },
          { label: '$(debug-restart) Reset', description: 'Ctrl+Shift+F5', command: 'textladder.sim.reset' },
          { label: '$(debug-stop) Stop', description: 'Shift+F5', command: 'textladder.sim.stop' },
        ]
      : [{ label: '$(debug-start) Start simulation', description: 'F5', command: 'textladder.sim.start' }];
    const picked = await vscode.window.showQuickPick(items, { title: 'Ladder simulation' });
    if (picked) {
      await vscode.commands.executeCommand(picked.command);
    }
  });
  reg('textladder.convert', async (uri?: unknown) => {
    const target = targetUri(uri);
    if (!target) {
      return execute('ladder.convert', undefined);
    }
    const fromLd = vscode.Uri.parse(target).path.toLowerCase().endsWith('.ld');
    const picked = await vscode.window.showQuickPick(
      [
        { label: '.ladder', description: 'text form', target: 'ladder' },
        { label: '.ld', description: "LDmicro's own format", target: 'ld' },
      ].sort((a) => ((a.target === 'ladder') === fromLd ? -1 : 1)),
      { title: 'Convert to' },
    );
    if (!picked) {
      return undefined;
    }
    if (!host.serverWritesFiles) {
      return writeExported(target, picked.target);
    }
    const result = (await execute('ladder.convert', target, picked.target)) as { path?: string } | undefined;
    if (result?.path) {
      const open = await vscode.window.showInformationMessage(`Ladder: wrote ${result.path}`, 'Open');
      if (open) {
        await vscode.window.showTextDocument(vscode.Uri.file(result.path));
      }
    }
    return result;
  });
  reg('textladder.build', async (uri?: unknown) => {
    const target = targetUri(uri);
    if (!host.serverWritesFiles) {
      return vscode.window.withProgress({ location: vscode.ProgressLocation.Notification, title: 'Ladder: building…' }, () =>
        writeExported(target, 'hex'),
      );
    }
    const result = (await vscode.window.withProgress(
      { location: vscode.ProgressLocation.Notification, title: 'Ladder: building…' },
      () => execute('ladder.build', target),
    )) as { ok?: boolean; summary?: string; hex?: string } | undefined;
    if (result?.ok) {
      void vscode.window.showInformationMessage(`Ladder: ${result.summary ?? 'built'}${result.hex ? ` → ${result.hex}` : ''}`);
    } else if (result) {
      void vscode.window.showErrorMessage(`Ladder: build failed${result.summary ? `: ${result.summary}` : ''}`);
    }
    return result;
  });
  reg('textladder.restartServer', async () => restartClient());
}

interface Exported {
  files: { name: string; data: string }[];
  summary: string;
  warnings: string[];
}

/**
 * In the browser the server writes nothing (lsp/worker_files.py): ladder.export gives the files,
 * written here through the workspace's file system beside the document, or, for a document that
 * has no folder (untitled), the first one opened as a new untitled editor.
 */
async function writeExported(uri: string | undefined, target: string): Promise<Exported | undefined> {
  const result = (await execute('ladder.export', uri, target)) as Exported | undefined;
  if (!result || !uri) {
    return result;
  }
  const document = vscode.Uri.parse(uri);
  for (const warning of result.warnings) {
    output.appendLine(`${target}: ${warning}`);
  }
  const summary = result.summary ? `${result.summary}: ` : '';
  if (document.scheme === 'untitled') {
    const first = result.files[0];
    const opened = await vscode.workspace.openTextDocument({
      content: new TextDecoder(target === 'ld' ? 'windows-1252' : 'utf-8').decode(fromBase64(first.data)),
      language: target === 'ladder' ? 'ladder' : target === 'ld' ? 'ldmicro' : undefined,
    });
    await vscode.window.showTextDocument(opened);
    void vscode.window.showInformationMessage(`Ladder: ${summary}${first.name} opened as a new, unsaved editor`);
    return result;
  }
  const folder = vscode.Uri.joinPath(document, '..');
  const written = [];
  for (const file of result.files) {
    const into = vscode.Uri.joinPath(folder, file.name);
    await vscode.workspace.fs.writeFile(into, fromBase64(file.data));
    written.push(into);
  }
  const names = written.map((u) => u.path.split('/').pop()).join(', ');
  const open = await vscode.window.showInformationMessage(`Ladder: ${summary}wrote ${names}`, 'Open');
  if (open) {
    await vscode.window.showTextDocument(written[0]);
  }
  return result;
}

function fromBase64(data: string): Uint8Array {
  return Uint8Array.from(atob(data), (c) => c.charCodeAt(0));
}
