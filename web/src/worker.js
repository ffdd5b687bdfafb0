// The playground's Web Worker: the language server (serve.js), with Pyodide's files and site.zip
// fetched from beside this script.
import { serve } from './serve.js';

const base = new URL('./', import.meta.url);

serve(async () => {
  const { loadPyodide } = await import(new URL('pyodide/pyodide.mjs', base).href);
  const site = fetch(new URL('site.zip', base)).then((r) => {
    if (!r.ok) throw new Error(`site.zip: HTTP ${r.status}`);
    return r.arrayBuffer();
  });
  return { loadPyodide, indexURL: new URL('pyodide/', base).href, site };
});
