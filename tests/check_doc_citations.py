#!/usr/bin/env python3
"""Fails when a comment cites documentation that is gone.

A citation is `docs/<file>.md "Heading"` (or `README "Heading"`) in a source, script or format
file; the file must exist and, when a heading is quoted, one of its Markdown headings must be that
heading (backticks ignored; a heading may go on after the quoted part with " (…)", ":" or ",").
A citation may wrap across comment lines. Relative links in README.md, CONTRIBUTING.md and docs/
must name files that exist.

Usage: check_doc_citations.py SOURCE_DIR        check the tree, exit 1 listing every broken one
       check_doc_citations.py --self-test       the checker catches a missing file and heading
"""
import pathlib
import re
import sys
import tempfile

SCAN_DIRS = ["src", "include", "tests", "bench", "fuzz", "scripts", "formats", "cmake", ".ci", "addons"]
SCAN_SUFFIXES = {".cpp", ".h", ".c", ".inc", ".py", ".sh", ".cmake", ".txt", ".md", ".glsl",
                 ".hlsl", ".mjs", ".json", ".gd", ".gdshader", ".gdshaderinc", ""}
SKIP_DIRS = {"data", "node_modules", "build"}
COMMENT_LEAD = re.compile(r"^\s*(?://+|/\*+|\*+/?|#+)?\s?")
CITATION = re.compile(r'(docs/[A-Za-z0-9_./-]+\.md|README(?:\.md)?)(?:,)?\s*(?:"([^"\n]+)")?')
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def headings(md: pathlib.Path) -> list[str]:
    out, fenced = [], False
    for line in md.read_text(encoding="utf-8").splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
        elif not fenced and re.match(r"^#{1,6} ", line):
            out.append(line.lstrip("#").strip().replace("`", ""))
    return out


def heading_exists(cited: str, found: list[str]) -> bool:
    cited = " ".join(cited.replace("`", "").split())
    for h in found:
        if h == cited or (h.startswith(cited) and h[len(cited)] in " (:,"):
            return True
    return False


def flattened(path: pathlib.Path) -> str:
    # Comment markers removed and lines joined, so a citation may wrap.
    text = path.read_text(encoding="utf-8", errors="replace")
    return " ".join(COMMENT_LEAD.sub("", line, count=1) for line in text.splitlines())


def source_files(root: pathlib.Path):
    for d in SCAN_DIRS:
        base = root / d
        if not base.is_dir():
            continue
        for p in sorted(base.rglob("*")):
            if p.is_file() and p.suffix in SCAN_SUFFIXES and not SKIP_DIRS & set(p.relative_to(root).parts):
                yield p
    cm = root / "CMakeLists.txt"
    if cm.is_file():
        yield cm


def check(root: pathlib.Path) -> list[str]:
    errors, cache = [], {}
    for path in source_files(root):
        if path.resolve() == pathlib.Path(__file__).resolve():
            continue  # this file's own examples
        for m in CITATION.finditer(flattened(path)):
            target, heading = m.group(1), m.group(2)
            if target.startswith("README") and heading is None:
                continue  # "README command 1" and the like: no section named
            doc = root / ("README.md" if target.startswith("README") else target)
            where = f"{path.relative_to(root)}: {target}" + (f' "{heading}"' if heading else "")
            if not doc.is_file():
                errors.append(f"{where}: no such file")
                continue
            if heading is not None:
                if doc not in cache:
                    cache[doc] = headings(doc)
                if not heading_exists(heading, cache[doc]):
                    errors.append(f"{where}: no such heading in {doc.relative_to(root)}")
    docs = [root / "README.md", root / "CONTRIBUTING.md"] + sorted((root / "docs").rglob("*.md"))
    for md in docs:
        if not md.is_file():
            continue
        for m in LINK.finditer(md.read_text(encoding="utf-8")):
            link = m.group(1)
            if re.match(r"^[a-z]+:", link):
                continue  # http:, https:, mailto:
            if not (md.parent / link).exists():
                errors.append(f"{md.relative_to(root)}: link to missing {link}")
    return errors


def self_test() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / "docs").mkdir()
        (root / "src").mkdir()
        (root / "docs" / "fit.md").write_text("# The fit (`src/fit/`)\n\n## Choosing ε, the horizon rule\n"
                                               "```\n# not a heading\n```\n")
        good = '// ok (docs/fit.md "The fit"; docs/fit.md\n// "Choosing ε")\n'
        (root / "src" / "a.cpp").write_text(good)
        if check(root):
            print("self-test: good citations reported:", check(root))
            return 1
        (root / "src" / "b.cpp").write_text('// (docs/fit.md "not a heading") (docs/gone.md "X")\n')
        errs = check(root)
        if len(errs) != 2:
            print("self-test: expected 2 broken citations, got", errs)
            return 1
    print("self-test: ok")
    return 0


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    errors = check(pathlib.Path(sys.argv[1]))
    for e in errors:
        print(e)
    print(f"{len(errors)} broken citation(s)" if errors else "every citation names an existing file and heading")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
