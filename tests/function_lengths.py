#!/usr/bin/env python3
"""Counts the lines of every C++ function body and fails listing each one over the limit.

Usage: function_lengths.py [--max-lines 120] [--list N] [--allow FILE] ROOT [DIR ...]
       function_lengths.py --self-test

--allow FILE names functions known to be longer (lines "PATH FUNCTION LINES", # comments): each
may stay at most that long until it is split, and an entry that is no longer over the limit
fails too (take it out), so the list only shrinks.
  DIR defaults to src elements constraints pim meshes (relative to ROOT).

A function's length is the number of lines from the line that opens its header (return type,
name, parameters; template<...> lines included) to the line of its closing brace. Lambdas and
local classes inside a function count toward it; a lambda bound at namespace scope
(`auto f = [](...) {`) counts as its own function.

The scan works on a copy of each file in which comments, string and character literals (raw
strings too) and preprocessor lines are blanked, keeping the line breaks, so braces inside them
do not count. Braces are then matched: a block opened in namespace or class scope is a function
body when its header has a parameter list and no `=` outside parentheses (aggregate initializers,
`enum` and brace-initialized members are skipped); in a constructor's initializer list, a brace
that follows a name is the member's initializer, one that follows `)` or `}` opens the body.
"""
import argparse
import os
import re
import sys

SOURCE_EXTENSIONS = (".cpp", ".hpp", ".h", ".cc", ".hh", ".cxx", ".hxx", ".inl")
DEFAULT_DIRS = ("src", "elements", "constraints", "pim", "meshes")


def blank(text, start, end):
    """The span [start, end) of text as spaces, line breaks kept."""
    return "".join("\n" if ch == "\n" else " " for ch in text[start:end])


def strip_code(text):
    """text with comments, literals and preprocessor lines replaced by spaces (same length)."""
    out = []
    i, n = 0, len(text)
    line_start = True  # only whitespace since the last line break
    while i < n:
        ch = text[i]
        if line_start and ch == "#":
            j = i
            while j < n and text[j] != "\n":
                if text[j] == "\\" and j + 1 < n and text[j + 1] == "\n":
                    j += 2
                    continue
                if text.startswith("/*", j):  # a block comment may run past the directive's line
                    close = text.find("*/", j + 2)
                    j = n if close < 0 else close + 2
                    continue
                j += 1
            out.append(blank(text, i, j))
            i = j
            continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(blank(text, i, j))
            i = j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(blank(text, i, j))
            i = j
            continue
        raw = re.match(r'(?:u8|u|U|L)?R"([^()\\\s]{0,16})\(', text[i:i + 24])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = text.find(")" + raw.group(1) + '"', i + raw.end())
            j = n if close < 0 else close + len(raw.group(1)) + 2
            out.append('"' + blank(text, i + 1, j - 1) + '"')
            i = j
            continue
        if ch == "'" and is_digit_separator(text, i):
            out.append(ch)
            i += 1
            continue
        if ch in "\"'":
            j = i + 1
            while j < n and text[j] != ch and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(ch + blank(text, i + 1, j - 1) + ch)
            i = j
            continue
        out.append(ch)
        if ch == "\n":
            line_start = True
        elif not ch.isspace():
            line_start = False
        i += 1
    return "".join(out)


def is_digit_separator(text, i):
    """True when the quote at i sits inside a number literal such as 1'000'000."""
    j = i - 1
    while j >= 0 and (text[j].isalnum() or text[j] in "_'."):
        j -= 1
    token = text[j + 1:i]
    return bool(token) and token[0].isdigit() and i + 1 < len(text) and text[i + 1].isalnum()


def match_close(code, open_index, opener="{", closer="}"):
    """Index of the bracket closing the one at open_index (len(code) - 1 if unbalanced)."""
    depth = 0
    for j in range(open_index, len(code)):
        if code[j] == opener:
            depth += 1
        elif code[j] == closer:
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


