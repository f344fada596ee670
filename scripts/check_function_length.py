#!/usr/bin/env python3
"""No function outside the tests is longer than a limit (120 lines).

A long function does several things; CONTRIBUTING asks for one thing per
function. This reads every .cpp and .h outside tests/, fuzz/ and build
folders, blanks out comments, string and character literals and preprocessor
lines, then walks the braces: at namespace or class scope a `{` that follows a
parameter list opens a function body (a constructor's initializer list with
braces is skipped), and the body's length is counted from the line of the
signature's first token to the line of its closing brace. Lambdas and local
classes count toward the function that holds them.

Usage: check_function_length.py [ROOT] [--limit N] [--list K]
Prints every function over the limit (file:line, name, lines) and exits 1 if
there is one; --list K also prints the K longest.
"""
import argparse
import os
import re
import sys

SKIP_DIRS = ("tests", "fuzz", "third_party")
SCOPE_WORDS = re.compile(r"\b(namespace|class|struct|union|enum|extern)\b")
CONTROL_WORDS = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try|return)\b")


def blank_non_code(text):
    """Replaces comments, literals and preprocessor lines by spaces, keeping newlines."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c == "/" and text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
            continue
        if c == "/" and text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        raw = re.match(r'R"([^(\s]*)\(', text[i:i + 20]) if c == "R" else None
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = text.find(")" + raw.group(1) + '"', i)
            j = n if end < 0 else end + len(raw.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():
                out.append(c)  # a digit separator, 1'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j + 1, n) - i))
            i = j + 1
            continue
        out.append(c)
        line_start = c == "\n" or (line_start and c in " \t")
        i += 1
    return "".join(out)


def matching_brace(code, open_at):
    depth = 0
    for k in range(open_at, len(code)):
        if code[k] == "{":
            depth += 1
        elif code[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    return len(code) - 1


def function_name(signature):
    head = signature.split("(")[0].split()
    return head[-1] if head else "?"


def is_function_signature(signature):
    s = re.sub(r"\boperator\s*[^\s(]+\s*\(", "operator(", signature)
    if "(" not in s or SCOPE_WORDS.search(s.split("(")[0]) or CONTROL_WORDS.match(s):
        return False
    return "=" not in s.split("(")[0]


def functions(code):
    """Yields (start offset, end offset, signature) of each function body."""
    pending_start = None
    i, n = 0, len(code)
    while i < n:
        c = code[i]
        if c in ";}":
            pending_start = None
            i += 1
            continue
        if c == "{":
            signature = code[pending_start:i] if pending_start is not None else ""
            flat = " ".join(signature.split())
            if is_function_signature(flat):
                # A constructor's initializer list may hold braces: `a_{x}`.
                init = re.search(r"\)\s*(noexcept\s*)?:[^:]", flat)
                if init and re.search(r"[\w>]\s*$", flat) and not re.search(
                        r"\)\s*(const|override|final|noexcept|mutable)?\s*$", flat):
                    i = matching_brace(code, i) + 1
                    continue
                end = matching_brace(code, i)
                yield pending_start, end, flat
                pending_start = None
                i = end + 1
                continue
            if SCOPE_WORDS.search(flat) or not flat:
                pending_start = None  # enter the namespace or class: keep scanning inside
                i += 1
                continue
            i = matching_brace(code, i) + 1  # an initializer or aggregate: skip it
            continue
        if pending_start is None and not c.isspace():
            pending_start = i
        i += 1


def line_of(code, offset):
    return code.count("\n", 0, offset) + 1


def source_files(root):
    for top, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs
                         if not d.startswith((".", "build")) and d not in SKIP_DIRS)
        for name in sorted(files):
            if name.endswith((".cpp", ".h")):
                yield os.path.join(top, name)


SELF_TEST = """
namespace acpca {
struct Widget {
  Widget(int a) : a_{a}, b_(a) {
    LINES(3)
  }
  int size() const { return a_; }
  int a_, b_;
};
const std::map<int, int> kTable = {{1, 2}, {3, 4}};
std::string quoted() {
  return "if (x) { not a brace } R";
}
int Widget::long_one(int x) {
  auto f = [](int y) { return y; };
  LINES(130)
  return f(x);
}
}  // namespace acpca
"""


def self_test():
    """The parser finds what a reader sees: fails the check if it does not."""
    text = SELF_TEST.replace("    LINES(3)\n", "    x;\n" * 3).replace(
        "  LINES(130)\n", "  y += 1;  // '{'\n" * 130)
    found = {function_name(sig): line_of(code, end) - line_of(code, start) + 1
             for code in [blank_non_code(text)] for start, end, sig in functions(code)}
    expected = {"Widget": 5, "size": 1, "quoted": 3, "Widget::long_one": 134}
    if found != expected:
        print(f"self-test failed: found {found}, expected {expected}", file=sys.stderr)
        return False
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(__file__), ".."))
    parser.add_argument("--limit", type=int, default=120)
    parser.add_argument("--list", type=int, default=0)
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    if not self_test():
        return 1
    found = []
    for path in source_files(root):
        code = blank_non_code(open(path, encoding="utf-8").read())
        for start, end, signature in functions(code):
            first, last = line_of(code, start), line_of(code, end)
            found.append((last - first + 1, os.path.relpath(path, root), first,
                          function_name(signature)))
    found.sort(reverse=True)
    for lines, path, line, name in found[:args.list]:
        print(f"{lines:5d}  {path}:{line}  {name}")
    over = [f for f in found if f[0] > args.limit]
    for lines, path, line, name in over:
        print(f"{path}:{line}: {name} is {lines} lines, over the limit of {args.limit}:"
              " split it by what it does")
    if not found:
        print("no functions found: is the root right?", file=sys.stderr)
        return 1
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
