#!/usr/bin/env python3
"""Fails when a file of the repository cites a document that is not in the repository.

Checks every tracked text file for mentions of Markdown files: a citation of the developers'
private notes (kept outside the repository; PRIVATE below lists their names) is an error; a
Markdown file under docs/, or a bare Markdown name that is not another project's path, must
exist in docs/ (or at the root); an anchor after "#" must be a heading of that file (GitHub's
slug rule).
Usage: tests/check_citations.py [repository root]; exit 1 and one line per problem on failure.
"""
import os
import re
import subprocess
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
MENTION = re.compile(r"(?<![\w./-])((?:[\w.-]+/)*[\w.-]+\.md)(#[\w-]+)?", re.UNICODE)
PRIVATE = re.compile(r"(^|/)(reference|design)\.md$|(^|/)shared/|(^|/)seeds/")
# Paths inside other projects that the code cites as such (not documents of ours).
FOREIGN_PREFIXES = ("libraries/", "src/", "Documentation/")


def slug(heading):
    text = heading.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text, flags=re.UNICODE)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        with open(path, encoding="utf-8") as f:
            cache[path] = {slug(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", f.read(), re.M)}
    return cache[path]


def resolve(name, citing_file):
    if name.startswith("docs/") or "/" not in name:
        base = os.path.basename(name)
        for candidate in (os.path.join(ROOT, "docs", base), os.path.join(ROOT, base)):
            if os.path.exists(candidate):
                return candidate
        return None
    return os.path.join(ROOT, name) if os.path.exists(os.path.join(ROOT, name)) else None


def source_files():
    """The tracked files; in a copy without git's data (a container build), every file but the
    build folders, run outputs and npm packages (what .dockerignore leaves out)."""
    listing = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True)
    if listing.returncode == 0:
        return listing.stdout.split()
    files = []
    for folder, subfolders, names in os.walk(ROOT):
        rel = os.path.relpath(folder, ROOT)
        subfolders[:] = [d for d in subfolders if not (
            (rel == "." and (d.startswith("build") or d in ("runs", ".git"))) or d == "node_modules")]
        files += [os.path.normpath(os.path.join(rel, name)) for name in names]
    return files


def main():
    files = source_files()
    problems = []
    for rel in files:
        if rel == "tests/check_citations.py" or rel.endswith((".png", ".svg", ".csv", ".pcap")):
            continue
        path = os.path.join(ROOT, rel)
        try:
            with open(path, encoding="utf-8") as f:
                lines = f.read().split("\n")
        except (UnicodeDecodeError, IsADirectoryError, FileNotFoundError):
            continue
        for number, line in enumerate(lines, 1):
            for m in MENTION.finditer(line):
                name, anchor = m.group(1), m.group(2)
                where = f"{rel}:{number}"
                if PRIVATE.search(name):
                    problems.append(f"{where}: cites {name}, which is not in the repository")
                    continue
                if name.startswith(FOREIGN_PREFIXES) or name.lower() == "readme.md" and "/" in name:
                    continue
                if re.fullmatch(r"[A-Z_]+\.md", os.path.basename(name)) and name != "README.md":
                    continue  # an upper-case placeholder in usage text, not a document
                target = resolve(name, rel)
                if target is None:
                    if "/" in name and not name.startswith("docs/"):
                        continue  # another project's path, e.g. an upstream file
                    problems.append(f"{where}: cites {name}, which does not exist")
                elif anchor and anchor[1:] not in anchors(target):
                    problems.append(f"{where}: {name} has no heading for {anchor}")
    for problem in problems:
        print(problem)
    print(f"{len(files)} files checked, {len(problems)} citation problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