def drop_template_heads(header):
    """header without `template <...>` prefixes (their `class T` is not a class)."""
    while True:
        found = re.search(r"\btemplate\s*<", header)
        if not found:
            return header
        depth, j = 0, found.end() - 1
        while j < len(header):
            if header[j] == "<":
                depth += 1
            elif header[j] == ">":
                depth -= 1
                if depth == 0:
                    break
            j += 1
        header = header[:found.start()] + " " + header[j + 1:]


def normalize(header):
    header = re.sub(r"\[\[.*?\]\]", " ", header, flags=re.S)  # attributes
    header = drop_template_heads(header)
    header = re.sub(r"\boperator\s*(\(\)|\[\]|[^\s(]+)", "operator_", header)
    header = re.sub(r"^\s*(public|private|protected)\s*:(?!:)", " ", header)
    return header


def top_level(header):
    """header with everything inside (), <> kept out: characters at depth 0 only."""
    out, depth = [], 0
    for ch in header:
        if ch == "(":
            depth += 1
            out.append("(" if depth == 1 else " ")
        elif ch == ")":
            depth -= 1
            out.append(")" if depth == 0 else " ")
        else:
            out.append(ch if depth == 0 else " ")
    return "".join(out)


def classify(header):
    """'namespace', 'class', 'function', 'member-init' (brace inside a header) or 'other'."""
    h = normalize(header)
    flat = top_level(h)
    if re.search(r"\bnamespace\b", flat) or re.fullmatch(r'\s*extern\s*"\s*"\s*', flat):
        return "namespace"
    if re.search(r"=\s*\[[^\]]*\]\s*(\(\s*\))?\s*(mutable\s*)?(->[^{]*)?$", flat):
        return "function"  # a lambda bound at namespace or class scope
    if re.search(r"(?<![=!<>])=(?!=)", flat):
        return "other"
    if re.search(r"\benum\b", flat):
        return "other"
    paren = flat.find("(")
    klass = re.search(r"\b(class|struct|union)\b", flat)
    if klass and (paren < 0 or klass.start() < paren):
        return "class"
    if paren < 0:
        return "other"
    tail = flat[flat.find(")", paren) + 1:]
    if re.search(r"(?<!:):(?!:)", tail):  # constructor with an initializer list
        return "function" if re.search(r"[)}]\s*$", h) else "member-init"
    return "function"


def function_name(header):
    flat = top_level(normalize(header))
    lambda_bound = re.search(r"([\w:]+)\s*=\s*\[", flat)
    if lambda_bound:
        return lambda_bound.group(1)
    paren = flat.find("(")
    found = re.search(r"([~\w:]+(?:<[^()]*>)?)\s*$", flat[:paren])
    return found.group(1) if found else flat.strip()[:40]


def functions_in(code):
    """(name, first line, last line) of every function in stripped code, lines from 1."""
    found = []
    line_of = []
    line = 1
    for ch in code:
        line_of.append(line)
        if ch == "\n":
            line += 1
    line_of.append(line)

    depth_kinds = []  # scope kinds of the open namespace/class blocks
    header_start = 0
    i = 0
    while i < len(code):
        ch = code[i]
        if ch == "{":
            header = code[header_start:i]
            kind = classify(header)
            if kind in ("namespace", "class"):
                depth_kinds.append(kind)
                header_start = i + 1
                i += 1
                continue
            close = match_close(code, i)
            if kind == "function":
                lead = re.match(r"(\s|(public|private|protected)\s*:(?!:))*", header)
                first = header_start + lead.end()
                found.append((function_name(header), line_of[first], line_of[close]))
                header_start = close + 1
            i = close + 1  # 'other' and 'member-init': the header runs on to its ';' or body
            continue
        if ch == "}":
            if depth_kinds:
                depth_kinds.pop()
            header_start = i + 1
        elif ch == ";":
            header_start = i + 1
        i += 1
    return found


