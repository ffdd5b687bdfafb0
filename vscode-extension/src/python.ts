// Which Python runs the bundled language server: the candidates in order, their lookup on PATH,
// the version check against the package's requires-python, and the message when none fits.
// Pure functions over (platform, environment, file test, probe), so that the Windows cases are
// tested on any machine (test/unit/python.test.ts); only probePython starts a process.
import { execFile } from 'child_process';
import * as path from 'path';

export interface Candidate {
  /** program to run: an absolute path, or a name as the user gave it */
  command: string;
  /** arguments that come before the script (`-3` for the `py` launcher) */
  args: string[];
  /** where it came from, for messages: a setting, "the Python extension", "PATH" */
  source: string;
}

export interface Probe {
  /** `3.11.2` */
  version?: string;
  /** sys.executable */
  executable?: string;
  /** why the interpreter could not be asked */
  error?: string;
}

export interface Found {
  candidate: Candidate;
  version: string;
  executable: string;
}

export interface Rejected {
  candidate: Candidate;
  reason: string;
}

/** The environment variables read: PATH (on Windows also spelled Path). */
export type Env = Record<string, string | undefined>;

/** The names looked for on PATH, in order: Windows prefers the `py` launcher, which knows every installed Python. */
export function pathNames(platform: NodeJS.Platform): { name: string; args: string[] }[] {
  return platform === 'win32'
    ? [
        { name: 'py', args: ['-3'] },
        { name: 'python', args: [] },
        { name: 'python3', args: [] },
      ]
    : [
        { name: 'python3', args: [] },
        { name: 'python', args: [] },
      ];
}

function pathApi(platform: NodeJS.Platform): path.PlatformPath {
  return platform === 'win32' ? path.win32 : path.posix;
}

/** A setting's value as a program: quotes that Windows' "Copy as path" adds are not part of it. */
export function unquote(value: string): string {
  const v = value.trim();
  return v.length >= 2 && v.startsWith('"') && v.endsWith('"') ? v.slice(1, -1) : v;
}

/**
 * Where `name` is on PATH, or undefined. On Windows the PATH variable may be spelled `Path`,
 * entries may be quoted, and only `.exe` files are taken: a `.bat` or `.cmd` shim (pyenv-win's)
 * cannot be started without a shell.
 */
export function findOnPath(name: string, platform: NodeJS.Platform, env: Env, isFile: (p: string) => boolean): string | undefined {
  const api = pathApi(platform);
  const windows = platform === 'win32';
  const value = env.PATH ?? env.Path ?? '';
  const names = windows && !/\.exe$/i.test(name) ? [`${name}.exe`] : [name];
  for (const raw of value.split(windows ? ';' : ':')) {
    const dir = unquote(raw);
    if (dir === '') {
      continue;
    }
    for (const n of names) {
      const full = api.join(dir, n);
      if (isFile(full)) {
        return full;
      }
    }
  }
  return undefined;
}

/** A program named in a setting: a bare name (`python3`, `py`) is looked up on PATH, a path is taken as it is. */
export function resolveProgram(program: string, platform: NodeJS.Platform, env: Env, isFile: (p: string) => boolean): string {
  const p = unquote(program);
  const hasDir = platform === 'win32' ? /[\\/]/.test(p) : p.includes('/');
  return hasDir ? p : findOnPath(p, platform, env, isFile) ?? p;
}

/** The interpreters found on PATH, in the platform's order. */
export function pathCandidates(platform: NodeJS.Platform, env: Env, isFile: (p: string) => boolean): Candidate[] {
  const out: Candidate[] = [];
  for (const { name, args } of pathNames(platform)) {
    const found = findOnPath(name, platform, env, isFile);
    if (found && !out.some((c) => c.command === found && c.args.join(' ') === args.join(' '))) {
      out.push({ command: found, args, source: 'PATH' });
    }
  }
  return out;
}

/** A `-c` program whose output parseProbe reads: the version and the interpreter behind a launcher. */
export const PROBE_CODE = 'import sys; print("%d.%d.%d" % sys.version_info[:3]); print(sys.executable)';

export function parseProbe(stdout: string): Probe {
  const lines = stdout.split(/\r?\n/).map((l) => l.trim());
  const version = lines.find((l) => /^\d+\.\d+\.\d+$/.test(l));
  if (!version) {
    return { error: `it did not answer as a Python does (${JSON.stringify(stdout.trim().slice(0, 120))})` };
  }
  return { version, executable: lines[lines.indexOf(version) + 1] || undefined };
}

/** What is read of the Python extension's API: the newer `environments`, else the older `settings`. */
export interface PythonExtensionApi {
  ready?: Promise<void>;
  environments?: {
    getActiveEnvironmentPath(resource?: unknown): { path: string };
    resolveEnvironment(env: { path: string } | string): Promise<{ executable: { uri?: { fsPath: string } } } | undefined>;
  };
  settings?: {
    getExecutionDetails(resource?: unknown): { execCommand?: string[] };
  };
}

/** The interpreter the Python extension has selected for `resource` (a workspace folder's URI). */
export async function interpreterOfPythonExtension(api: PythonExtensionApi | undefined, resource?: unknown): Promise<Candidate | undefined> {
  await api?.ready;
  if (api?.environments) {
    const env = await api.environments.resolveEnvironment(api.environments.getActiveEnvironmentPath(resource));
    const exe = env?.executable.uri?.fsPath;
    if (exe) {
      return { command: exe, args: [], source: 'the Python extension' };
    }
  }
  const exec = api?.settings?.getExecutionDetails(resource).execCommand;
  if (exec && exec.length > 0) {
    return { command: exec[0], args: exec.slice(1), source: 'the Python extension' };
  }
  return undefined;
}

