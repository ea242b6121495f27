#!/usr/bin/env python3
"""Every page and note under results/ shows no broken image and no broken link.

Reads each *.html (report pages: src= and href= attributes) and *.md (notes, tables, compare
reports: [text](target), ![alt](target), [ref]: target and <img src=...>, outside code fences and
code spans) under results/, and checks each relative target: it names a file or folder inside the
repository, and it is not a PNG under results/ (a sweep's full-size images are not committed,
results/.gitignore; link the WebP preview that scripts/previews.sh writes). Targets with a scheme
(https:, data:) and anchors within the page are not checked.

Usage: python3 tests/results_links_test.py [ROOT]   (ctest: Results.NoPageOrNoteLinksToAMissingFile)
ROOT is the repository (default: this file's); exit 0: every target resolves; 1: each broken one
named as FILE:LINE: TARGET and why.
"""
import os
import re
import sys
from urllib.parse import unquote

SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def markdown_targets(text):
    """(line, target) of each link and image of a Markdown text."""
    fence = False
    for number, line in enumerate(text.split("\n"), 1):
        if re.match(r"^\s*(```|~~~)", line):
            fence = not fence
            continue
        if fence:
            continue
        line = re.sub(r"`[^`]*`", "", line)
        m = re.match(r"^ {0,3}\[[^\]]+\]:\s+(\S+)", line)
        if m:
            yield number, m.group(1)
            continue
        for m in re.finditer(r"\]\(\s*<?([^)\s>]*)", line):
            yield number, m.group(1)
        for m in re.finditer(r"<img\b[^>]*\bsrc=\"([^\"]*)\"", line):
            yield number, m.group(1)


def html_targets(text):
    """(line, target) of each src= and href= attribute of an HTML page."""
    for number, line in enumerate(text.split("\n"), 1):
        for m in re.finditer(r"\b(?:src|href)=(?:\"([^\"]*)\"|'([^']*)')", line):
            yield number, m.group(1) if m.group(1) is not None else m.group(2)


def problem(root, page, target):
    """Why target, as written in page, is broken; None when it resolves."""
    path = target.split("#", 1)[0].split("?", 1)[0]
    if not path or SCHEME.match(path):
        return None
    path = unquote(path.replace("&amp;", "&"))
    resolved = os.path.realpath(os.path.join(root, path.lstrip("/")) if path.startswith("/") else
                                os.path.join(os.path.dirname(page), path))
    if resolved != root and not resolved.startswith(root + os.sep):
        return "leads out of the repository"
    results = os.path.join(root, "results") + os.sep
    if resolved.startswith(results) and resolved.endswith(".png"):
        return ("a full-size PNG, which is not committed (results/.gitignore); write its preview with "
                "bash scripts/previews.sh DIR and link NAME.webp (hybridbench report does where it is there)")
    if not os.path.exists(resolved):
        return "names no file; fix the path, or regenerate the page from its results"
    return None


def main():
    root = os.path.realpath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    results = os.path.join(root, "results")
    if not os.path.isdir(results):
        sys.exit(f"results_links_test.py: {results} is not a folder; pass the repository as ROOT")
    pages = checked = 0
    broken = []
    for dirpath, dirnames, filenames in os.walk(results):
        dirnames.sort()
        for name in sorted(filenames):
            if not name.endswith((".md", ".html")):
                continue
            page = os.path.join(dirpath, name)
            with open(page, encoding="utf-8") as f:
                text = f.read()
            pages += 1
            for line, target in (markdown_targets if name.endswith(".md") else html_targets)(text):
                checked += 1
                why = problem(root, page, target)
                if why:
                    broken.append(f"{os.path.relpath(page, root)}:{line}: {target}: {why}")
    for b in broken:
        print(b)
    if broken:
        print(f"results_links_test.py: {len(broken)} broken target(s) in {pages} page(s) under results/")
        sys.exit(1)
    print(f"results_links_test.py: {checked} target(s) in {pages} page(s) under results/ resolve")


if __name__ == "__main__":
    main()
