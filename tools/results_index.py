#!/usr/bin/env python3
"""Writes results/README.md: the index of the committed studies.

A study is a folder results/<device>/<study>/ with a README.md, its notes: the first line is its
title ("# ..."), the one line the index shows. For each study the index gives the device and the
revisions its results files were measured at (their context: context.device.name, context.tool.git,
context.host.date; docs/results-format.md), and links to its notes, its page (report*.html) and its
tables (tables.md). Folders of a device without notes of their own are listed after its studies,
each with the study whose notes name it. A device folder's README.md (its title and a paragraph:
driver, backend, scene) heads its section.

Usage:
  python3 tools/results_index.py          # rewrites results/README.md
  python3 tools/results_index.py --check  # exit 1 when results/README.md is not what it would write
Needs python3 alone. Run from anywhere; ROOT (the repository) is found from this file.
"""
import collections
import gzip
import json
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "results")
INDEX = os.path.join(RESULTS, "README.md")
# Devices in the order the index shows them; a device folder not named here comes after, by name.
DEVICE_ORDER = ["h100", "h200", "lavapipe"]
MAX_REVISIONS = 3  # shown per study; the rest as a count

HEAD = """\
# Results

<!-- Written by tools/results_index.py from the study folders; edit a study's README.md, then run
     python3 tools/results_index.py (a test checks that this file is what it writes). -->

Results measured on real devices: one folder per device, one folder per study in it. A study's
`README.md` holds its notes (what was run, what it shows, its tables, each generated from the
committed files by the `hybridbench` command named above it); its folders hold what the runs wrote:
`results.json` ([the results format](../docs/results-format.md)), `results.csv`, `tables.md`,
`accuracy.md`, logs, the device record and, for sweeps from after the page existed, `report.html`
([`hybridbench report`](../docs/usage.md#report-resultsjson---out-reporthtml); for a folder from
before, `hybridbench report DIR/results.json --out DIR/report.html`). Images are small WebP
previews: a sweep writes full-size PNGs, which are not committed
([committing results](../docs/usage.md#committing-results)). How to read the tables:
[reading the results](reading.md).

Revision: the `git` revision of the tool that measured (`context.tool.git` of the study's results
files), oldest first.
"""


def rel(path):
    """path relative to results/, '/'-separated."""
    return os.path.relpath(path, RESULTS).replace(os.sep, "/")


def title_of(readme):
    with open(readme, encoding="utf-8") as f:
        first = f.readline().rstrip("\n")
    if not first.startswith("# "):
        sys.exit(f"results_index.py: {rel(readme)}: the first line must be its title, '# ...'; got {first!r}")
    return first[2:].strip()


def first_paragraph(readme):
    """The first paragraph after the title, joined into one line."""
    with open(readme, encoding="utf-8") as f:
        lines = f.read().split("\n")[1:]
    para = []
    for line in lines:
        if line.strip():
            para.append(line.strip())
        elif para:
            break
    return " ".join(para)


def sorted_files(folder, suffixes):
    """Paths under folder ending in one of suffixes, folders and names in sorted order."""
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames.sort()
        yield from (os.path.join(dirpath, n) for n in sorted(filenames) if n.endswith(suffixes))


def load_json(path):
    """A JSON file, gzipped (a committed results.json.gz) or not."""
    with open(path, "rb") as f:
        raw = f.read()
    return json.loads(gzip.decompress(raw) if raw[:2] == b"\x1f\x8b" else raw)


def results_files(folder):
    """(path, context) of every schema-1 results file under folder."""
    out = []
    for path in sorted_files(folder, (".json", ".json.gz")):
        try:
            data = load_json(path)
        except (OSError, ValueError) as e:
            sys.exit(f"results_index.py: {rel(path)}: not readable JSON ({e}); fix or remove it")
        if isinstance(data, dict) and data.get("schema_version") == 1 and "runs" in data:
            out.append((path, data.get("context", {})))
    return out


def files_named(folder, pattern):
    """Files under folder whose name matches pattern, shallowest first, then by path."""
    found = []
    for dirpath, _, filenames in os.walk(folder):
        for name in filenames:
            if re.fullmatch(pattern, name):
                path = os.path.join(dirpath, name)
                found.append((rel(path).count("/"), rel(path), path))
    return [p for _, _, p in sorted(found)]


def links(folder, pattern, label):
    found = files_named(folder, pattern)
    if not found:
        return ""
    text = f"[{label}]({rel(found[0])})"
    return text + (f" +{len(found) - 1}" if len(found) > 1 else "")


def revisions(contexts):
    """The tool revisions, oldest first (by the date each was first measured)."""
    first = {}
    for ctx in contexts:
        git = str(ctx.get("tool", {}).get("git", "")).strip()
        if not git:
            continue
        git = git[:7] + ("-dirty" if git.endswith("-dirty") else "")
        date = str(ctx.get("host", {}).get("date", ""))
        first[git] = min(first.get(git, date), date)
    ordered = sorted(first, key=lambda g: (first[g], g))
    shown = ", ".join(f"`{g}`" for g in ordered[:MAX_REVISIONS])
    more = len(ordered) - MAX_REVISIONS
    return shown + (f" +{more}" if more > 0 else "") if ordered else "—"


def dates(contexts):
    days = sorted({str(c.get("host", {}).get("date", ""))[:10] for c in contexts} - {""})
    if not days:
        return "—"
    return days[0] if len(days) == 1 else f"{days[0]} – {days[-1]}"


def rebase_links(text, folder):
    """Markdown links of text, written from results/<folder>/, as written from results/."""
    def fix(m):
        target = m.group(1)
        if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:|^#", target):
            return m.group(0)
        slash = "/" if target.endswith("/") else ""
        return "](" + os.path.normpath(os.path.join(folder, target)).replace(os.sep, "/") + slash + ")"
    return re.sub(r"\]\(([^)\s]+)\)", fix, text)


