// How the language server is started: the command of `ladder.server.command`, or the server bundled
// in the extension (bundled/tool/lsp_server.py) run by a Python found as src/python.ts describes.
import * as fs from 'fs';
import * as os from 'os';
import * as path from 'path';
import * as vscode from 'vscode';
import { Executable } from 'vscode-languageclient/node';
import {
  Candidate,
  PythonExtensionApi,
  describeCandidate,
  findPython,
  interpreterOfPythonExtension,
  noPythonMessage,
  pathCandidates,
  probePython,
  resolveProgram,
} from './python';

/** Expands `~`, `${workspaceFolder}`, `${userHome}` and `${env:NAME}` in a setting value. */
export function expandVariables(value: string): string {
  const folder = vscode.workspace.workspaceFolders?.[0]?.uri.fsPath ?? '';
  let out = value
    .replace(/\$\{workspaceFolder\}/g, folder)
    .replace(/\$\{userHome\}/g, os.homedir())
    .replace(/\$\{env:([^}]+)\}/g, (_m, name: string) => process.env[name] ?? '');
  if (out === '~' || out.startsWith('~/') || out.startsWith('~\\')) {
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

/** Why no server can be started, for the notification. */
export interface NoServer {
  message: string;
  /** offer python.org's download page */
  download: boolean;
}

function isExecutableFile(p: string): boolean {
  try {
    if (!fs.statSync(p).isFile()) {
      return false;
    }
    if (process.platform !== 'win32') {
      fs.accessSync(p, fs.constants.X_OK);
    }
    return true;
  } catch {
    return false;
  }
}

/** The interpreter selected in the Python extension (ms-python.python), when it is installed. */
async function pythonExtensionCandidate(log: (line: string) => void): Promise<Candidate | undefined> {
  const ext = vscode.extensions.getExtension<PythonExtensionApi>('ms-python.python');
  if (!ext) {
    return undefined;
  }
  try {
    const api = ext.isActive ? ext.exports : await ext.activate();
    return await interpreterOfPythonExtension(api, vscode.workspace.workspaceFolders?.[0]?.uri);
  } catch (err) {
    log(`the Python extension gave no interpreter: ${err instanceof Error ? err.message : String(err)}`);
    return undefined;
  }
}

/**
 * The server to start, in order: `ladder.server.command` as it is; otherwise the bundled server run
 * by `ladder.server.pythonPath` alone when it is set, else by the first suitable of the Python
 * extension's interpreter and those on PATH.
 */
export async function serverCommand(
  config: vscode.WorkspaceConfiguration,
  extensionPath: string,
  log: (line: string) => void,
): Promise<ServerCommand | NoServer> {
  const cmd = (config.get<string[]>('server.command') ?? []).filter((part) => typeof part === 'string');
  if (cmd.length > 0 && cmd[0].trim() !== '') {
    const parts = cmd.map(expandVariables);
    return { command: parts[0], args: parts.slice(1), source: 'ladder.server.command' };
  }
  const script = path.join(extensionPath, 'bundled', 'tool', 'lsp_server.py');
  let requires: string;
  try {
    requires = JSON.parse(fs.readFileSync(path.join(extensionPath, 'bundled', 'tool', 'python.json'), 'utf8')).requiresPython;
  } catch {
    return {
      message: 'This copy of the extension carries no language server (bundled/ is missing: build it with `npm run package`), ' +
        'and the setting "ladder.server.command" is empty.',
      download: false,
    };
  }
  const env = process.env;
  const setting = (config.get<string>('server.pythonPath') ?? '').trim();
  let candidates: Candidate[];
  if (setting !== '') {
    const program = resolveProgram(expandVariables(setting), process.platform, env, isExecutableFile);
    candidates = [{ command: program, args: [], source: 'ladder.server.pythonPath' }];
  } else {
    const fromExtension = await pythonExtensionCandidate(log);
    candidates = [...(fromExtension ? [fromExtension] : []), ...pathCandidates(process.platform, env, isExecutableFile)];
  }
  const { found, rejected } = await findPython(candidates, (c) => probePython(c), requires);
  for (const r of rejected) {
    log(`not using ${describeCandidate(r.candidate)} (${r.candidate.source}): ${r.reason}`);
  }
  if (!found) {
    return {
      message: noPythonMessage(process.platform, requires, rejected, setting !== '' ? 'ladder.server.pythonPath' : undefined),
      download: true,
    };
  }
  const c = found.candidate;
  return {
    command: c.command,
    args: [...c.args, script],
    source: `the bundled server, Python ${found.version} from ${c.source}`,
  };
}

export function isNoServer(x: ServerCommand | NoServer): x is NoServer {
  return 'message' in x;
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
  return describeCandidate(cmd);
}
