// Which Python runs the bundled server (src/python.ts), on purpose for Windows as well as Linux:
// the py launcher, .exe suffixes, backslashes, paths with spaces, the Store's alias.
// `npm run test:unit` bundles this file with esbuild and runs it with node's test runner.
import * as assert from 'node:assert/strict';
import * as fs from 'node:fs';
import * as path from 'node:path';
import { test } from 'node:test';
import {
  Candidate,
  Probe,
  findOnPath,
  findPython,
  interpreterOfPythonExtension,
  minimumVersion,
  noPythonMessage,
  parseProbe,
  pathCandidates,
  probePython,
  resolveProgram,
  satisfies,
} from '../../src/python';

const files = (...paths: string[]) => (p: string) => paths.includes(p);

const WIN_PATH = [
  'C:\\WINDOWS\\system32',
  'C:\\WINDOWS',
  '',
  '"C:\\Program Files\\Python312"',
  'C:\\Users\\Ana Lopez\\AppData\\Local\\Microsoft\\WindowsApps',
].join(';');

test('Windows: the py launcher comes first, with -3, then python.exe and python3.exe', () => {
  const isFile = files(
    'C:\\WINDOWS\\py.exe',
    'C:\\Program Files\\Python312\\python.exe',
    'C:\\Users\\Ana Lopez\\AppData\\Local\\Microsoft\\WindowsApps\\python3.exe',
  );
  assert.deepEqual(pathCandidates('win32', { Path: WIN_PATH }, isFile), [
    { command: 'C:\\WINDOWS\\py.exe', args: ['-3'], source: 'PATH' },
    { command: 'C:\\Program Files\\Python312\\python.exe', args: [], source: 'PATH' },
    { command: 'C:\\Users\\Ana Lopez\\AppData\\Local\\Microsoft\\WindowsApps\\python3.exe', args: [], source: 'PATH' },
  ]);
});

test('Windows: a quoted PATH entry with spaces is found, joined with a backslash', () => {
  const found = findOnPath('python', 'win32', { PATH: WIN_PATH }, files('C:\\Program Files\\Python312\\python.exe'));
  assert.equal(found, 'C:\\Program Files\\Python312\\python.exe');
});

test('Windows: only .exe files count (a .bat shim needs a shell), and a name with .exe is not doubled', () => {
  const isFile = files('C:\\Users\\me\\.pyenv\\pyenv-win\\shims\\python.bat', 'C:\\Python311\\python.exe');
  const env = { PATH: 'C:\\Users\\me\\.pyenv\\pyenv-win\\shims;C:\\Python311' };
  assert.equal(findOnPath('python', 'win32', env, isFile), 'C:\\Python311\\python.exe');
  assert.equal(findOnPath('python.exe', 'win32', env, isFile), 'C:\\Python311\\python.exe');
});

test('Linux: python3 before python, PATH split on colons, joined with a slash', () => {
  const isFile = files('/usr/bin/python3', '/home/ana/.local/bin/python');
  assert.deepEqual(pathCandidates('linux', { PATH: '/home/ana/.local/bin::/usr/bin' }, isFile), [
    { command: '/usr/bin/python3', args: [], source: 'PATH' },
    { command: '/home/ana/.local/bin/python', args: [], source: 'PATH' },
  ]);
  assert.deepEqual(pathCandidates('linux', { PATH: '/usr/local/bin' }, files()), []);
});

test('a setting: a path is kept as written (spaces, backslashes, copied with quotes), a bare name is looked up', () => {
  const none = files();
  assert.equal(resolveProgram('C:\\Program Files\\Python312\\python.exe', 'win32', {}, none), 'C:\\Program Files\\Python312\\python.exe');
  assert.equal(resolveProgram('"C:\\Program Files\\Python312\\python.exe"', 'win32', {}, none), 'C:\\Program Files\\Python312\\python.exe');
  assert.equal(resolveProgram('C:/Python311/python.exe', 'win32', {}, none), 'C:/Python311/python.exe');
  assert.equal(resolveProgram('py', 'win32', { PATH: 'C:\\WINDOWS' }, files('C:\\WINDOWS\\py.exe')), 'C:\\WINDOWS\\py.exe');
  assert.equal(resolveProgram('python3', 'linux', { PATH: '/usr/bin' }, files('/usr/bin/python3')), '/usr/bin/python3');
  assert.equal(resolveProgram('/opt/my venv/bin/python', 'linux', {}, none), '/opt/my venv/bin/python');
});

