#!/usr/bin/env python3
"""Keeps results/ light: gzips every committed JSON file of 32 KiB or more, and points every
reference to it at the .gz.

Usage: python3 tools/compress_results.py [--check]

A results file of a sweep is mostly per-frame samples (300 frames x every pass and sub-pass); gzip
keeps all of it in a sixth of the bytes, and every reader takes the .gz as it is: hybridbench
(`tables`, `report`, `compare`, `merge` read gzip by its magic bytes), tools/results_index.py,
tools/same_outputs.py and scripts/ci-compare.sh. See docs/results-format.md "Committed results".

Each FILE.json of 32 KiB or more under results/ becomes FILE.json.gz (gzip -9, no name or time in
the header, so the same JSON gives the same bytes). Then, in the repository's text files (docs,
README.md, results/**/*.md|html|txt|sh, tests/, tools/, scripts/, .ci/), each path that names one
of those files gains ".gz": a path relative to the file that holds it, to the repository root, or
to results/ (the tests write kResults + "h200/...").

--check changes nothing: it exits 1 naming each JSON file of 32 KiB or more under results/ (one
that should be compressed), and each reference to a .json that is now only a .json.gz.
"""
import gzip
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIMIT = 32 * 1024
TEXT = (".md", ".html", ".txt", ".sh", ".cpp", ".h", ".py", ".mjs", ".cmake")
TOKEN = re.compile(r"[A-Za-z0-9_./+-]*\.json(?![A-Za-z0-9_.])")


def tracked():
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True).stdout
    return [p for p in out.decode().split("\0") if p]


def gzip_bytes(data):
    return gzip.compress(data, compresslevel=9, mtime=0)


def resolve(holder, token, compressed):
    """The compressed file's repository path that `token` in file `holder` names, or None."""
    if "://" in token:
        return None
    if token.startswith("/"):  # HYBRIDBENCH_SOURCE_DIR "/results/...": from the root only
        token = token.lstrip("/")
        return token if token in compressed else None
    candidates = [
        os.path.normpath(os.path.join(os.path.dirname(holder), token)),
        os.path.normpath(token),
        os.path.normpath(os.path.join("results", token)),
    ]
    for c in candidates:
        if c in compressed:
            return c
    return None


def rewrite(paths, compressed, write):
    """Appends .gz to each reference to a compressed file; returns [(file, count)]."""
    changed = []
    for p in paths:
        if not p.endswith(TEXT) or p.startswith("tools/node_modules/") or p == "tools/compress_results.py":
            continue
        full = os.path.join(ROOT, p)
        try:
            text = open(full, encoding="utf-8").read()
        except (OSError, UnicodeDecodeError):
            continue
        count = 0

        def sub(m):
            nonlocal count
            if resolve(p, m.group(0), compressed) is None:
                return m.group(0)
            count += 1
            return m.group(0) + ".gz"

        new = TOKEN.sub(sub, text)
        if count:
            changed.append((p, count))
            if write:
                with open(full, "w", encoding="utf-8") as f:
                    f.write(new)
    return changed


def main():
    check = sys.argv[1:] == ["--check"]
    if sys.argv[1:] not in ([], ["--check"]):
        sys.exit("usage: python3 tools/compress_results.py [--check]")
    paths = tracked()
    big = [p for p in paths if p.startswith("results/") and p.endswith(".json")
           and os.path.getsize(os.path.join(ROOT, p)) >= LIMIT]
    already = {p[:-3] for p in paths if p.startswith("results/") and p.endswith(".json.gz")}
    if check:
        stale = rewrite(paths, already, write=False)
        for p in big:
            print(f"{p}: {os.path.getsize(os.path.join(ROOT, p))} bytes; run python3 tools/compress_results.py")
        for p, n in stale:
            print(f"{p}: {n} reference(s) to a .json kept as .json.gz; run python3 tools/compress_results.py")
        sys.exit(1 if big or stale else 0)
    before = after = 0
    for p in big:
        full = os.path.join(ROOT, p)
        data = open(full, "rb").read()
        with open(full + ".gz", "wb") as f:
            f.write(gzip_bytes(data))
        subprocess.run(["git", "rm", "-q", "--cached", p], cwd=ROOT, check=True)
        os.remove(full)
        subprocess.run(["git", "add", p + ".gz"], cwd=ROOT, check=True)
        before += len(data)
        after += os.path.getsize(full + ".gz")
    changed = rewrite(paths, already | set(big), write=True)
    print(f"compressed {len(big)} file(s): {before / 1e6:.1f} -> {after / 1e6:.1f} MB; "
          f"{sum(n for _, n in changed)} reference(s) in {len(changed)} file(s) now name the .gz")
    for p, n in changed:
        print(f"  {p}: {n}")


if __name__ == "__main__":
    main()
