// How the language server is started: `ladder lsp`, `<python> -m ladder lsp`, or a command from
// the settings.
import * as os from 'os';
import * as path from 'path';
import * as vscode from 'vscode';
import { Executable } from 'vscode-languageclient/node';

/** Expands `~`, `${workspaceFolder}`, `${userHome}` and `${env:NAME}` in a setting value. */
export function expandVariables(value: string): string {
  const folder = vscode.workspace.workspaceFolders?.[0]?.uri.fsPath ?? '';
  let out = value
    .replace(/\$\{workspaceFolder\}/g, folder)
    .replace(/\$\{userHome\}/g, os.homedir())
    .replace(/\$\{env:([^}]+)\}/g, (_m, name: string) => process.env[name] ?? '');
  if (out === '~' || out.startsWith('~/')) {
    out = path.join(os.homedir(), out.slice(1));
  }
  return out;
}

export interface ServerCommand {
  command: string;
  args: string[];
  /** where the command came from, for messages */
  source: string;
}

/** The server command from the settings, in order: `ladder.server.command`, `ladder.server.pythonPath`, default. */
export function serverCommand(config: vscode.WorkspaceConfiguration): ServerCommand {
  const cmd = (config.get<string[]>('server.command') ?? []).filter((part) => typeof part === 'string');
  if (cmd.length > 0 && cmd[0].trim() !== '') {
    const parts = cmd.map(expandVariables);
    return { command: parts[0], args: parts.slice(1), source: 'ladder.server.command' };
  }
  const python = (config.get<string>('server.pythonPath') ?? '').trim();
  if (python !== '') {
    return { command: expandVariables(python), args: ['-m', 'ladder', 'lsp'], source: 'ladder.server.pythonPath' };
  }
  return { command: 'ladder', args: ['lsp'], source: 'default' };
}

export function executable(cmd: ServerCommand): Executable {
  const folder = vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;
  return {
    command: cmd.command,
    args: cmd.args,
    options: folder ? { cwd: folder } : undefined,
  };
}

export function describe(cmd: ServerCommand): string {
  return [cmd.command, ...cmd.args].map((p) => (/\s/.test(p) ? JSON.stringify(p) : p)).join(' ');
}
