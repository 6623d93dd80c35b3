// Rewrites JSON files that Godot's JSON.stringify wrote at full precision, in place: every
// non-integer number that is exactly a float32 (mesh arrays, Rect2, Vector3: Godot's real_t) is
// written in the shortest form that reads back to the same float32 (0.10000000149011612 -> 0.1);
// any other number keeps its shortest double form. Read a number as double and cast it to float:
// that gives Godot's float32 exactly. Arrays of numbers stay on one line, other values one per line.
//   node f32_json.mjs FILE.json...
import { readFileSync, writeFileSync } from 'node:fs';

function num(x) {
  if (Number.isInteger(x) || Math.fround(x) !== x) return String(x);
  for (let p = 1; p <= 9; p++) {
    const s = String(Number(x.toPrecision(p)));
    if (Math.fround(Number(s)) === x) return s;
  }
  return String(x);
}

function write(v, indent) {
  if (typeof v === 'number') return num(v);
  if (v === null || typeof v !== 'object') return JSON.stringify(v);
  const pad = '\n' + ' '.repeat(indent + 1);
  if (Array.isArray(v)) {
    if (v.length === 0) return '[]';
    if (v.every((e) => typeof e === 'number')) return '[' + v.map(num).join(',') + ']';
    return '[' + v.map((e) => pad + write(e, indent + 1)).join(',') + '\n' + ' '.repeat(indent) + ']';
  }
  const keys = Object.keys(v);
  if (keys.length === 0) return '{}';
  return '{' + keys.map((k) => pad + JSON.stringify(k) + ': ' + write(v[k], indent + 1)).join(',') + '\n' + ' '.repeat(indent) + '}';
}

for (const f of process.argv.slice(2)) writeFileSync(f, write(JSON.parse(readFileSync(f, 'utf8')), 0) + '\n');
