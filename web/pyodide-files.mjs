// Pyodide's files and textladder's, ready for a browser: Pyodide's core (the WebAssembly and its
// loader), its standard library trimmed and precompiled, and site.zip (textladder and the packages
// it needs, precompiled). The playground's build (build.mjs) and the VS Code web extension's
// (vscode-extension/scripts/web.mjs) both make them here.
// Python bytecode is compiled here, once, by Pyodide's own Python under Node: a browser cannot
// keep the .pyc it would write, so without it every page load compiles every module it imports.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const REPO = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
// what a browser has no use for: the command line, the runners of native simulators
const LEFT_OUT = ['ladder', 'compiler/run', 'bin'];

function log(message) {
  process.stderr.write(`build: ${message}\n`);
}

function run(command, args) {
  execFileSync(command, args, { stdio: ['ignore', 'ignore', 'inherit'], cwd: REPO });
}

/** textladder's wheel, as users get it, and the wheels of its dependencies that any platform runs
 * on Pyodide's Python (pythonVersion, e.g. "3.13"). */
function wheels(python, pythonVersion, dir) {
  run(python, ['-m', 'pip', 'wheel', '-q', '--no-deps', '-w', dir, REPO]);
  const own = fs.readdirSync(dir).find((f) => f.startsWith('textladder-'));
  run(python, ['-m', 'pip', 'download', '-q', '--only-binary=:all:', '--platform', 'any',
    '--python-version', pythonVersion, '--implementation', 'py', '-d', dir, path.join(dir, own)]);
  return fs.readdirSync(dir).filter((f) => f.endsWith('.whl')).sort();
}

