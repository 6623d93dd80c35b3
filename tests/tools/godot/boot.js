// Evaluated in page.html by chromium_cdp.mjs (an async function body): boots Godot's web build
// with `--main-pack project.pck`, collects what the project hands over through
// JavaScriptBridge.eval (window.__ahd.emit / done, see lib/harness.gd) and returns it.
const lines = [];
const emitted = {};
let settle;
const finished = new Promise((resolve) => { settle = resolve; });
window.__ahd = {
  emit(name, b64) { emitted[name] = b64; },
  done(code) { settle({ how: 'done', code }); },
};
// Also to the page's console: chromium_cdp.mjs reports that one when the run times out.
const onPrint = (...a) => { lines.push('out: ' + a.join(' ')); console.log(a.join(' ')); };
const onPrintError = (...a) => {
  const s = a.join(' ');
  lines.push('err: ' + s);
  console.error(s);
  // A GDScript error stops the generator's function, so `done` would never come.
  if (/SCRIPT ERROR|Parse Error|Failed to load script/.test(s)) setTimeout(() => settle({ how: 'script error', code: 1 }), 300);
};
const onExit = (code) => settle({ how: 'exit', code });
// The print hooks must be in the constructor's config: init() binds them into the wasm module.
const engine = new Engine({ executable: 'godot/index', unloadAfterInit: false, canvasResizePolicy: 0,
                            focusCanvas: false, args: [], onPrint, onPrintError, onExit });
await engine.init('godot/index');
await engine.preloadFile('project.pck', 'project.pck');
await engine.start({ canvas: document.getElementById('canvas'),
                     args: ['--main-pack', 'project.pck', '--audio-driver', 'Dummy'] });
const r = await finished;
return { how: r.how, code: r.code, files: emitted, lines };
