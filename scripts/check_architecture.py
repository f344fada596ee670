#!/usr/bin/env python3
"""docs/architecture.md draws the libraries' links as CMake declares them.

Reads every CMakeLists.txt for the project's targets (acpca_NAME libraries,
the adaptive-cpca executable, the adaptive_cpca Python module) and the
acpca:: targets each links (PUBLIC or PRIVATE), and compares them with the
"links" block of docs/architecture.md: one line per target, `NAME ──▶ A, B`.
Also holds the libraries that only show or judge pictures off the batch
relighter: pictures, viewer and eval reach no `dataset`, directly or through
another library, so writing a PNG does not pull in batches. And every file
the recipes of "Where new things go" name (a path in backticks) exists, so
that the recipes cannot outlive a move. Prints each difference and exits 1 if
there is any.
"""
import glob
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), ".."))
TARGET = re.compile(r"(?:add_library|add_executable|pybind11_add_module)\((acpca_\w+|adaptive-cpca|adaptive_cpca)\b")
LINKS = re.compile(r"target_link_libraries\(\s*(acpca_\w+|adaptive-cpca|adaptive_cpca)\b([^)]*)\)", re.S)


def short(name):
    return name[len("acpca_"):] if name.startswith("acpca_") else name


def declared():
    graph = {}
    for top, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if not d.startswith((".", "build")) and d not in ("tests", "fuzz")]
        if "CMakeLists.txt" not in files:
            continue
        text = open(os.path.join(top, "CMakeLists.txt"), encoding="utf-8").read()
        for name in TARGET.findall(text):
            if name != "acpca_options":
                graph.setdefault(short(name), set())
        for name, body in LINKS.findall(text):
            graph.setdefault(short(name), set()).update(re.findall(r"acpca::(\w+)", body))
    return graph


def drawn():
    text = open(os.path.join(ROOT, "docs", "architecture.md"), encoding="utf-8").read()
    block = re.search(r"<!-- links -->\n(.*?)<!-- /links -->", text, re.S)
    if not block:
        return None
    graph = {}
    for line in block.group(1).splitlines():
        m = re.match(r"\s*([\w-]+)\s+──▶\s+(.*?)\s*(?:\(.*\))?$", line)
        if m:
            graph[m.group(1)] = {n.strip() for n in m.group(2).split(",") if n.strip()}
        elif re.match(r"\s*([\w-]+)\s*(?:\(.*\))?$", line) and line.strip() and not line.strip().startswith("```"):
            graph[line.split()[0]] = set()
    return graph


# Libraries and what they must not reach, directly or through another library.
UNREACHABLE = {"pictures": "dataset", "viewer": "dataset", "eval": "dataset"}


def reaches(graph, start, goal):
    seen, todo = set(), [start]
    while todo:
        name = todo.pop()
        for n in graph.get(name, ()):
            if n == goal:
                return True
            if n not in seen:
                seen.add(n)
                todo.append(n)
    return False


def recipe_paths_missing():
    """Paths named in backticks under "Where new things go" that do not exist."""
    text = open(os.path.join(ROOT, "docs", "architecture.md"), encoding="utf-8").read()
    section = re.search(r"## Where new things go\n(.*?)\n## ", text, re.S)
    if not section:
        return ["docs/architecture.md has no \"Where new things go\" section"]
    missing = []
    for path in re.findall(r"`([^`\s]+/[^`\s]*)`", section.group(1)):
        if "<" in path or "NAME" in path or path.startswith("--"):
            continue  # a placeholder, not a path
        if not glob.glob(os.path.join(ROOT, path)):
            missing.append(f"docs/architecture.md, \"Where new things go\": {path} does not exist")
    return missing


def main():
    cmake, doc = declared(), drawn()
    if doc is None:
        print("check_architecture: docs/architecture.md has no <!-- links --> block")
        return 1
    problems = []
    for name in sorted(set(cmake) | set(doc)):
        if name not in doc:
            problems.append(f"{name}: a CMake target docs/architecture.md does not draw")
        elif name not in cmake:
            problems.append(f"{name}: drawn in docs/architecture.md, not a CMake target")
        elif cmake[name] != doc[name]:
            problems.append(f"{name}: CMake links {sorted(cmake[name])}, the doc draws {sorted(doc[name])}")
    problems += recipe_paths_missing()
    for name, goal in sorted(UNREACHABLE.items()):
        if reaches(cmake, name, goal):
            problems.append(f"{name}: reaches {goal} through CMake's links; it must not")
    for p in problems:
        print(p)
    print(f"check_architecture: {len(cmake)} targets, {len(problems)} difference(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
