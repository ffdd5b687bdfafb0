// What a running simulation shows: energized elements painted red, the status-bar item, a lens
// per input to toggle it, a toggle link in the hover, and the watch view (with what the UART sent).
import * as vscode from 'vscode';
import {
  SimulationState,
  SimulationStore,
  formatTime,
  isLadderDocument,
  toRange,
  uriKey,
} from './state';

// ---------------------------------------------------------------- energized elements

export class EnergizedDecorations implements vscode.Disposable {
  private readonly type = vscode.window.createTextEditorDecorationType({
    color: new vscode.ThemeColor('textladder.energizedForeground'),
    backgroundColor: new vscode.ThemeColor('textladder.energizedBackground'),
    fontWeight: 'bold',
    overviewRulerColor: new vscode.ThemeColor('textladder.energizedForeground'),
    overviewRulerLane: vscode.OverviewRulerLane.Left,
    rangeBehavior: vscode.DecorationRangeBehavior.ClosedClosed,
  });
  private readonly subscriptions: vscode.Disposable[] = [];

  constructor(private readonly store: SimulationStore) {
    this.subscriptions.push(
      store.onDidChange((key) => this.refresh(key)),
      vscode.window.onDidChangeVisibleTextEditors(() => this.refresh()),
    );
  }

  refresh(key?: string): void {
    for (const editor of vscode.window.visibleTextEditors) {
      const editorKey = uriKey(editor.document.uri);
      if (key !== undefined && editorKey !== key) {
        continue;
      }
      const state = this.store.get(editorKey);
      editor.setDecorations(this.type, state ? state.energized.map(toRange) : []);
    }
  }

  dispose(): void {
    this.subscriptions.forEach((s) => s.dispose());
    this.type.dispose();
  }
}

// ---------------------------------------------------------------- status bar

export class SimulationStatusBar implements vscode.Disposable {
  private readonly item = vscode.window.createStatusBarItem('textladder.simulation', vscode.StatusBarAlignment.Left, 50);
  private readonly subscriptions: vscode.Disposable[] = [];
  private serverProblem: string | undefined;

  constructor(private readonly store: SimulationStore) {
    this.item.name = 'Ladder simulation';
    this.subscriptions.push(
      store.onDidChange(() => this.refresh()),
      vscode.window.onDidChangeActiveTextEditor(() => this.refresh()),
    );
    this.refresh();
  }

  /** Shows that the server could not be started (until it starts). */
  setServerProblem(message: string | undefined): void {
    this.serverProblem = message;
    this.refresh();
  }

  refresh(): void {
    const editor = vscode.window.activeTextEditor;
    const doc = isLadderDocument(editor?.document) ? editor!.document : undefined;
    const state = this.store.get(doc?.uri) ?? (doc ? undefined : this.store.running()[0]);
    this.item.backgroundColor = undefined;
    if (this.serverProblem) {
      this.item.text = '$(error) Ladder server';
      this.item.tooltip = this.serverProblem;
      this.item.command = 'textladder.restartServer';
      this.item.backgroundColor = new vscode.ThemeColor('statusBarItem.errorBackground');
      this.item.show();
      return;
    }
    if (state) {
      this.item.text = statusText(state);
      this.item.tooltip = statusTooltip(state);
      this.item.command = 'textladder.sim.actions';
      if (state.error) {
        this.item.backgroundColor = new vscode.ThemeColor('statusBarItem.warningBackground');
      }
      this.item.show();
    } else if (doc) {
      this.item.text = '$(debug-start) Simulate';
      this.item.tooltip = 'Start a simulation of this program (F5)';
      this.item.command = 'textladder.sim.start';
      this.item.show();
    } else {
      this.item.hide();
    }
  }

  dispose(): void {
    this.subscriptions.forEach((s) => s.dispose());
    this.item.dispose();
  }
}

export function statusText(state: SimulationState): string {
  const icon = state.error ? '$(warning)' : state.realtime ? '$(sync~spin)' : '$(debug-pause)';
  const mode = state.realtime ? 'running' : 'paused';
  const replay = state.replay ? ` · replay to ${formatTime(state.replay.endMs)}` : '';
  return `${icon} Sim ${mode} ${formatTime(state.timeMs)} · scan ${state.scan}${replay}`;
}

function statusTooltip(state: SimulationState): vscode.MarkdownString {
  const md = new vscode.MarkdownString();
  const name = vscode.Uri.parse(state.uri).path.split('/').pop();
  md.appendMarkdown(`**Simulation of ${name}**\n\n`);
  md.appendMarkdown(`time ${formatTime(state.timeMs)}, scan ${state.scan}, ${state.realtime ? 'running in real time' : 'paused'}\n\n`);
  if (state.error) {
    md.appendText(`error: ${state.error}\n\n`);
  }
  if (state.replay) {
    const { name, applied, total, endMs } = state.replay;
    md.appendText(`replaying the ${name}: ${applied} of its ${total} inputs applied; the scan at ${formatTime(endMs)} decides it\n\n`);
  }
  md.appendMarkdown('F10 one scan · F8 real time · F9 toggle input · Shift+F5 stop · click for more');
  return md;
}