// Run by Pyodide's Python under Node. A module the server imports until it answers (every module
// of textladder but the compiler, what they import, and what a session of every feature imports)
// is shipped as bytecode only; the rest of the standard library and of the packages stays source,
// smaller to download, compiled in the browser when first imported: the compiler (about 140 kB
// less to download) on the first HEX or C file exported.
const PACK = `
import asyncio, compileall, importlib, json, pkgutil, shutil, sys, zipfile, zlib
from pathlib import Path

# never imported by the server, and of no use in a browser worker (a REPL, tests, debuggers and
# profilers, process pools, GUIs, mail, HTTP, HTML, XML, archives, statistics, the pure-Python io and
# ctypes, for native libraries a browser has none of):
# left out of the standard library
UNUSED_STDLIB = ["_pyrepl", "unittest", "doctest.py", "pdb.py", "bdb.py", "trace.py", "profile.py", "cProfile.py",
                 "pstats.py", "tabnanny.py", "pydoc.py", "pydoc_data", "multiprocessing", "ensurepip", "venv",
                 "idlelib", "tkinter", "turtle.py", "turtledemo", "lib2to3", "sqlite3", "curses", "dbm",
                 "wsgiref", "xmlrpc", "xml", "plistlib.py", "http", "socketserver.py", "imaplib.py", "smtplib.py",
                 "poplib.py", "nntplib.py", "ftplib.py", "mailbox.py", "pickletools.py", "optparse.py",
                 "_pyio.py", "tarfile.py", "statistics.py", "email", "html", "ctypes"]


# read by web/src/server.js
START_CODE = "/site/lsp/start-code.marshal"


# optional dependencies a browser does not have: z3, the prover's solver (a native library), so
# ladder verify answers that it is not installed
OPTIONAL = {"z3"}


def trimmed(root, names):
    root = Path(root)
    for name in names:
        path = root / name
        if path.is_dir():
            shutil.rmtree(path)
        elif path.exists():
            path.unlink()
    for tests in [p for p in root.rglob("tests") if p.is_dir()]:
        shutil.rmtree(tests)
    for record in root.glob("*.dist-info/RECORD"):
        record.unlink()


async def exercise(program):
    """Import every module of textladder but the compiler, then a session of every feature; returns
    the modules imported before the files are exported (which imports the compiler). The code
    compiled from source text until the first diagnostics, a problem's and an edit's included (attrs'
    and cattrs' methods) is kept in START_CODE for the browser's worker (lsp/worker_compile.py)."""
    from lsp import worker_compile
    start_code = worker_compile.record()
    for package in ("lang", "ide", "lsp"):
        for info in pkgutil.walk_packages(importlib.import_module(package).__path__, package + "."):
            if info.name.endswith(".__main__"):  # which would start the server on standard input
                continue
            try:
                importlib.import_module(info.name)
            except ModuleNotFoundError as missing:
                if missing.name not in OPTIONAL:
                    raise
    from lsp.worker import connect
    answers = {}
    send = connect(lambda text: answers.setdefault(json.loads(text).get("id"), json.loads(text)))
    def message(method, params, ident=None):
        send(json.dumps({"jsonrpc": "2.0", "method": method, "params": params, **({"id": ident} if ident else {})}))
    uri, position = "inmemory://build/program.ladder", {"line": 9, "character": 8}
    document = {"uri": uri}
    message("initialize", {"processId": None, "rootUri": None, "capabilities": {}}, 1)
    message("initialized", {})
    message("textDocument/didOpen", {"textDocument": {**document, "languageId": "ladder", "version": 1, "text": program}})
    # a program with a problem, then typed into: cattrs writes the code that turns a diagnostic into
    # JSON when the first one is published, and the code that reads a didChange at the first edit;
    # without these, the page's first keystroke and first mistake would compile them
    typo = {"uri": "inmemory://build/typo.ladder"}
    message("textDocument/didOpen", {"textDocument": {**typo, "languageId": "ladder", "version": 1,
                                                      "text": program.replace("||", "|!", 1)}})
    start = {"line": 0, "character": 0}
    message("textDocument/didChange", {"textDocument": {**typo, "version": 2},
                                       "contentChanges": [{"range": {"start": start, "end": start}, "text": " "}]})
    await asyncio.sleep(0.05)
    worker_compile.stop()
    worker_compile.save(start_code, START_CODE)
    requests = [("textDocument/hover", {"textDocument": document, "position": position}),
                ("textDocument/completion", {"textDocument": document, "position": position}),
                ("textDocument/formatting", {"textDocument": document, "options": {"tabSize": 4, "insertSpaces": True}}),
                ("textDocument/documentSymbol", {"textDocument": document}),
                ("textDocument/semanticTokens/full", {"textDocument": document}),
                ("textDocument/definition", {"textDocument": document, "position": position})]
    commands = [("ladder.sim.start",), ("ladder.sim.toggle", "Xstart"), ("ladder.sim.step", 2), ("ladder.sim.stop",),
                ("ladder.export", "ladder"), ("ladder.export", "ld")]
    exports = [("ladder.export", "c"), ("ladder.export", "hex")]
    requests += [("workspace/executeCommand", {"command": c[0], "arguments": [uri, *c[1:]]}) for c in commands + exports]
    used = None
    for ident, (method, params) in enumerate(requests, start=2):
        if ident == len(requests) + 2 - len(exports):
            used = imported()
        message(method, params, ident)
        await asyncio.sleep(0.05)
    failed = [answers.get(i) for i in range(1, len(requests) + 2) if "result" not in answers.get(i, {})]
    assert not failed, failed
    import base64
    ld = base64.b64decode(answers[len(requests) + 1 - len(exports)]["result"]["files"][0]["data"]).decode("cp1252")
    message("textDocument/didOpen", {"textDocument": {"uri": "inmemory://build/program.ld", "languageId": "ldmicro",
                                                      "version": 1, "text": ld}})
    await asyncio.sleep(0.1)
    return used | {m for m in imported() if not m.startswith("/site/compiler/")}


def imported():
    """The module files imported so far: paths under their root (a folder of sys.path, or a zip)."""
    found = set()
    for module in list(sys.modules.values()):
        origin = getattr(getattr(module, "__spec__", None), "origin", None) or ""
        if origin.endswith(".py"):
            found.add(origin.split(".zip/", 1)[1] if ".zip/" in origin else origin)
    return found


def compiled(root, used, prefix="", smaller=False):
    """Each module of used as bytecode in its place (FILE.pyc, imported when FILE.py is gone),
    without its docstrings and asserts (-OO: nothing the server runs reads a docstring). With
    smaller, any other module too where its bytecode is smaller to download than its source: the
    standard library's code pages (encodings/), whose source spells out each character's name."""
    root = Path(root)
    for source in list(root.rglob("*.py")):
        use = prefix + source.relative_to(root).as_posix() in used
        if not (use or smaller):
            continue
        assert compileall.compile_file(str(source), quiet=2, legacy=True, optimize=2) or not use, source
        bytecode = source.with_suffix(".pyc")
        if use or (bytecode.exists() and packed(bytecode) < packed(source)):
            source.unlink()
        elif bytecode.exists():
            bytecode.unlink()
    for cache in [p for p in root.rglob("__pycache__")]:
        shutil.rmtree(cache)


def packed(path):
    """The bytes of path in a zip, compressed."""
    return len(zlib.compress(path.read_bytes(), 9))


def zipped(root, out):
    root = Path(root)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        for path in sorted(root.rglob("*")):
            if path.is_file():
                z.write(path, path.relative_to(root).as_posix())
`;