test("the Python extension's interpreter: its environments API, else its older execution details", async () => {
  const folder = { fsPath: 'C:\\Users\\Ana\\plc' };
  const asked: unknown[] = [];
  const environments = {
    getActiveEnvironmentPath: (resource?: unknown) => {
      asked.push(resource);
      return { path: 'C:\\Users\\Ana\\plc\\.venv' };
    },
    resolveEnvironment: async (env: { path: string } | string) => ({
      executable: { uri: { fsPath: `${typeof env === 'string' ? env : env.path}\\Scripts\\python.exe` } },
    }),
  };
  assert.deepEqual(await interpreterOfPythonExtension({ environments }, folder), {
    command: 'C:\\Users\\Ana\\plc\\.venv\\Scripts\\python.exe',
    args: [],
    source: 'the Python extension',
  });
  assert.deepEqual(asked, [folder]);
  // an environment with no executable yet: the execution details (a conda command line) are used
  const settings = { getExecutionDetails: () => ({ execCommand: ['C:\\Miniconda3\\Scripts\\conda.exe', 'run', '-n', 'plc', 'python'] }) };
  const noExe = { ...environments, resolveEnvironment: async () => ({ executable: { uri: undefined } }) };
  assert.deepEqual(await interpreterOfPythonExtension({ environments: noExe, settings, ready: Promise.resolve() }), {
    command: 'C:\\Miniconda3\\Scripts\\conda.exe',
    args: ['run', '-n', 'plc', 'python'],
    source: 'the Python extension',
  });
  assert.equal(await interpreterOfPythonExtension({ settings: { getExecutionDetails: () => ({ execCommand: undefined }) } }), undefined);
  assert.equal(await interpreterOfPythonExtension(undefined), undefined);
});

test('the probe reads the version and the interpreter, CRLF line ends included', () => {
  assert.deepEqual(parseProbe('3.12.1\r\nC:\\Program Files\\Python312\\python.exe\r\n'), {
    version: '3.12.1',
    executable: 'C:\\Program Files\\Python312\\python.exe',
  });
  assert.deepEqual(parseProbe('3.11.2\n/usr/bin/python3\n'), { version: '3.11.2', executable: '/usr/bin/python3' });
  const store = parseProbe('Python was not found; run without arguments to install from the Microsoft Store, or disable this shortcut from Settings > Manage App Execution Aliases.\r\n');
  assert.equal(store.version, undefined);
  assert.match(store.error ?? '', /did not answer as a Python does/);
});

test('requires-python: the specifiers a pyproject.toml uses', () => {
  assert.equal(satisfies('3.11.0', '>=3.11'), true);
  assert.equal(satisfies('3.13.1', '>=3.11'), true);
  assert.equal(satisfies('3.10.12', '>=3.11'), false);
  assert.equal(satisfies('3.9.2', '>=3.11'), false);
  assert.equal(satisfies('4.0.0', '>=3.11, <4'), false);
  assert.equal(satisfies('3.12.0', '~=3.11'), true);
  assert.equal(satisfies('4.1.0', '~=3.11'), false);
  assert.equal(satisfies('3.11.9', '==3.11.*'), true);
  assert.equal(satisfies('3.12.0', '==3.11.*'), false);
  assert.equal(satisfies('3.11.0', '>=3.11,!=3.11.0'), false);
  assert.equal(minimumVersion('>=3.11,<4'), '3.11');
  assert.throws(() => satisfies('3.11.0', '>=3.11a1'), /cannot read the Python version requirement/);
});

test("the repository's requires-python is one the extension reads", () => {
  const pyproject = fs.readFileSync(path.resolve(__dirname, '..', '..', '..', 'pyproject.toml'), 'utf8');
  const spec = /^requires-python\s*=\s*"([^"]+)"/m.exec(pyproject)?.[1];
  assert.ok(spec, 'pyproject.toml has requires-python');
  assert.ok(minimumVersion(spec), `${spec} names a minimum version`);
});