// ---------------------------------------------------------------- inputs: lens and hover

/** The lines that hold the diagram (ladder) or the program (ldmicro): where input lenses go. */
function diagramLines(doc: vscode.TextDocument): [number, number] {
  let start = 0;
  let end = doc.lineCount;
  if (doc.languageId === 'ldmicro') {
    for (let i = 0; i < doc.lineCount; i++) {
      if (/^PROGRAM\s*$/.test(doc.lineAt(i).text)) {
        start = i + 1;
        break;
      }
    }
    return [start, end];
  }
  let inDiagram = false;
  for (let i = 0; i < doc.lineCount; i++) {
    const text = doc.lineAt(i).text;
    if (/^LADDER DIAGRAM\s*:/.test(text)) {
      inDiagram = true;
      start = i + 1;
    } else if (inDiagram && /^[A-Za-z/][^:|]*:\s*$/.test(text)) {
      end = i;
      break;
    }
  }
  return [start, end];
}

const NAME = /(?<![\w$])[A-Za-z_$][A-Za-z0-9_]*(?:\[[A-Za-z0-9_]+\])?/g;

export function isInput(name: string): boolean {
  return /^X/.test(name);
}

export class InputLenses implements vscode.CodeLensProvider, vscode.HoverProvider, vscode.Disposable {
  private readonly emitter = new vscode.EventEmitter<void>();
  readonly onDidChangeCodeLenses = this.emitter.event;
  private readonly subscriptions: vscode.Disposable[] = [];
  private lastSignature = '';

  constructor(private readonly store: SimulationStore) {
    this.subscriptions.push(
      store.onDidChange(() => {
        // realtime runs push ten states a second: refresh the lenses only when inputs change
        const sig = JSON.stringify(
          store.running().map((s) => [s.uri, Object.entries(s.values).filter(([k]) => isInput(k))]),
        );
        if (sig !== this.lastSignature) {
          this.lastSignature = sig;
          this.emitter.fire();
        }
      }),
      vscode.workspace.onDidChangeConfiguration((e) => {
        if (e.affectsConfiguration('ladder.simulation.codeLens')) {
          this.emitter.fire();
        }
      }),
    );
  }

  provideCodeLenses(doc: vscode.TextDocument): vscode.CodeLens[] {
    const state = this.store.get(doc.uri);
    if (!state || !vscode.workspace.getConfiguration('ladder', doc).get<boolean>('simulation.codeLens', true)) {
      return [];
    }
    const lenses: vscode.CodeLens[] = [];
    const [start, end] = diagramLines(doc);
    for (let i = start; i < end; i++) {
      const text = doc.lineAt(i).text;
      if (/^\s*[0-9]*\|[|+]\s*;/.test(text)) {
        continue; // a comment line
      }
      for (const m of text.matchAll(NAME)) {
        const name = m[0];
        if (!isInput(name) || !(name in state.values)) {
          continue;
        }
        const value = state.values[name];
        const range = new vscode.Range(i, m.index!, i, m.index! + name.length);
        lenses.push(
          new vscode.CodeLens(range, {
            title: `${value ? '$(circle-filled)' : '$(circle-outline)'} ${name} = ${value} ⇄`,
            tooltip: `Toggle the input ${name}`,
            command: 'textladder.sim.toggle',
            arguments: [name, doc.uri.toString()],
          }),
        );
      }
    }
    return lenses;
  }

  provideHover(doc: vscode.TextDocument, position: vscode.Position): vscode.Hover | undefined {
    const state = this.store.get(doc.uri);
    if (!state) {
      return undefined;
    }
    const range = doc.getWordRangeAtPosition(position, /[A-Za-z_$][A-Za-z0-9_]*/);
    if (!range) {
      return undefined;
    }
    const name = doc.getText(range);
    if (!(name in state.values)) {
      return undefined;
    }
    const args = encodeURIComponent(JSON.stringify([name, doc.uri.toString()]));
    const md = new vscode.MarkdownString(`Simulation: \`${name}\` = **${state.values[name]}**`);
    if (isInput(name)) {
      md.appendMarkdown(` — [Toggle ${name}](command:textladder.sim.toggle?${args} "Toggle the input")`);
    } else {
      md.appendMarkdown(` — [Set…](command:textladder.sim.set?${args} "Set a value")`);
    }
    md.isTrusted = { enabledCommands: ['textladder.sim.toggle', 'textladder.sim.set'] };
    return new vscode.Hover(md, range);
  }

  dispose(): void {
    this.subscriptions.forEach((s) => s.dispose());
    this.emitter.dispose();
  }
}

// ---------------------------------------------------------------- watch view