async function pack(pyodideDir, wheelDir, names, out) {
  const { loadPyodide } = await import(path.join(pyodideDir, 'pyodide.mjs'));
  const py = await loadPyodide({ indexURL: pyodideDir + path.sep });
  for (const name of names) {
    py.unpackArchive(new Uint8Array(fs.readFileSync(path.join(wheelDir, name))), 'wheel', { extractDir: '/site' });
  }
  py.FS.mkdir('/stdlib');
  py.unpackArchive(new Uint8Array(fs.readFileSync(path.join(pyodideDir, 'python_stdlib.zip'))), 'zip', { extractDir: '/stdlib' });
  py.runPython(PACK);
  py.runPython(`trimmed("/site", ${JSON.stringify(LEFT_OUT)}); trimmed("/stdlib", UNUSED_STDLIB); sys.path.insert(0, "/site")`);
  py.globals.set('program', fs.readFileSync(path.join(REPO, 'examples', 'conveyor.ladder'), 'utf8'));
  await py.runPythonAsync('used = await exercise(program)');
  py.runPython(`
compiled("/site", used, "/site/")
zipped("/site", "/site.zip")
compiled("/stdlib", used, smaller=True)
zipped("/stdlib", "/python_stdlib.zip")
`);
  fs.writeFileSync(path.join(out, 'site.zip'), py.FS.readFile('/site.zip'));
  fs.writeFileSync(path.join(out, 'pyodide', 'python_stdlib.zip'), py.FS.readFile('/python_stdlib.zip'));
}

/**
 * Writes into `out`: pyodide/ (the files of `core` copied from the package `pyodideDir`, its lock
 * file without packages, python_stdlib.zip trimmed and precompiled) and site.zip. `python` builds
 * the wheel and runs pip. The server exercised in the packing leaves its timers (the idle
 * collector) running: the caller exits when it is done.
 */
export async function pyodideFiles({ pyodideDir, out, python, core }) {
  fs.mkdirSync(path.join(out, 'pyodide'), { recursive: true });
  for (const file of core) {
    fs.copyFileSync(path.join(pyodideDir, file), path.join(out, 'pyodide', file));
  }
  // Pyodide reads its lock file as it starts; a browser's server installs no package of Pyodide's
  const lock = JSON.parse(fs.readFileSync(path.join(pyodideDir, 'pyodide-lock.json'), 'utf8'));
  fs.writeFileSync(path.join(out, 'pyodide', 'pyodide-lock.json'), JSON.stringify({ ...lock, packages: {} }));
  // Pyodide's Python: the wheels pip may choose for it
  const pythonVersion = lock.info.python.split('.').slice(0, 2).join('.');
  const wheelDir = fs.mkdtempSync(path.join(os.tmpdir(), 'textladder-wheels-'));
  try {
    const names = wheels(python, pythonVersion, wheelDir);
    log(`wheels: ${names.join(', ')}`);
    await pack(pyodideDir, wheelDir, names, out);
  } finally {
    fs.rmSync(wheelDir, { recursive: true, force: true });
  }
}