// ---------------------------------------------------------------- requires-python

interface Clause {
  op: string;
  release: number[];
  wildcard: boolean;
}

/** The clauses of a PEP 440 specifier such as `>=3.11` or `>=3.11,<4`; throws on what it does not read. */
export function parseSpecifier(spec: string): Clause[] {
  return spec.split(',').map((part) => {
    const m = /^\s*(~=|===|==|!=|<=|>=|<|>)\s*(\d+(?:\.\d+)*)(\.\*)?\s*$/.exec(part);
    if (!m || m[1] === '===' || (m[3] && m[1] !== '==' && m[1] !== '!=')) {
      throw new Error(`cannot read the Python version requirement ${JSON.stringify(spec)}`);
    }
    return { op: m[1], release: m[2].split('.').map(Number), wildcard: m[3] !== undefined };
  });
}

function compare(a: number[], b: number[]): number {
  for (let i = 0; i < Math.max(a.length, b.length); i++) {
    const d = (a[i] ?? 0) - (b[i] ?? 0);
    if (d !== 0) {
      return d;
    }
  }
  return 0;
}

function clauseHolds(v: number[], c: Clause): boolean {
  const prefix = (n: number) => compare(v.slice(0, n), c.release.slice(0, n)) === 0;
  switch (c.op) {
    case '>=':
      return compare(v, c.release) >= 0;
    case '>':
      return compare(v, c.release) > 0;
    case '<=':
      return compare(v, c.release) <= 0;
    case '<':
      return compare(v, c.release) < 0;
    case '==':
      return c.wildcard ? prefix(c.release.length) : compare(v, c.release) === 0;
    case '!=':
      return c.wildcard ? !prefix(c.release.length) : compare(v, c.release) !== 0;
    default: // ~=X.Y: >= X.Y and the same X
      return compare(v, c.release) >= 0 && prefix(Math.max(1, c.release.length - 1));
  }
}

export function satisfies(version: string, spec: string): boolean {
  const v = version.split('.').map(Number);
  return parseSpecifier(spec).every((c) => clauseHolds(v, c));
}

/** `3.11` for `>=3.11`: what the message asks the user to install. */
export function minimumVersion(spec: string): string | undefined {
  const low = parseSpecifier(spec).find((c) => c.op === '>=' || c.op === '~=' || c.op === '>');
  return low ? low.release.join('.') : undefined;
}

// ---------------------------------------------------------------- the search

/** Probes the candidates in order; the first whose version satisfies `spec` wins. */
export async function findPython(
  candidates: Candidate[],
  probe: (c: Candidate) => Promise<Probe>,
  spec: string,
): Promise<{ found?: Found; rejected: Rejected[] }> {
  const rejected: Rejected[] = [];
  for (const candidate of candidates) {
    const answer = await probe(candidate);
    if (!answer.version) {
      rejected.push({ candidate, reason: answer.error ?? 'no answer' });
    } else if (!satisfies(answer.version, spec)) {
      rejected.push({ candidate, reason: `Python ${answer.version} is too old (the server needs ${spec})` });
    } else {
      return { found: { candidate, version: answer.version, executable: answer.executable ?? candidate.command }, rejected };
    }
  }
  return { found: undefined, rejected };
}

export function describeCandidate(c: Candidate): string {
  return [c.command, ...c.args].map((p) => (/\s/.test(p) ? JSON.stringify(p) : p)).join(' ');
}

/** The Store's `python.exe` in WindowsApps: an alias that offers to install Python, not a Python. */
export function isStoreAlias(command: string): boolean {
  return /[\\/]Microsoft[\\/]WindowsApps[\\/]python3?(\.exe)?$/i.test(command);
}

export const PYTHON_DOWNLOAD = 'https://www.python.org/downloads/';

/** What the notification says when no Python fits: what was tried, and what to install. */
export function noPythonMessage(platform: NodeJS.Platform, spec: string, rejected: Rejected[], setting?: string): string {
  const min = minimumVersion(spec);
  const need = min ? `Python ${min} or newer` : `a Python ${spec}`;
  const tried =
    rejected.length === 0
      ? platform === 'win32'
        ? 'None of py, python.exe, python3.exe is on PATH'
        : 'Neither python3 nor python is on PATH'
      : rejected
          .map((r) => {
            const why = isStoreAlias(r.candidate.command) && !/too old/.test(r.reason)
              ? "the Microsoft Store's alias, not an installed Python"
              : r.reason;
            return `${describeCandidate(r.candidate)} (${r.candidate.source}): ${why}`;
          })
          .join('; ');
  const install =
    platform === 'win32'
      ? `Install ${need} from ${PYTHON_DOWNLOAD} (keep "py launcher" ticked in the installer) or from the Microsoft Store`
      : `Install ${need} (your system's package, or ${PYTHON_DOWNLOAD})`;
  const where = setting
    ? `or correct the setting "${setting}"`
    : 'or name one in the setting "ladder.server.pythonPath"';
  return `The ladder language server needs ${need}. ${tried}. ${install}, ${where}; then run "Ladder: Restart Language Server".`;
}

/** Asks an interpreter for its version; never throws. */
export function probePython(c: Candidate, timeoutMs = 15000): Promise<Probe> {
  return new Promise((resolve) => {
    execFile(c.command, [...c.args, '-c', PROBE_CODE], { timeout: timeoutMs, windowsHide: true }, (err, stdout, stderr) => {
      if (err) {
        const detail = String(stderr || '').trim().split(/\r?\n/)[0] || err.message;
        resolve({ error: (err as NodeJS.ErrnoException).code === 'ENOENT' ? 'not found' : detail });
        return;
      }
      resolve(parseProbe(String(stdout)));
    });
  });
}