const GROUPS: [string, string, RegExp][] = [
  ['X', 'Inputs (X)', /^X/],
  ['Y', 'Outputs (Y)', /^Y/],
  ['R', 'Relays (R)', /^R/],
  ['T', 'Timers (T)', /^T/],
  ['C', 'Counters (C)', /^C/],
  ['A', 'ADC inputs (A)', /^A/],
  ['P', 'PWM outputs (P)', /^P/],
  ['other', 'Variables', /./],
];

/** What the UART sent: the server's byte count and its last messages, each as `ladder sim --watch uart` prints it. */
export interface UartState {
  sent: number;
  messages: { timeMs: number; text: string }[];
}

export function uartOf(state: SimulationState): UartState {
  return (state as SimulationState & { uart?: UartState }).uart ?? { sent: 0, messages: [] };
}

const UART_GROUP = 'uart';

export class WatchItem extends vscode.TreeItem {
  constructor(
    readonly kind: 'group' | 'value' | 'message',
    readonly key: string,
    label: string,
    readonly uri: string,
    value?: number,
  ) {
    super(label, kind === 'group' ? vscode.TreeItemCollapsibleState.Expanded : vscode.TreeItemCollapsibleState.None);
    this.id = `${uri}#${kind}:${key}`;
    if (kind === 'message') {
      this.iconPath = new vscode.ThemeIcon('output');
    }
    if (kind === 'value') {
      this.description = String(value);
      const bit = isInput(key);
      this.contextValue = bit ? 'bit' : 'value';
      this.iconPath = new vscode.ThemeIcon(value ? 'circle-filled' : 'circle-outline',
        value ? new vscode.ThemeColor('textladder.energizedForeground') : undefined);
      this.tooltip = bit ? `${key} = ${value} (click to toggle)` : `${key} = ${value}`;
      if (bit) {
        this.command = { command: 'textladder.sim.toggle', title: 'Toggle', arguments: [key, uri] };
      }
    }
  }
}

export class WatchView implements vscode.TreeDataProvider<WatchItem>, vscode.Disposable {
  private readonly emitter = new vscode.EventEmitter<WatchItem | undefined>();
  readonly onDidChangeTreeData = this.emitter.event;
  readonly view: vscode.TreeView<WatchItem>;
  private readonly subscriptions: vscode.Disposable[] = [];

  constructor(private readonly store: SimulationStore) {
    this.view = vscode.window.createTreeView('textladder.watch', { treeDataProvider: this, showCollapseAll: true });
    this.subscriptions.push(
      this.view,
      store.onDidChange(() => this.refresh()),
      vscode.window.onDidChangeActiveTextEditor(() => this.refresh()),
    );
    this.refresh();
  }

  private current(): SimulationState | undefined {
    const editor = vscode.window.activeTextEditor;
    return this.store.get(editor?.document.uri) ?? this.store.get(this.store.lastUri) ?? this.store.running()[0];
  }

  refresh(): void {
    const state = this.current();
    if (state) {
      const name = vscode.Uri.parse(state.uri).path.split('/').pop();
      this.view.message = undefined;
      this.view.description = `${name} · ${formatTime(state.timeMs)} · scan ${state.scan}`;
    } else {
      this.view.description = undefined;
      this.view.message = 'No simulation is running. Open a ladder program and run "Ladder: Start Simulation" (F5).';
    }
    this.emitter.fire(undefined);
  }

  getTreeItem(item: WatchItem): vscode.TreeItem {
    return item;
  }

  getChildren(item?: WatchItem): WatchItem[] {
    const state = this.current();
    if (!state) {
      return [];
    }
    const names = Object.keys(state.values).sort((a, b) => a.localeCompare(b));
    const groupOf = (name: string) => GROUPS.find(([, , re]) => re.test(name))![0];
    const uart = uartOf(state);
    if (!item) {
      const groups = GROUPS.filter(([key]) => names.some((n) => groupOf(n) === key)).map(
        ([key, label]) => new WatchItem('group', key, label, state.uri),
      );
      if (uart.sent > 0) {
        const bytes = uart.sent === 1 ? '1 byte' : `${uart.sent} bytes`;
        groups.push(new WatchItem('group', UART_GROUP, `UART sent (${bytes})`, state.uri));
      }
      return groups;
    }
    if (item.kind !== 'group') {
      return [];
    }
    if (item.key === UART_GROUP) {
      // the latest message first, where the eye looks; its time as the description
      return uart.messages
        .map((m, i) => {
          const message = new WatchItem('message', `${m.timeMs}#${i}`, m.text, state.uri);
          message.description = formatTime(m.timeMs);
          message.tooltip = `${m.text}, its first byte sent at ${formatTime(m.timeMs)}`;
          return message;
        })
        .reverse();
    }
    return names
      .filter((n) => groupOf(n) === item.key)
      .map((n) => new WatchItem('value', n, n, state.uri, state.values[n]));
  }

  dispose(): void {
    this.subscriptions.forEach((s) => s.dispose());
    this.emitter.dispose();
  }
}