def names_folder(notes_folder, notes, folder):
    """Whether a study's notes (in results/<notes_folder>/) name results/<folder>/: as text
    ("h100/render-best") or by a link that leads into it."""
    if re.search(re.escape(folder) + r"(?![A-Za-z0-9_.-])", notes):
        return True
    for target in re.findall(r"\]\(([^)#\s]+)", notes):
        if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", target):
            continue
        resolved = os.path.normpath(os.path.join(notes_folder, target)).replace(os.sep, "/")
        if resolved == folder or resolved.startswith(folder + "/"):
            return True
    return False


def escape(text):
    return text.replace("|", "\\|")


def all_notes():
    """{'<device>/<study>': the text of its README.md} for every study, and {'<name>.md': its text}
    for the notes across devices in results/ itself."""
    notes = {}
    for f in loose_notes():
        with open(os.path.join(RESULTS, f), encoding="utf-8") as g:
            notes[f] = g.read()
    for device in sorted(os.listdir(RESULTS)):
        if not os.path.isdir(os.path.join(RESULTS, device)):
            continue
        for d in sorted(os.listdir(os.path.join(RESULTS, device))):
            readme = os.path.join(RESULTS, device, d, "README.md")
            if os.path.isfile(readme):
                with open(readme, encoding="utf-8") as f:
                    notes[f"{device}/{d}"] = f.read()
    return notes


def device_section(device, notes):
    folder = os.path.join(RESULTS, device)
    subfolders = sorted(d for d in os.listdir(folder) if os.path.isdir(os.path.join(folder, d)))
    studies = [d for d in subfolders if os.path.isfile(os.path.join(folder, d, "README.md"))]
    others = [d for d in subfolders if d not in studies]

    contexts = {d: [c for _, c in results_files(os.path.join(folder, d))] for d in subfolders}
    names = collections.Counter(
        c.get("device", {}).get("name") for d in subfolders for c in contexts[d] if c.get("device", {}).get("name"))
    device_readme = os.path.join(folder, "README.md")
    heading = names.most_common(1)[0][0] if names else device
    out = [f"## {heading} (`{device}/`)", ""]
    if os.path.isfile(device_readme):
        out += [rebase_links(first_paragraph(device_readme), device) + f" [More]({device}/README.md).", ""]

    out += ["| Study | Device | Revision | Measured | Page | Tables |", "| --- | --- | --- | --- | --- | --- |"]
    # The most recent study first.
    last = {d: max((str(c.get("host", {}).get("date", "")) for c in contexts[d]), default="") for d in studies}
    for d in sorted(studies, key=lambda d: (last[d], d), reverse=True):
        path = os.path.join(folder, d)
        readme = os.path.join(path, "README.md")
        ctx = contexts[d]
        devs = sorted({c.get("device", {}).get("name") for c in ctx} - {None})
        device_text = "; ".join(devs) if devs else "—"
        page = links(path, r"report.*\.html", "page") or "—"
        tables = links(path, r"tables\.md", "tables") or "—"
        out.append(f"| [{escape(title_of(readme))}]({device}/{d}/README.md) | {escape(device_text)} | "
                   f"{revisions(ctx)} | {dates(ctx)} | {page} | {tables} |")
    out.append("")
    if others:
        items = []
        for d in others:
            where = next((s for s in notes if names_folder(os.path.dirname(s) if s.endswith(".md") else s, notes[s],
                                                           f"{device}/{d}")), None)
            see = f" ([{where}]({where if where.endswith('.md') else where + '/README.md'}))" if where else ""
            items.append(f"[`{d}`]({device}/{d}/){see}")
        out += ["Folders without notes of their own, with the study that names them: " + ", ".join(items) + ".", ""]
    return out


def loose_notes():
    """The notes in results/ itself (across devices), by file name."""
    return sorted(f for f in os.listdir(RESULTS) if os.path.isfile(os.path.join(RESULTS, f)) and f.endswith(".md") and
                  f not in ("README.md", "reading.md"))


def index():
    devices = sorted((d for d in os.listdir(RESULTS) if os.path.isdir(os.path.join(RESULTS, d))),
                     key=lambda d: (DEVICE_ORDER.index(d) if d in DEVICE_ORDER else len(DEVICE_ORDER), d))
    out = [HEAD]
    notes = all_notes()
    for device in devices:
        out += device_section(device, notes)
    loose = loose_notes()
    if loose:
        out += ["## Across devices", ""]
        for f in loose:
            with open(os.path.join(RESULTS, f), encoding="utf-8") as g:
                first = g.readline().strip()
            out.append(f"- [{first[2:] if first.startswith('# ') else f}]({f})")
        out.append("")
    return "\n".join(out).rstrip("\n") + "\n"


def main():
    check = sys.argv[1:] == ["--check"]
    if sys.argv[1:] not in ([], ["--check"]):
        sys.exit("results_index.py: expected no argument or --check (usage: python3 tools/results_index.py [--check])")
    text = index()
    if check:
        try:
            with open(INDEX, encoding="utf-8") as f:
                current = f.read()
        except OSError:
            current = ""
        if current != text:
            print("results/README.md is not what tools/results_index.py writes from the study folders; "
                  "rewrite it with: python3 tools/results_index.py")
            sys.exit(1)
        print("results/README.md is what tools/results_index.py writes")
        return
    with open(INDEX, "w", encoding="utf-8") as f:
        f.write(text)
    print(f"results_index.py: wrote results/README.md ({text.count(chr(10))} lines)")


if __name__ == "__main__":
    main()
