// Drives Debian's headless Chromium over the DevTools protocol (a pipe, no network port) for the
// suite's browser tests: optionally serves a folder on 127.0.0.1 (random port), opens a page,
// waits for its load event, evaluates a script file in it (an async function body; its return
// value is JSON), and writes {result, console, exceptions} to --out. Bounded: --timeout seconds
// (default 60), then everything is stopped and the exit code is 2. Nothing is fetched from outside.
//
//   node chromium_cdp.mjs --chromium /usr/bin/chromium --url 'URL' --script S.js --out R.json
//        [--serve ROOT] [--user-data-dir DIR] [--timeout 60] [--screenshot SHOT.png]
// In --url, "{origin}" is replaced with the local server's http://127.0.0.1:PORT.
import { spawn } from 'node:child_process';
import { createServer } from 'node:http';
import { readFileSync, writeFileSync, statSync, mkdtempSync, rmSync } from 'node:fs';
import { join, normalize, extname, sep } from 'node:path';
import { tmpdir } from 'node:os';

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const timeoutS = Number(args.timeout || 60);
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
                '.glsl': 'text/plain', '.ktx2': 'image/ktx2', '.glb': 'model/gltf-binary', '.png': 'image/png' };

function serve(root) {
  return new Promise((resolve) => {
    const srv = createServer((req, res) => {
      const rel = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname)).replace(/^([/\\])+/, '');
      const file = join(root, rel);
      if (!file.startsWith(normalize(root) + sep) && file !== normalize(root)) { res.writeHead(403).end(); return; }
      try {
        if (!statSync(file).isFile()) throw new Error('not a file');
        res.writeHead(200, { 'Content-Type': TYPES[extname(file)] || 'application/octet-stream' });
        res.end(readFileSync(file));
      } catch { res.writeHead(404).end(); }
    });
    srv.listen(0, '127.0.0.1', () => resolve(srv));
  });
}

const server = args.serve ? await serve(args.serve) : null;
const origin = server ? `http://127.0.0.1:${server.address().port}` : '';
const url = args.url.replaceAll('{origin}', origin);
const ownProfile = !args['user-data-dir'];
const profile = args['user-data-dir'] || mkdtempSync(join(tmpdir(), 'ahd-chromium-'));

const chrome = spawn(args.chromium, [
  '--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
  '--disable-default-apps', '--disable-extensions', '--hide-scrollbars', '--window-size=1280,900',
  '--remote-debugging-pipe', `--user-data-dir=${profile}`, 'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
let stderr = '';
chrome.stderr.on('data', (d) => { stderr += d; });

let nextId = 1, buf = '';
const pending = new Map(), listeners = [];
const out = chrome.stdio[3], inp = chrome.stdio[4];
inp.on('data', (d) => {
  buf += d.toString('utf8');
  let k;
  while ((k = buf.indexOf('\0')) >= 0) {
    const msg = JSON.parse(buf.slice(0, k));
    buf = buf.slice(k + 1);
    if (msg.id && pending.has(msg.id)) {
      const { resolve, reject } = pending.get(msg.id);
      pending.delete(msg.id);
      msg.error ? reject(new Error(JSON.stringify(msg.error))) : resolve(msg.result);
    } else for (const l of listeners) l(msg);
  }
});
function send(method, params = {}, sessionId) {
  const id = nextId++;
  out.write(JSON.stringify({ id, method, params, sessionId }) + '\0');
  return new Promise((resolve, reject) => pending.set(id, { resolve, reject }));
}

const consoleLines = [], exceptions = [];
let finished = false;
function finish(code, body) {
  if (finished) return;
  finished = true;
  if (args.out) writeFileSync(args.out, JSON.stringify(body));
  try { out.write(JSON.stringify({ id: nextId++, method: 'Browser.close' }) + '\0'); } catch {}
  const killer = setTimeout(() => chrome.kill('SIGKILL'), 3000);
  chrome.on('exit', () => {
    clearTimeout(killer);
    if (server) server.close();
    if (ownProfile) rmSync(profile, { recursive: true, force: true });
    process.exit(code);
  });
  if (chrome.exitCode !== null) chrome.emit('exit');
}
const timer = setTimeout(() => finish(2, { error: `timeout after ${timeoutS} s`, console: consoleLines, exceptions, stderr: stderr.slice(-4000) }), timeoutS * 1000);
chrome.on('exit', () => { if (!finished) { clearTimeout(timer); finish(3, { error: 'chromium exited', stderr: stderr.slice(-4000) }); } });

try {
  const { targetInfos } = await send('Target.getTargets');
  const page = targetInfos.find((t) => t.type === 'page');
  const { sessionId } = await send('Target.attachToTarget', { targetId: page.targetId, flatten: true });
  listeners.push((m) => {
    if (m.sessionId !== sessionId) return;
    if (m.method === 'Runtime.consoleAPICalled')
      consoleLines.push(m.params.type + ': ' + m.params.args.map((a) => a.value ?? a.description ?? '').join(' '));
    if (m.method === 'Runtime.exceptionThrown')
      exceptions.push(m.params.exceptionDetails.exception?.description || m.params.exceptionDetails.text);
  });
  await send('Page.enable', {}, sessionId);
  await send('Runtime.enable', {}, sessionId);
  const loaded = new Promise((r) => listeners.push((m) => { if (m.sessionId === sessionId && m.method === 'Page.loadEventFired') r(); }));
  await send('Page.navigate', { url }, sessionId);
  await loaded;
  const script = args.script ? readFileSync(args.script, 'utf8') : 'return null;';
  const r = await send('Runtime.evaluate', { expression: `(async () => {\n${script}\n})()`, awaitPromise: true, returnByValue: true }, sessionId);
  if (args.screenshot) {
    const shot = await send('Page.captureScreenshot', { format: 'png' }, sessionId);
    writeFileSync(args.screenshot, Buffer.from(shot.data, 'base64'));
  }
  clearTimeout(timer);
  if (r.exceptionDetails) finish(1, { error: r.exceptionDetails.exception?.description || r.exceptionDetails.text, console: consoleLines, exceptions });
  else finish(0, { result: r.result.value, console: consoleLines, exceptions });
} catch (e) {
  clearTimeout(timer);
  finish(1, { error: String(e), console: consoleLines, exceptions, stderr: stderr.slice(-4000) });
}
