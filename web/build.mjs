// Builds the playground into web/dist (static files, docs/browser.md):
//   index.html, style.css, main.js (the page and CodeMirror), worker.js (the Web Worker),
//   pyodide/ (Pyodide's core, its standard library precompiled), site.zip (textladder and the
//   packages it needs, precompiled): pyodide-files.mjs.
//
//   node build.mjs            (PYTHON: the Python that builds the wheel and runs pip; default python3)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import * as esbuild from 'esbuild';
import { pyodideFiles } from './pyodide-files.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const DIST = path.join(HERE, 'dist');

async function main() {
  fs.rmSync(DIST, { recursive: true, force: true });
  await pyodideFiles({
    pyodideDir: path.join(HERE, 'node_modules', 'pyodide'), out: DIST, python: process.env.PYTHON || 'python3',
    core: ['pyodide.mjs', 'pyodide.asm.mjs', 'pyodide.asm.wasm'],
  });
  await esbuild.build({
    entryPoints: { main: path.join(HERE, 'src', 'main.js'), worker: path.join(HERE, 'src', 'worker.js') },
    bundle: true, format: 'esm', minify: true, target: 'es2022', outdir: DIST, logLevel: 'warning',
    loader: { '.ladder': 'text' },
  });
  for (const file of ['index.html', 'style.css']) {
    fs.copyFileSync(path.join(HERE, 'src', file), path.join(DIST, file));
  }
  process.stderr.write(`build: done: ${DIST}\n`);
  process.exit(0); // the server exercised in pyodideFiles() left its timers running
}

main().catch((error) => {
  process.stderr.write(`build: ${error.stack || error}\n`);
  process.exit(1);
});
