// textladder for VS Code on the desktop: starts `ladder lsp` (docs/lsp-protocol.md) as a process,
// the bundled server or an installed one (server.ts), and adds the simulation UI (activate.ts).
import * as vscode from 'vscode';
import { LanguageClient } from 'vscode-languageclient/node';
import { Host, NoServer, Server, activateWith } from './activate';
import { PYTHON_DOWNLOAD } from './python';
import { describe, executable, isNoServer, serverCommand } from './server';
import { LADDER_LANGUAGES } from './state';

export { deactivate } from './activate';

export function activate(context: vscode.ExtensionContext): Promise<void> {
  const host: Host = {
    selector: LADDER_LANGUAGES.flatMap((language) => [
      { scheme: 'file', language },
      { scheme: 'untitled', language },
    ]),
    findServer: (log) => findServer(context.extensionPath, log),
    serverWritesFiles: true,
  };
  return activateWith(context, host);
}

/** `ladder.server.command`, or the server in bundled/ run by a Python found on this machine. */
async function findServer(extensionPath: string, log: (line: string) => void): Promise<Server | NoServer> {
  const cmd = await serverCommand(vscode.workspace.getConfiguration('ladder'), extensionPath, log);
  if (isNoServer(cmd)) {
    return { message: cmd.message, download: cmd.download ? PYTHON_DOWNLOAD : undefined };
  }
  const exe = executable(cmd);
  return {
    name: describe(cmd),
    source: cmd.source,
    hint:
      cmd.source === 'ladder.server.command'
        ? 'Check the setting "ladder.server.command".'
        : 'See the "Ladder" output; the settings "ladder.server.pythonPath" and "ladder.server.command" choose another server.',
    create: (options) => new LanguageClient('ladder', 'Ladder language server', { run: exe, debug: exe }, options),
  };
}