def scan(root, dirs):
    results = []
    for directory in dirs:
        for base, _, files in os.walk(os.path.join(root, directory)):
            for name in sorted(files):
                if not name.endswith(SOURCE_EXTENSIONS):
                    continue
                path = os.path.join(base, name)
                with open(path, encoding="utf-8", errors="replace") as handle:
                    code = strip_code(handle.read())
                for function, first, last in functions_in(code):
                    results.append((last - first + 1, os.path.relpath(path, root), first, function))
    return results


SELF_TEST_SOURCE = r'''
#include <map>
#define OPEN_BRACE {
namespace outer { namespace {
struct Point { double x{0.0}; double y = 1.0; };
enum class Colour { red, green };
const std::map<int, int> table = { {1, 2}, {3, 4} };
template <class T> T twice(T value) {
  return value + value;  // } in a comment
}
class Holder : public Base {
 public:
  Holder(int a, int b) : a_(a), b_{b}, name_("{") {
    auto lambda = [this](int c) { return a_ + c; };
    const char* brace = "}}}";
    char open = '{';
    (void)lambda; (void)brace; (void)open;
  }
  int get() const override { return 1'000 + a_; }
  bool operator==(const Holder& other) const { return a_ == other.a_; }
 private:
  int a_, b_;
};
auto scale = [](double v) {
  /* { */ return 2.0 * v;
};
}  // namespace
}  // namespace outer
extern "C" {
int plain(void) {
  const char* raw = R"x(})x";
  for (int i = 0; i < 3; ++i) { if (i) { continue; } }
  return 0;
}
}
'''
SELF_TEST_EXPECTED = [("twice", 8, 10), ("Holder", 13, 18), ("get", 19, 19),
                      ("operator_", 20, 20), ("scale", 24, 26), ("plain", 30, 34)]


def self_test():
    """The scanner on a sample with the constructs it must see through; 0 when all found."""
    found = functions_in(strip_code(SELF_TEST_SOURCE))
    if found != SELF_TEST_EXPECTED:
        print("self test failed:\n  found    ", found, "\n  expected ", SELF_TEST_EXPECTED)
        return 1
    print("self test passed:", len(found), "functions with their line spans")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    if "--self-test" in sys.argv[1:]:
        return self_test()
    parser.add_argument("root")
    parser.add_argument("dirs", nargs="*", default=list(DEFAULT_DIRS))
    parser.add_argument("--max-lines", type=int, default=120)
    parser.add_argument("--list", type=int, default=0, help="also print the N longest functions")
    parser.add_argument("--allow", help="file of functions allowed to be longer for now")
    args = parser.parse_args()
    allowed = {}
    if args.allow:
        with open(args.allow, encoding="utf-8") as handle:
            for line in handle:
                fields = line.split("#", 1)[0].split()
                if fields:
                    allowed[(fields[0], fields[1])] = int(fields[2])

    results = sorted(scan(args.root, args.dirs), reverse=True)
    if not results:
        print("no functions found under", args.root, args.dirs)
        return 2
    if args.list:
        print(f"the {args.list} longest of {len(results)} functions:")
        for lines, path, first, name in results[:args.list]:
            print(f"  {lines:5d}  {path}:{first}  {name}")
    too_long = [r for r in results if r[0] > args.max_lines]
    failed = 0
    for lines, path, first, name in too_long:
        allowance = allowed.pop((path, name), None)
        if allowance is not None and lines <= allowance:
            print(f"{path}:{first}: {name} is {lines} lines (limit {args.max_lines}; allowed {allowance} until split)")
            continue
        failed += 1
        print(f"{path}:{first}: {name} is {lines} lines (limit {args.max_lines}"
              + (f"; grew beyond the {allowance} allowed until split)" if allowance else ")"))
    for (path, name), allowance in sorted(allowed.items()):
        failed += 1
        print(f"{path}: {name} is no longer over {args.max_lines} lines: take it out of {args.allow}")
    print(f"{len(results)} functions scanned, {len(too_long)} over {args.max_lines} lines, {failed} failing")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
