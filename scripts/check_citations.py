#!/usr/bin/env python3
"""Every citation in the repository resolves inside it.

Checks code, tests, scripts and docs for: documents outside the repository
(the shared folder beside a developer's checkout, papers cited by file
number instead of by key); docs/NAME.md paths that do not exist; sections
of docs/design.md ("docs/design.md section N") and named sections
('docs/X.md, "Heading"') that the document does not have; paper keys
("[Mahajan07]") missing from docs/references.md. Prints each problem as
FILE:LINE and exits 1 if there is any.
"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), ".."))
SKIP_DIRS = {".git", "regressions", "images"}
EXTENSIONS = {".cpp", ".h", ".py", ".md", ".sh", ".txt", ".json"}

OUTSIDE = re.compile(r"\.\./shared|shared/(docs|papers)|[Pp]aper 00[0-9]")
DOC_PATH = re.compile(r"docs/([\w-]+\.md)")
DESIGN_SECTION = re.compile(r"docs/design\.md,? sections? (\d+)(?:-(\d+))?")
NAMED_SECTION = re.compile(r"docs/([\w-]+\.md),? \(?\"([^\"]+)\"")
KEY = re.compile(r"\[([A-Z][A-Za-z]+\d{2})\]")


def sources():
    for top, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not d.startswith("build")]
        for name in files:
            if os.path.splitext(name)[1] in EXTENSIONS or name == "run":
                yield os.path.join(top, name)


def headings(doc):
    path = os.path.join(ROOT, "docs", doc)
    with open(path, encoding="utf-8") as f:
        return [line.lstrip("#").strip() for line in f if line.startswith("#")]


def main():
    with open(os.path.join(ROOT, "docs", "references.md"), encoding="utf-8") as f:
        keys = set(re.findall(r"^\| \[([A-Za-z]+\d{2})\]", f.read(), re.M))
    design = headings("design.md")
    problems = []
    this = os.path.abspath(__file__)
    for path in sources():
        if os.path.abspath(path) == this:
            continue
        rel = os.path.relpath(path, ROOT)
        try:
            lines = open(path, encoding="utf-8").read().splitlines()
        except UnicodeDecodeError:
            continue
        for number, line in enumerate(lines, 1):
            where = f"{rel}:{number}"
            if OUTSIDE.search(line):
                problems.append(f"{where}: cites a document outside the repository: {line.strip()}")
            for doc in DOC_PATH.findall(line):
                if not os.path.exists(os.path.join(ROOT, "docs", doc)):
                    problems.append(f"{where}: docs/{doc} does not exist")
            for first, last in DESIGN_SECTION.findall(line):
                for n in range(int(first), int(last or first) + 1):
                    if not any(h.startswith(f"{n}.") for h in design):
                        problems.append(f"{where}: docs/design.md has no section {n}")
            for doc, heading in NAMED_SECTION.findall(line):
                if os.path.exists(os.path.join(ROOT, "docs", doc)) and not any(
                        heading.lower() in h.lower() for h in headings(doc)):
                    problems.append(f"{where}: docs/{doc} has no section \"{heading}\"")
            if rel != os.path.join("docs", "references.md"):
                for key in KEY.findall(line):
                    if key not in keys:
                        problems.append(f"{where}: [{key}] is not in docs/references.md")
    for p in problems:
        print(p)
    print(f"check_citations: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
