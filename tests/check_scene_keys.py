#!/usr/bin/env python3
"""Checks that docs/scene-reference.md documents exactly the scene keys the readers accept.

The readers declare the keys of each YAML mapping with one call
`YamlReader::allowKeys(map, path, {"key", ...})`. Each such call is one key set. The reference
documents each mapping in a table whose header row starts with `| key |`; the first cell of
every row names one key in backticks. Each table is one key set.

The element and constraint kinds of src/scene/KindTable.cpp must be the headings ### `kind`.
Every key set of the code must equal the key set of some table, and every table must equal
some key set of the code. A key added to a reader and not documented, a documented key that no
reader accepts, or a key moved from one mapping to another therefore fails the test, which
prints the nearest table or call and the keys that differ.

Usage: check_scene_keys.py [SOURCE_DIR]   (default: the checkout this file is in)
Exit status 0 when the sets agree, 1 when they differ, 2 when nothing was found to compare.
"""
import pathlib
import re
import sys

SOURCE_DIRS = ("src", "elements", "constraints", "pim", "meshes")
CALL = re.compile(r"\ballowKeys\s*\(")
STRING = re.compile(r'"((?:[^"\\]|\\.)*)"')
KEY_CELL = re.compile(r"^\|\s*`([^`]+)`")


def call_text(text, start):
    """The text of the call's argument list from the '(' at `start` to its matching ')'."""
    depth, i = 0, start
    while i < len(text):
        ch = text[i]
        if ch == '"':  # skip string literals (they may hold parentheses)
            i += 1
            while i < len(text) and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
        elif ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                return text[start + 1:i]
        i += 1
    raise ValueError("unbalanced parentheses after allowKeys")


def code_key_sets(root):
    """[(location, frozenset of keys)] for every allowKeys call with a braced key list."""
    sets = []
    for sub in SOURCE_DIRS:
        for path in sorted((root / sub).rglob("*")):
            if path.suffix not in (".cpp", ".hpp", ".h") or not path.is_file():
                continue
            text = path.read_text(encoding="utf-8", errors="replace")
            for m in CALL.finditer(text):
                args = call_text(text, m.end() - 1)
                brace = args.find("{")
                if brace < 0:
                    continue  # the declaration or definition, not a call with keys
                keys = frozenset(STRING.findall(args[brace:]))
                if not keys:
                    continue
                line = text.count("\n", 0, m.start()) + 1
                sets.append((f"{path.relative_to(root)}:{line}", keys))
    return sets


def doc_key_sets(doc):
    """[(location, frozenset of keys)] for every table whose header row starts with `| key |`."""
    sets, current, start = [], None, 0
    lines = doc.read_text(encoding="utf-8").splitlines()
    for number, line in enumerate(lines + [""], start=1):
        stripped = line.strip()
        if current is None:
            if re.match(r"^\|\s*key\s*\|", stripped):
                current, start = [], number
            continue
        if not stripped.startswith("|"):
            sets.append((f"{doc.name}:{start}", frozenset(current)))
            current = None
            continue
        m = KEY_CELL.match(stripped)
        if m:
            current.append(m.group(1))
    return sets


def code_kinds(root):
    """Element and constraint kind names of the scene's kind table ({"kind", readKind})."""
    text = (root / "src" / "scene" / "KindTable.cpp").read_text(encoding="utf-8")
    return set(re.findall(r'\{\s*"([a-z0-9_]+)"\s*,\s*read\w+\s*\}', text))


def doc_kinds(doc):
    """Kinds documented as level-3 headings of the form ### `kind`."""
    return set(re.findall(r"^###\s+`([a-z0-9_]+)`\s*$", doc.read_text(encoding="utf-8"), re.M))


def nearest(keys, candidates):
    """The candidate sharing the most keys with `keys` (ties: the smaller difference)."""
    return max(candidates, key=lambda c: (len(keys & c[1]), -len(keys ^ c[1])))


def describe(keys, other):
    missing = sorted(keys - other[1])
    extra = sorted(other[1] - keys)
    parts = []
    if missing:
        parts.append("missing there: " + ", ".join(missing))
    if extra:
        parts.append("extra there: " + ", ".join(extra))
    return f"nearest is {other[0]} ({'; '.join(parts)})"


def main():
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    doc = root / "docs" / "scene-reference.md"
    code = code_key_sets(root)
    tables = doc_key_sets(doc) if doc.is_file() else []
    if not code or not tables:
        print(f"check_scene_keys: found {len(code)} allowKeys calls and {len(tables)} key tables in {doc}")
        return 2
    doc_sets = {s for _, s in tables}
    code_sets = {s for _, s in code}
    problems = []
    for where, keys in code:
        if keys not in doc_sets:
            problems.append(f"{where}: keys {sorted(keys)} are not one table of {doc.name}; "
                            + describe(keys, nearest(keys, tables)))
    for where, keys in tables:
        if keys not in code_sets:
            problems.append(f"{where}: table keys {sorted(keys)} are not one allowKeys call of the readers; "
                            + describe(keys, nearest(keys, code)))
    kinds, documented = code_kinds(root), doc_kinds(doc)
    if not kinds:
        problems.append("src/scene/KindTable.cpp: no kinds found")
    for k in sorted(kinds - documented):
        problems.append(f"kind '{k}' of src/scene/KindTable.cpp has no heading ### `{k}` in {doc.name}")
    for k in sorted(documented - kinds):
        problems.append(f"{doc.name}: heading ### `{k}` names no kind of src/scene/KindTable.cpp")
    if problems:
        print("check_scene_keys: docs/scene-reference.md and the scene readers disagree:")
        for p in problems:
            print("  " + p)
        print("Document each mapping's keys as one `| key | meaning |` table, one key in backticks per row,"
              " and each element or constraint kind under a heading ### `kind`.")
        return 1
    print(f"check_scene_keys: {len(code)} allowKeys calls ({len(code_sets)} distinct key sets, "
          f"{len(set().union(*code_sets))} keys) match {len(tables)} tables of {doc.name}; "
          f"{len(kinds)} element and constraint kinds have their headings")
    return 0


if __name__ == "__main__":
    sys.exit(main())
