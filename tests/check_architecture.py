#!/usr/bin/env python3
"""Checks docs/architecture.md's module table against the build's link graph (issue 43, "the map").

Each row's "links" column must list exactly the sitlnet libraries its library links directly
(build/link_graph.txt, written by CMake with the libraries' LINK_LIBRARIES), and every sitlnet
library must have a row. Prints one line per difference; exits 1 if any.

Usage: tests/check_architecture.py DOCS/architecture.md BUILD/link_graph.txt
"""
import re
import sys


def documented_links(page):
    """{library: set of linked libraries} from the table under "## Modules"."""
    rows = {}
    in_modules = False
    for line in open(page, encoding="utf-8"):
        if line.startswith("## "):
            in_modules = line.strip() == "## Modules"
            continue
        if not in_modules or not line.startswith("| `"):
            continue
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        library = re.fullmatch(r"`(sitlnet_\w+)`", cells[1])
        if library is None:
            continue  # The CLI: an executable, not a library.
        links = {"sitlnet_" + name.strip() for name in cells[3].split(",") if name.strip()}
        rows[library.group(1)] = links
    return rows


def built_links(graph):
    """{library: set of sitlnet libraries it links} from link_graph.txt."""
    links = {}
    for line in open(graph, encoding="utf-8"):
        if ":" not in line:
            continue
        library, linked = line.split(":", 1)
        links[library.strip()] = {name for name in linked.split() if name.startswith("sitlnet_")}
    return links


def main():
    page, graph = sys.argv[1], sys.argv[2]
    documented, built = documented_links(page), built_links(graph)
    problems = []
    for library in sorted(built):
        if library not in documented:
            problems.append(f"{page}: no row for {library} (it links {sorted(built[library])})")
            continue
        extra = built[library] - documented[library]
        if extra:
            problems.append(f"{page}: {library} links {sorted(extra)}, which its row does not list")
        missing = documented[library] - built[library]
        if missing:
            problems.append(f"{page}: {library}'s row lists {sorted(missing)}, which it does not link")
    for library in sorted(set(documented) - set(built)):
        problems.append(f"{page}: a row for {library}, which the build does not have")
    for problem in problems:
        print(problem)
    if not problems:
        print(f"{page}: the module table matches the build's link graph ({len(built)} libraries)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
