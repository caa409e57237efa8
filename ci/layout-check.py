#!/usr/bin/env python3
"""The code as a map, kept true (docs/architecture.md, "Rules of the map").

Fails (exit 1) when, anywhere in `src/`, `shaders/` or `python/src/`:

- a source file (Rust or GLSL) is over 800 lines;
- two or more files of `src/` import each other in a loop: file A names an
  item of file B (a `use` or a path written out), and B, directly or
  through others, names one of A's;
- a function outside tests is over 100 lines, from its `fn` line to its
  closing brace;
- a command of the CLI names an item of another command (a file under
  `src/cli/<command>/`, or `src/cli/<command>.rs`, importing from another
  command's), or `src/cli/common/`, which every command shares, names a
  command's; or the library (`src/` outside `src/cli/` and `src/main.rs`)
  names anything of `cli`.

The same rules hold in `tests/` (`check_tests_folder`), for every
function there, `#[test]` ones included, and for import loops within
each test binary.

An item reached through a re-export (`pub use child::Thing` in a `mod.rs`)
counts as an import of the file that defines it, not of the re-exporting
one, so that a parent which re-exports its children is not a loop with
them. `mod child;` declarations are not imports: a parent owns its
children's files, it does not read them.

`--list` prints every file and function over half the limits, largest
first, and the import edges of each loop, to plan a split.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

MAX_FILE_LINES = 800
MAX_FUNCTION_LINES = 100

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"
SHADERS = ROOT / "shaders"


def set_root(root: Path):
    """Checks another tree (ci/test_layout_check.py's small ones)."""
    global ROOT, SRC, SHADERS
    ROOT, SRC, SHADERS = root, root / "src", root / "shaders"

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"


def strip_comments_and_strings(text: str) -> str:
    """Blanks comments, string and char literals (keeping line breaks), so
    that braces and paths inside them are not read as code."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "r" and re.match(r'r#*"', text[i:i + 8]) and not re.match(r"[A-Za-z0-9_]", text[i - 1] if i else " "):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + 2 + len(hashes))
            end = n if end < 0 else end + 1 + len(hashes)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(re.sub(r"[^\n]", " ", text[i:j + 1]))
            i = j + 1
        elif c == "'" and re.match(r"'(\\.|[^\\'])'|'\\u\{[0-9a-fA-F]+\}'|'\\x[0-9a-fA-F]{2}'", text[i:i + 12]):
            m = re.match(r"'(\\.|[^\\'])'|'\\u\{[0-9a-fA-F]+\}'|'\\x[0-9a-fA-F]{2}'", text[i:i + 12])
            out.append(" " * len(m.group(0)))
            i += len(m.group(0))
        else:
            out.append(c)
            i += 1
    return "".join(out)


def module_of(path: Path) -> tuple[str, ...]:
    rel = path.relative_to(SRC).with_suffix("")
    parts = rel.parts
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


def rust_files() -> dict[tuple[str, ...], Path]:
    files = {}
    for path in sorted(SRC.rglob("*.rs")):
        if path.name == "main.rs":
            continue  # the binary's root: it imports the library, no one imports it
        files[module_of(path)] = path
    return files


def test_spans(code: str) -> list[tuple[int, int]]:
    """Character spans of `#[cfg(test)]` items (test modules)."""
    spans = []
    for m in re.finditer(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*\{", code):
        end = matching_brace(code, m.end() - 1)
        spans.append((m.start(), end))
    return spans


def matching_brace(code: str, open_at: int) -> int:
    depth = 0
    for j in range(open_at, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


def outside(spans, pos):
    return not any(a <= pos <= b for a, b in spans)


def reexports(files, codes):
    """For each module, the names it re-exports: name -> module path the
    `pub use` points at (resolved relative to the module)."""
    table = {}
    for module, code in codes.items():
        names = {}
        for m in re.finditer(r"pub(\([^)]*\))?\s+use\s+([^;]+);", code):
            for path, alias in expand_use(m.group(2)):
                full = absolute(module, files[module], path)
                if full is None and path and tuple(module) + (path[0],) in files:
                    full = tuple(module) + tuple(path)  # `pub use child::Thing`
                if full is None:
                    continue
                names[alias or path[-1]] = full
        table[module] = names
    return table


def expand_use(tree: str):
    """`a::{b, c::d as e}` -> [(['a','b'], None), (['a','c','d'], 'e')]."""
    tree = re.sub(r"\s+", "", tree)
    results = []

    def walk(prefix, t):
        if t.startswith("{") and t.endswith("}"):
            for part in split_top(t[1:-1]):
                if part:
                    walk(prefix, part)
            return
        m = re.match(r"^((?:" + IDENT + r"::)*)(\{.*\})$", t)
        if m:
            walk(prefix + [p for p in m.group(1).split("::") if p], m.group(2))
            return
        alias = None
        if "as" in t and re.search(r"\bas" + IDENT, t):
            pass
        m = re.match(r"^(.*?)(?:as(" + IDENT + r"))?$", t)
        body = t
        am = re.match(r"^((?:" + IDENT + r"::)*" + IDENT + r")as(" + IDENT + r")$", t)
        if am:
            body, alias = am.group(1), am.group(2)
        parts = [p for p in body.split("::") if p]
        if parts and parts[-1] == "*":
            parts = parts[:-1]
            alias = "*"
        results.append((prefix + parts, alias))

    def split_top(s):
        depth, cur, out = 0, "", []
        for ch in s:
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            if ch == "," and depth == 0:
                out.append(cur)
                cur = ""
            else:
                cur += ch
        out.append(cur)
        return out

    walk([], tree)
    return results


def absolute(module, path_file, parts):
    """A use path made absolute (a tuple from the crate root), or None for an
    outside crate."""
    parts = list(parts)
    if not parts:
        return None
    is_dir_module = path_file.name in ("mod.rs", "lib.rs")
    if parts[0] == "crate":
        return tuple(parts[1:])
    if parts[0] == "self":
        return tuple(module) + tuple(parts[1:])
    if parts[0] == "super":
        base = list(module)
        while parts and parts[0] == "super":
            base = base[:-1]
            parts = parts[1:]
        return tuple(base) + tuple(parts)
    return None


def resolve(files, exports, path, depth=0):
    """The file module an absolute path lands in: the longest prefix that is
    a file, followed through re-exports."""
    for k in range(len(path), -1, -1):
        prefix = tuple(path[:k])
        if prefix in files:
            rest = path[k:]
            if rest and depth < 8:
                target = exports.get(prefix, {}).get(rest[0])
                if target is not None and tuple(target) != prefix + (rest[0],):
                    return resolve(files, exports, tuple(target) + tuple(rest[1:]), depth + 1)
            return prefix
    return None


def import_graph(files):
    # `pub(in crate::x)` names a module for visibility, not an import.
    codes = {
        m: re.sub(r"pub\(in [^)]*\)", lambda v: " " * len(v.group(0)), strip_comments_and_strings(p.read_text()))
        for m, p in files.items()
    }
    exports = reexports(files, codes)
    edges = {m: {} for m in files}
    for module, code in codes.items():
        spans = test_spans(code)
        refs = []
        for m in re.finditer(r"\buse\s+([^;]+);", code):
            if not outside(spans, m.start()):
                continue
            line = code.count("\n", 0, m.start()) + 1
            for parts, _ in expand_use(m.group(1)):
                refs.append((parts, line))
        for m in re.finditer(r"\b((?:crate|super|self)(?:::(?:super|" + IDENT + r"))+)", code):
            if not outside(spans, m.start()):
                continue
            line = code.count("\n", 0, m.start()) + 1
            refs.append((m.group(1).split("::"), line))
        # A child module named by its bare name (`child::f()`, `use
        # child::Thing`) in the file that declares it.
        for m in re.finditer(r"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+(" + IDENT + r")\s*;", code, re.M):
            child = m.group(1)
            for use in re.finditer(r"(?<![:\w])" + child + r"::((?:" + IDENT + r"::)*" + IDENT + r"|\{)", code):
                if not outside(spans, use.start()):
                    continue
                line = code.count("\n", 0, use.start()) + 1
                rest = use.group(1).split("::") if use.group(1) != "{" else []
                refs.append((["self", child] + rest, line))
        for parts, line in refs:
            full = absolute(module, files[module], parts)
            if full is None:
                continue
            target = resolve(files, exports, full)
            if target is None or target == module:
                continue
            # A child naming its own ancestor module's items through
            # `super` is an import too; keep it.
            edges[module].setdefault(target, line)
    return edges


def loops(edges):
    """Strongly connected components of more than one file (Tarjan)."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


# The CLI's folder that every command may import: what they share.
CLI_SHARED = "common"


def command_imports(files, edges):
    """Problems where the commands of `src/cli/` are not apart, or the
    library leans on the CLI (docs/architecture.md, "A new command").

    A command is a folder `src/cli/<command>/` or a file
    `src/cli/<command>.rs`; it may import `src/cli/common/` and the library,
    never another command: what two commands use is shared, or library
    work. `src/cli/common/` imports no command, and `src/cli/mod.rs`, which
    dispatches to every command, is neither. The library (every file of
    `src/` outside `src/cli/`; `src/main.rs` is not read) names nothing of
    `cli`, and declares no module `cli`: it must work without a command
    line (a Python package calls it)."""
    problems = []
    for source, targets in sorted(edges.items()):
        for target, line in sorted(targets.items(), key=lambda kv: kv[1]):
            where = f"{files[source].relative_to(ROOT)}:{line}"
            named = files[target].relative_to(ROOT)
            if source[:1] != ("cli",):
                if target[:1] == ("cli",):
                    problems.append(f"{where}: the library imports the command line ({named})")
                continue
            if len(source) < 2 or len(target) < 2 or target[0] != "cli":
                continue
            own, other = source[1], target[1]
            if other in (own, CLI_SHARED):
                continue
            if own == CLI_SHARED:
                problems.append(
                    f"{where}: src/cli/{CLI_SHARED}/ imports the command {other} ({named}); "
                    "what the commands share depends on none of them"
                )
            else:
                problems.append(
                    f"{where}: the command {own} imports the command {other} ({named}); "
                    f"move what both use into src/cli/{CLI_SHARED}/ or the library"
                )
    for module, path in sorted(files.items()):
        if module[:1] == ("cli",):
            continue
        code = strip_comments_and_strings(path.read_text())
        for m in re.finditer(r"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+cli\b", code, re.M):
            line = code.count("\n", 0, m.start()) + 1
            problems.append(f"{path.relative_to(ROOT)}:{line}: the library declares the command line (mod cli)")
    return problems


def functions(path: Path, keep_tests: bool = False):
    """(name, first line, length in lines) of every function outside test
    modules and `#[test]` functions; with `keep_tests`, of every one."""
    code = strip_comments_and_strings(path.read_text())
    spans = [] if keep_tests else test_spans(code)
    found = []
    for m in re.finditer(r"\bfn\s+(" + IDENT + r")\s*(<[^{;]*?>)?\s*\(", code):
        if not outside(spans, m.start()):
            continue
        before = code[max(0, m.start() - 200):m.start()]
        if not keep_tests and re.search(r"#\[test\]\s*(pub\s+)?$", before):
            continue
        # The body starts at the first `{` after the signature; a `;` first
        # means a declaration without a body (a trait method).
        j = m.end()
        depth = 1
        while j < len(code) and depth:
            if code[j] == "(":
                depth += 1
            elif code[j] == ")":
                depth -= 1
            j += 1
        brace = code.find("{", j)
        semi = code.find(";", j)
        if brace < 0 or (0 <= semi < brace):
            continue
        end = matching_brace(code, brace)
        first = code.count("\n", 0, m.start()) + 1
        last = code.count("\n", 0, end) + 1
        found.append((m.group(1), first, last - first + 1))
    return found


def glsl_functions(path: Path):
    code = strip_comments_and_strings(path.read_text())
    found = []
    pattern = r"^[ \t]*(?:" + IDENT + r"\s+)+(" + IDENT + r")\s*\([^;{]*\)\s*\{"
    for m in re.finditer(pattern, code, re.M):
        if m.group(1) in ("if", "for", "while", "switch"):
            continue
        end = matching_brace(code, m.end() - 1)
        first = code.count("\n", 0, m.start()) + 1
        last = code.count("\n", 0, end) + 1
        found.append((m.group(1), first, last - first + 1))
    return found


# The test files (tests/): the same limits as src/, and every function
# counts, `#[test]` ones too. Each test binary is its own crate, so import
# loops are looked for within one binary: a `.rs` file directly in `tests/`
# alone, or a folder's `main.rs` and the modules under that folder, with
# `tests/common/` as the module `common` of every binary that declares it.

TEST_ROOT_COMMON = re.compile(r"^\s*(?:#\[path\s*=\s*\"[^\"]*\"\]\s*)?(?:pub\s+)?mod\s+common\s*;", re.M)


def test_sources(tests: Path) -> list[Path]:
    """Every Rust file of `tests/` but the fixtures (`tests/data/`)."""
    return [p for p in sorted(tests.rglob("*.rs")) if "data" not in p.relative_to(tests).parts[:1]]


def test_binaries(tests: Path) -> dict[str, dict[tuple[str, ...], Path]]:
    """Each test binary's files by module path (the root is `()`)."""
    def tree(folder: Path, root: Path) -> dict[tuple[str, ...], Path]:
        files = {}
        for path in sorted(folder.rglob("*.rs")):
            parts = path.relative_to(folder).with_suffix("").parts
            if parts[-1] in ("mod", "main"):
                parts = parts[:-1]
            if path == root or parts:
                files[tuple(parts)] = path
        return files

    binaries = {}
    roots = [(p.stem, p, None) for p in sorted(tests.glob("*.rs"))]
    roots += [(p.parent.name, p, p.parent) for p in sorted(tests.glob("*/main.rs"))]
    for name, root, folder in roots:
        files = tree(folder, root) if folder else {(): root}
        common = tests / "common"
        if common.is_dir() and TEST_ROOT_COMMON.search(strip_comments_and_strings(root.read_text())):
            for parts, path in tree(common, common / "mod.rs").items():
                files[("common",) + parts] = path
        binaries[name] = files
    return binaries


def check_tests_folder(listing: bool) -> list[str]:
    """The problems in `tests/`: files over the line limit, functions
    (tests included) over theirs, import loops within a test binary."""
    tests = ROOT / "tests"
    if not tests.is_dir():
        return []
    problems, sizes, lengths = [], [], []
    sources = test_sources(tests)
    for path in sources:
        n = len(path.read_text().splitlines())
        sizes.append((n, path.relative_to(ROOT)))
        if n > MAX_FILE_LINES:
            problems.append(f"{path.relative_to(ROOT)}: {n} lines (at most {MAX_FILE_LINES})")
        for name, line, length in functions(path, keep_tests=True):
            lengths.append((length, f"{path.relative_to(ROOT)}:{line}", name))
            if length > MAX_FUNCTION_LINES:
                problems.append(
                    f"{path.relative_to(ROOT)}:{line}: fn {name} is {length} lines (at most {MAX_FUNCTION_LINES})"
                )
    binaries = test_binaries(tests)
    for binary, files in binaries.items():
        edges = import_graph(files)
        for comp in loops(edges):
            detail = [
                f"{files[a].relative_to(ROOT)}:{edges[a][b]} -> {files[b].relative_to(ROOT)}"
                for a in comp for b in comp if b in edges[a]
            ]
            names = [str(files[m].relative_to(ROOT)) for m in comp]
            problems.append(f"import loop in test binary {binary}: " + ", ".join(names) + "\n    " + "\n    ".join(detail))
    if listing:
        print("Test files over half the limit:")
        for n, p in sorted(sizes, reverse=True):
            if n > MAX_FILE_LINES // 2:
                print(f"  {n:5} {p}")
        print("Test functions over half the limit:")
        for n, where, name in sorted(lengths, reverse=True):
            if n > MAX_FUNCTION_LINES // 2:
                print(f"  {n:5} {where} {name}")
    if not problems:
        print(
            f"layout-check: tests/: {len(sources)} files within {MAX_FILE_LINES} lines, "
            f"{len(lengths)} functions within {MAX_FUNCTION_LINES}, no import loop in {len(binaries)} test binaries"
        )
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--list", action="store_true", help="list what is near or over the limits")
    parser.add_argument("--root", type=Path, help="the repository to check (default: this one)")
    args = parser.parse_args()
    if args.root:
        set_root(args.root.resolve())

    problems = []
    # The Python package's Rust half (python/src/) keeps the same limits.
    sources = (
        sorted(SRC.rglob("*.rs"))
        + sorted(SHADERS.rglob("*.glsl"))
        + sorted((ROOT / "python" / "src").rglob("*.rs"))
    )
    sizes = []
    for path in sources:
        n = len(path.read_text().splitlines())
        sizes.append((n, path.relative_to(ROOT)))
        if n > MAX_FILE_LINES:
            problems.append(f"{path.relative_to(ROOT)}: {n} lines (at most {MAX_FILE_LINES})")

    long_functions = []
    for path in sources:
        found = functions(path) if path.suffix == ".rs" else glsl_functions(path)
        for name, line, length in found:
            long_functions.append((length, f"{path.relative_to(ROOT)}:{line}", name))
            if length > MAX_FUNCTION_LINES:
                problems.append(
                    f"{path.relative_to(ROOT)}:{line}: fn {name} is {length} lines (at most {MAX_FUNCTION_LINES})"
                )

    files = rust_files()
    edges = import_graph(files)
    for comp in loops(edges):
        names = ["src/" + "/".join(m) if m else "src/lib.rs" for m in comp]
        detail = []
        for a in comp:
            for b in comp:
                if b in edges[a]:
                    detail.append(f"{files[a].relative_to(ROOT)}:{edges[a][b]} -> {files[b].relative_to(ROOT)}")
        problems.append("import loop: " + ", ".join(names) + "\n    " + "\n    ".join(detail))
    problems.extend(command_imports(files, edges))

    problems += check_tests_folder(args.list)

    if args.list:
        print("Files over half the limit:")
        for n, p in sorted(sizes, reverse=True):
            if n > MAX_FILE_LINES // 2:
                print(f"  {n:5} {p}")
        print("Functions over half the limit:")
        for n, where, name in sorted(long_functions, reverse=True):
            if n > MAX_FUNCTION_LINES // 2:
                print(f"  {n:5} {where} {name}")

    if problems:
        print(f"layout-check: {len(problems)} problem(s):")
        for p in problems:
            print("  " + p)
        sys.exit(1)
    print(
        f"layout-check: {len(sources)} files within {MAX_FILE_LINES} lines, "
        f"{len(long_functions)} functions within {MAX_FUNCTION_LINES}, no import loop among {len(files)} files, "
        "no command importing another"
    )


if __name__ == "__main__":
    main()
