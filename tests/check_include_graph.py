#!/usr/bin/env python3
"""The include graph of src/: no cycle between files, none between folders (rooms), and src/cli
names no baker outside comments (CONTRIBUTING.md "Layering rules").

Usage: check_include_graph.py SOURCE_DIR      check the tree; exit 1 naming each cycle
       check_include_graph.py --self-test     the checks catch a file cycle, a room cycle and a
                                              baker name in src/cli code (exit 0 when they do)
"""
import os
import re
import sys
import tempfile

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
BAKERS = {'godot', 'bakery', 'unity', 'bevy'}
IDENT = re.compile(r'[A-Za-z_][A-Za-z0-9_]*')
WORD = re.compile(r'[A-Z]?[a-z0-9]+|[A-Z]+(?![a-z])')


def read_tree(src):
    files = {}
    for root, _, names in os.walk(src):
        for n in names:
            if n.endswith(('.h', '.cpp', '.hpp', '.inl')):
                p = os.path.relpath(os.path.join(root, n), src)
                with open(os.path.join(root, n), errors='replace') as f:
                    files[p] = f.read()
    return files


def graph(files):
    g = {}
    for p, text in files.items():
        deps = []
        for inc in INCLUDE.findall(text):
            for cand in (os.path.normpath(inc), os.path.normpath(os.path.join(os.path.dirname(p), inc))):
                if cand in files:
                    deps.append(cand)
                    break
        g[p] = sorted(set(deps))
    return g


def cycles(g):
    """One cycle per strongly connected component with more than one node (or a self-loop)."""
    index, low, on, stack, out, n = {}, {}, set(), [], [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in g.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in g.get(v, ()):
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(g):
        if v not in index:
            visit(v)
    return out


def room(p):
    return p.split(os.sep)[0] if os.sep in p else '.'


def strip_comments(text):
    text = re.sub(r'/\*.*?\*/', '', text, flags=re.S)
    text = re.sub(r'//[^\n]*', '', text)
    return text


def check(src):
    files = read_tree(src)
    g = graph(files)
    problems = []
    for c in cycles(g):
        problems.append('file include cycle: ' + ' <-> '.join(c))
    rooms = {}
    for p, deps in g.items():
        for d in deps:
            if room(p) != room(d):
                rooms.setdefault(room(p), set()).add(room(d))
    for c in cycles({k: sorted(v) for k, v in rooms.items()}):
        why = {}  # one include per pair of folders: where each direction comes from
        for p, deps in sorted(g.items()):
            for d in deps:
                if room(p) in c and room(d) in c and room(p) != room(d):
                    why.setdefault((room(p), room(d)), f'{p} -> {d}')
        problems.append('folder include cycle: ' + ' <-> '.join(c) + ' (' + '; '.join(why.values()) + ')')
    for p, text in sorted(files.items()):
        if room(p) == 'cli':
            for ident in IDENT.findall(strip_comments(text)):
                if any(w.lower() in BAKERS for w in WORD.findall(ident)):
                    problems.append(f'{p}: src/cli names a baker in code ({ident}): put it in src/bakers')
                    break
    return problems


def self_test():
    cases = {
        'file cycle': {'a/x.h': '#include "a/y.h"\n', 'a/y.h': '#include "a/x.h"\n'},
        'folder cycle': {'a/x.h': '#include "b/y.h"\n', 'b/y.h': '', 'b/z.cpp': '#include "a/x.h"\n'},
        'baker in cli': {'cli/run.cpp': '// Godot in a comment is fine\nint godot_pages = 1;\n'},
    }
    clean = {'a/x.h': '#include "b/y.h"\n', 'b/y.h': '', 'cli/run.cpp': '// reads a Godot project\n'}
    ok = True
    for name, tree in list(cases.items()) + [('clean', clean)]:
        with tempfile.TemporaryDirectory() as d:
            for p, text in tree.items():
                os.makedirs(os.path.join(d, os.path.dirname(p)), exist_ok=True)
                with open(os.path.join(d, p), 'w') as f:
                    f.write(text)
            found = check(d)
        if (name == 'clean') == bool(found):
            print(f'self-test {name}: expected {"nothing" if name == "clean" else "a problem"}, got {found}')
            ok = False
    return 0 if ok else 1


if __name__ == '__main__':
    if sys.argv[1:] == ['--self-test']:
        sys.exit(self_test())
    problems = check(os.path.join(sys.argv[1], 'src'))
    for p in problems:
        print(p)
    sys.exit(1 if problems else 0)
