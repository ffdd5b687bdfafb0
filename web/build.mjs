// Builds the playground into web/dist (static files, docs/browser.md):
//   index.html, style.css, main.js (the page and CodeMirror), worker.js (the Web Worker),
//   pyodide/ (Pyodide's core, its standard library precompiled), site.zip (textladder and the
//   packages it needs, precompiled).
// Python bytecode is compiled here, once, by Pyodide's own Python under Node: a browser cannot
// keep the .pyc it would write, so without it every page load compiles every module again.
//
//   node build.mjs            (PYTHON: the Python that builds the wheel and runs pip; default python3)
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import * as esbuild from 'esbuild';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const REPO = path.resolve(HERE, '..');
const DIST = path.join(HERE, 'dist');
const PYODIDE = path.join(HERE, 'node_modules', 'pyodide');
const PYTHON = process.env.PYTHON || 'python3';
// Pyodide's Python: the wheels pip may choose for it
const PYTHON_VERSION = JSON.parse(fs.readFileSync(path.join(PYODIDE, 'pyodide-lock.json'), 'utf8'))
  .info.python.split('.').slice(0, 2).join('.');
// what a browser has no use for: the command line and the runners of native simulators
const LEFT_OUT = ['ladder', 'compiler/run', 'bin'];

function log(message) {
  process.stderr.write(`build: ${message}\n`);
}

function run(command, args) {
  execFileSync(command, args, { stdio: ['ignore', 'ignore', 'inherit'], cwd: REPO });
}

/** textladder's wheel, as users get it, and the wheels of its dependencies that any platform runs. */
function wheels(dir) {
  run(PYTHON, ['-m', 'pip', 'wheel', '-q', '--no-deps', '-w', dir, REPO]);
  const own = fs.readdirSync(dir).find((f) => f.startsWith('textladder-'));
  run(PYTHON, ['-m', 'pip', 'download', '-q', '--only-binary=:all:', '--platform', 'any',
    '--python-version', PYTHON_VERSION, '--implementation', 'py', '-d', dir, path.join(dir, own)]);
  return fs.readdirSync(dir).filter((f) => f.endsWith('.whl')).sort();
}

const COMPILE = `
import compileall, os, pathlib, shutil, zipfile

def compiled(root, left_out=()):
    """Bytecode beside each module (sourceless: Python imports FILE.pyc when FILE.py is gone)."""
    root = pathlib.Path(root)
    for name in left_out:
        shutil.rmtree(root / name, ignore_errors=True)
    for tests in [p for p in root.rglob("tests") if p.is_dir()]:
        shutil.rmtree(tests)
    assert compileall.compile_dir(str(root), quiet=1, legacy=True, workers=1)
    for source in list(root.rglob("*.py")):
        source.unlink()
    for cache in [p for p in root.rglob("__pycache__")]:
        shutil.rmtree(cache)
    for record in root.glob("*.dist-info/RECORD"):
        record.unlink()

def zipped(root, out):
    root = pathlib.Path(root)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        for path in sorted(root.rglob("*")):
            if path.is_file():
                z.write(path, path.relative_to(root).as_posix())
`;

async function pack(wheelDir, names) {
  const { loadPyodide } = await import(path.join(PYODIDE, 'pyodide.mjs'));
  const py = await loadPyodide({ indexURL: PYODIDE + path.sep });
  py.runPython(COMPILE);
  for (const name of names) {
    py.unpackArchive(new Uint8Array(fs.readFileSync(path.join(wheelDir, name))), 'wheel', { extractDir: '/site' });
  }
  py.FS.mkdir('/stdlib');
  py.unpackArchive(new Uint8Array(fs.readFileSync(path.join(PYODIDE, 'python_stdlib.zip'))), 'zip', { extractDir: '/stdlib' });
  py.runPython(`
compiled("/site", ${JSON.stringify(LEFT_OUT)})
zipped("/site", "/site.zip")
compiled("/stdlib")
zipped("/stdlib", "/python_stdlib.zip")
`);
  fs.writeFileSync(path.join(DIST, 'site.zip'), py.FS.readFile('/site.zip'));
  fs.writeFileSync(path.join(DIST, 'pyodide', 'python_stdlib.zip'), py.FS.readFile('/python_stdlib.zip'));
}

async function main() {
  fs.rmSync(DIST, { recursive: true, force: true });
  fs.mkdirSync(path.join(DIST, 'pyodide'), { recursive: true });
  for (const file of ['pyodide.mjs', 'pyodide.asm.mjs', 'pyodide.asm.wasm', 'pyodide-lock.json']) {
    fs.copyFileSync(path.join(PYODIDE, file), path.join(DIST, 'pyodide', file));
  }
  const wheelDir = fs.mkdtempSync(path.join(os.tmpdir(), 'textladder-wheels-'));
  try {
    const names = wheels(wheelDir);
    log(`wheels: ${names.join(', ')}`);
    await pack(wheelDir, names);
  } finally {
    fs.rmSync(wheelDir, { recursive: true, force: true });
  }
  await esbuild.build({
    entryPoints: { main: path.join(HERE, 'src', 'main.js'), worker: path.join(HERE, 'src', 'worker.js') },
    bundle: true, format: 'esm', minify: true, target: 'es2022', outdir: DIST, logLevel: 'warning',
    loader: { '.ladder': 'text' },
  });
  for (const file of ['index.html', 'style.css']) {
    fs.copyFileSync(path.join(HERE, 'src', file), path.join(DIST, file));
  }
  log(`done: ${DIST}`);
}

main().catch((error) => {
  process.stderr.write(`build: ${error.stack || error}\n`);
  process.exit(1);
});