test('the first candidate that answers with a suitable version wins; the others say why not', async () => {
  const store: Candidate = { command: 'C:\\Users\\Ana\\AppData\\Local\\Microsoft\\WindowsApps\\python.exe', args: [], source: 'PATH' };
  const old: Candidate = { command: 'C:\\Python39\\python.exe', args: [], source: 'the Python extension' };
  const launcher: Candidate = { command: 'C:\\WINDOWS\\py.exe', args: ['-3'], source: 'PATH' };
  const answers = new Map<Candidate, Probe>([
    [old, { version: '3.9.13', executable: old.command }],
    [store, { error: 'Python was not found; run without arguments to install from the Microsoft Store' }],
    [launcher, { version: '3.12.4', executable: 'C:\\Program Files\\Python312\\python.exe' }],
  ]);
  const asked: Candidate[] = [];
  const probe = async (c: Candidate) => {
    asked.push(c);
    return answers.get(c)!;
  };
  const { found, rejected } = await findPython([old, store, launcher], probe, '>=3.11');
  assert.deepEqual(found, { candidate: launcher, version: '3.12.4', executable: 'C:\\Program Files\\Python312\\python.exe' });
  assert.deepEqual(asked, [old, store, launcher]);
  assert.deepEqual(rejected.map((r) => r.reason), [
    'Python 3.9.13 is too old (the server needs >=3.11)',
    'Python was not found; run without arguments to install from the Microsoft Store',
  ]);

  const none = await findPython([old, store], probe, '>=3.11');
  assert.equal(none.found, undefined);
  const message = noPythonMessage('win32', '>=3.11', none.rejected);
  assert.match(message, /needs Python 3\.11 or newer/);
  assert.match(message, /C:\\Python39\\python\.exe \(the Python extension\): Python 3\.9\.13 is too old/);
  assert.match(message, /WindowsApps\\python\.exe \(PATH\): the Microsoft Store's alias, not an installed Python/);
  assert.match(message, /https:\/\/www\.python\.org\/downloads\//);
  assert.match(message, /py launcher/);
  assert.match(message, /ladder\.server\.pythonPath/);
});

test('the message when nothing is on PATH, and when the setting names a bad Python', () => {
  assert.match(noPythonMessage('win32', '>=3.11', []), /None of py, python\.exe, python3\.exe is on PATH/);
  assert.match(noPythonMessage('linux', '>=3.11', []), /Neither python3 nor python is on PATH/);
  const setting: Candidate = { command: 'C:\\Program Files\\Python310\\python.exe', args: [], source: 'ladder.server.pythonPath' };
  const message = noPythonMessage('win32', '>=3.11', [{ candidate: setting, reason: 'Python 3.10.11 is too old (the server needs >=3.11)' }], 'ladder.server.pythonPath');
  assert.match(message, /"C:\\\\Program Files\\\\Python310\\\\python\.exe" \(ladder\.server\.pythonPath\): Python 3\.10\.11 is too old/);
  assert.match(message, /correct the setting "ladder\.server\.pythonPath"/);
});

test('probing a program that is missing, or that is not Python, gives a reason and never throws', async () => {
  assert.deepEqual(await probePython({ command: path.join(__dirname, 'no such python'), args: [], source: 'PATH' }), { error: 'not found' });
  const notPython = await probePython({ command: process.execPath, args: [], source: 'PATH' });
  assert.equal(notPython.version, undefined);
  assert.ok(notPython.error);
});

test('probing a real Python on this machine', async (t) => {
  const python = findOnPath(process.platform === 'win32' ? 'python' : 'python3', process.platform, process.env, (p) => fs.existsSync(p));
  if (!python) {
    t.skip('no Python on PATH');
    return;
  }
  const answer = await probePython({ command: python, args: [], source: 'PATH' });
  assert.match(answer.version ?? '', /^\d+\.\d+\.\d+$/);
  assert.ok(answer.executable && fs.existsSync(answer.executable));
});
